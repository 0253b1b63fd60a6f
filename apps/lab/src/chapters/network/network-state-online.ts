/**
 * Chapter 6, "Play online — state sync": a state-sync session over a real WebSocket to the rooms
 * of `fixedstep serve` (`/state/<room>`), where the server runs capture the flag. Open the same
 * room in two tabs (`#/network?state=<room>` joins it); each tab predicts its own player and draws
 * the other between the server's snapshots. Play with the keyboard, or let a bot play.
 */
import {
  StateSyncSession,
  connectWebSocket,
  fnv1a64,
  hex64,
  performanceClock,
  type ButtonInput,
} from 'fixedstep';
import type { Game } from '@fixedstep/games';
import { SceneCanvas } from '../../ui/canvas.js';
import { button, toggle } from '../../ui/controls.js';
import { h, setAttr, setText } from '../../ui/dom.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import { gameDef, keyMap } from '../../games-view/games.js';
import { ASPECT, drawGame, drawMessage } from '../../games-view/render.js';
import { BOT_EVERY, CHECKPOINT_TICKS } from './network-model.js';
import { SnapshotDisplay, arenaRender } from './network-state.js';

/** A room name the server accepts. */
const ROOM_NAME = /^[A-Za-z0-9_.-]{1,32}$/;
/** The tick whose server world both tabs report by default (10 s at 60 Hz). */
const DEFAULT_AT = 600;

/** The state-sync room to join at once, and the tick to report the hash of, from the address. */
export function stateOnlineOptions(hash: string): { room: string | undefined; at: number } {
  const q = hash.includes('?') ? new URLSearchParams(hash.slice(hash.indexOf('?') + 1)) : undefined;
  const room = q?.get('state') ?? undefined;
  const at = Number(q?.get('at') ?? '');
  return {
    room: room !== undefined && ROOM_NAME.test(room) ? room : undefined,
    at:
      Number.isInteger(at) && at >= CHECKPOINT_TICKS && at % CHECKPOINT_TICKS === 0
        ? at
        : DEFAULT_AT,
  };
}

/** The address that opens state-sync room `room` in another tab and joins it there. */
export function stateRoomLink(room: string, at: number): string {
  const q = new URLSearchParams({ state: room });
  if (at !== DEFAULT_AT) q.set('at', String(at));
  return `#/network?${q.toString()}`;
}

export class StateOnlinePanel {
  readonly el: HTMLElement;
  private readonly roomInput: HTMLInputElement;
  private readonly joinBtn: HTMLButtonElement;
  private readonly tabLink: HTMLAnchorElement;
  private readonly canvas: SceneCanvas;
  private readonly out: Record<string, Readout> = {};
  private readonly def = gameDef('ctf');
  private readonly display = new SnapshotDisplay(this.def);
  private session: StateSyncSession<ButtonInput, Game> | undefined;
  private raf = 0;
  private state = 'offline';
  private readonly at: number;
  private hashAt: string | undefined;
  private keyboard = false;
  private keys = 0;
  private readonly onKey: (e: KeyboardEvent) => void;

  constructor() {
    const opts = stateOnlineOptions(location.hash);
    this.at = opts.at;
    this.roomInput = h('input', {
      type: 'text',
      id: 'net-state-room',
      'data-testid': 'control-state-room',
      value: opts.room ?? `state-${Math.floor(Math.random() * 1e6).toString(36)}`,
      maxlength: 32,
      pattern: '[A-Za-z0-9_.\\-]{1,32}',
      spellcheck: 'false',
    });
    this.joinBtn = button('Join room', 'control-state-join', () => {
      if (this.session) this.leave();
      else this.join();
    });
    const keys = toggle('Play with the keyboard', 'control-state-keyboard', false, (on) => {
      this.keyboard = on;
      this.keys = 0;
    });
    keys.title = 'WASD or arrows to move, Space to shoot; off: a bot plays your side';
    this.tabLink = h(
      'a',
      {
        class: 'net-tab-link',
        target: '_blank',
        rel: 'noopener',
        'data-testid': 'link-state-room-tab',
        title: 'The second player: this page in a new tab, joining the same room',
      },
      'Open this room in a new tab ↗',
    );
    this.roomInput.addEventListener('input', () => {
      this.updateLink();
    });
    this.updateLink();
    this.canvas = new SceneCanvas({
      class: 'scene net-online-scene',
      label: 'Your machine in the state-sync room',
      testId: 'canvas-state-online',
      onResize: () => {
        if (!this.session) this.render();
      },
    });
    this.canvas.canvas.style.setProperty('--aspect', String(ASPECT.ctf ?? 1.5));
    const row = (label: string, id: string, hash = false) => {
      const r = new Readout('dd', `state-online-${id}`, { hash });
      this.out[id] = r;
      return [h('dt', {}, label), r.el];
    };
    const map = keyMap(this.def.info);
    this.onKey = (e: KeyboardEvent) => {
      if (!this.keyboard || !this.session) return;
      const target = e.target as HTMLElement | null;
      if (target && /^(INPUT|TEXTAREA|SELECT)$/.test(target.tagName)) return;
      const b = map[e.code];
      if (b === undefined) return;
      e.preventDefault();
      this.keys = e.type === 'keydown' ? this.keys | (1 << b) : this.keys & ~(1 << b);
    };
    window.addEventListener('keydown', this.onKey);
    window.addEventListener('keyup', this.onKey);
    this.el = h(
      'section',
      { class: 'bench net-online', 'aria-labelledby': 'net-state-online-title' },
      h('h2', { id: 'net-state-online-title' }, 'Play online: state sync, two tabs, one server'),
      h(
        'p',
        { class: 'section-intro' },
        'The server runs capture the flag in this room; each tab sends only its buttons and draws the world the server sends back. Join a room here, then open it in another tab or on another computer. Your player answers at once; the other one is drawn a little in the past, between two of the server’s snapshots.',
      ),
      h(
        'div',
        { class: 'controls', role: 'group', 'aria-label': 'State-sync room' },
        h(
          'div',
          { class: 'control-group' },
          h('label', { class: 'control-label', for: 'net-state-room' }, 'Room'),
          this.roomInput,
          this.joinBtn,
          keys,
          this.tabLink,
        ),
      ),
      h(
        'div',
        { class: 'net-online-body' },
        h('figure', { class: 'net-machine' }, this.canvas.canvas),
        h(
          'dl',
          { class: 'readouts' },
          ...row('Connection', 'state'),
          ...row('Player', 'slot'),
          ...row('Round trip', 'rtt'),
          ...row('Predicted tick', 'tick'),
          ...row('Server snapshot tick', 'snapshot'),
          ...row('Render delay', 'render-delay'),
          ...row('Received', 'down'),
          ...row('Corrections', 'corrections'),
          ...row(`Server world at tick ${this.at}`, 'hash-at', true),
        ),
      ),
    );
    this.render();
    if (opts.room !== undefined) this.join();
  }

  private updateLink(): void {
    const room = this.roomInput.value.trim();
    const ok = ROOM_NAME.test(room);
    this.tabLink.hidden = !ok;
    if (ok) this.tabLink.href = stateRoomLink(room, this.at);
  }

  private join(): void {
    const room = this.roomInput.value.trim();
    if (!ROOM_NAME.test(room)) {
      this.state = 'bad room name';
      this.render();
      return;
    }
    const def = this.def;
    const url = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/state/${room}`;
    this.state = 'connecting';
    setText(this.joinBtn, 'Leave');
    this.roomInput.disabled = true;
    this.render();
    connectWebSocket(url)
      .then((transport) => {
        let held = 0;
        let prev = 0;
        const session: StateSyncSession<ButtonInput, Game> = new StateSyncSession<
          ButtonInput,
          Game
        >({
          transport,
          clock: performanceClock(),
          room,
          game: def,
          players: 2,
          render: arenaRender(def),
          localInput: (tick, sim) => {
            if (this.keyboard) {
              const down = this.keys;
              const input = (down | ((down & ~prev) << 16)) >>> 0;
              prev = down;
              return input;
            }
            if (tick % BOT_EVERY === 0) held = def.bot(sim, session.welcome?.slot ?? 0);
            return held;
          },
          onEvent: (e) => {
            // A fatal error (a refusal, a welcome it cannot build, the connection lost: what
            // `finished` rejects with) says more than the close that follows it.
            if (e.type === 'error') this.state = `error: ${e.error.message}`;
            if (e.type === 'closed' && this.session?.failure === undefined) {
              this.state = `closed (${e.reason})`;
            }
          },
        });
        this.session = session;
        const frame = () => {
          this.raf = requestAnimationFrame(frame);
          session.frame();
          session.render();
          this.render();
        };
        this.raf = requestAnimationFrame(frame);
      })
      .catch((e: unknown) => {
        this.state = `could not connect (${e instanceof Error ? e.message : String(e)})`;
        setText(this.joinBtn, 'Join room');
        this.roomInput.disabled = false;
        this.render();
      });
  }

  private leave(): void {
    cancelAnimationFrame(this.raf);
    this.session?.leave();
    this.session = undefined;
    this.hashAt = undefined;
    this.state = 'offline';
    setText(this.joinBtn, 'Join room');
    this.roomInput.disabled = false;
    this.render();
  }

  private render(): void {
    const s = this.session;
    const o = this.out;
    const state = s ? (s.phase === 'closed' ? this.state : s.phase) : this.state;
    o.state?.set(state, state);
    const slot = s?.welcome?.slot;
    o.slot?.set(slot === undefined ? '—' : String(slot + 1), slot === undefined ? '' : slot + 1);
    o.rtt?.set(s ? fmt.millis(s.stats.rtt) : '—', s?.stats.rtt ?? '');
    o.tick?.set(s ? fmt.count(s.tick) : '—', s?.tick ?? '');
    const snap = s?.snapshotTick ?? -1;
    o.snapshot?.set(snap < 0 ? '—' : fmt.count(snap), snap < 0 ? '' : snap);
    o['render-delay']?.set(s ? fmt.millis(s.renderDelayMs) : '—', s?.renderDelayMs ?? '');
    const bytes = s?.stats.bytesReceived ?? 0;
    o.down?.set(s ? `${fmt.count(bytes)} B` : '—', s ? bytes : '');
    o.corrections?.set(s ? fmt.count(s.stats.corrections) : '—', s?.stats.corrections ?? '');
    if (s && this.hashAt === undefined) {
      const b = s.snapshotAt(this.at);
      if (b) this.hashAt = hex64(fnv1a64(b));
    }
    o['hash-at']?.set(this.hashAt ?? '—', this.hashAt ?? '');
    setAttr(this.el, 'data-state', s?.phase ?? 'offline');
    if (this.canvas.fit()) {
      const v = s ? this.display.view(s) : undefined;
      if (v) {
        drawGame(this.canvas, v.game, {
          alpha: v.alpha,
          nowMs: performance.now(),
          badge: { text: `tick ${v.tick}`, tone: 'info' },
        });
      } else {
        drawMessage(this.canvas, this.message());
      }
    }
  }

  private message(): string[] {
    const s = this.session;
    if (s?.phase === 'closed') return ['The connection closed.', 'Join the room again to play.'];
    if (s) return ['Waiting for the server’s world…'];
    if (this.state === 'connecting') return ['Connecting to the server…'];
    if (this.state !== 'offline') {
      return [`Could not join: ${this.state}.`, 'Check the room name and the server.'];
    }
    return [
      'Not in a room.',
      'Press “Join room”: the server starts the game at once;',
      'open the room in a second tab to play against it.',
    ];
  }

  destroy(): void {
    window.removeEventListener('keydown', this.onKey);
    window.removeEventListener('keyup', this.onKey);
    this.leave();
    this.canvas.destroy();
  }
}
