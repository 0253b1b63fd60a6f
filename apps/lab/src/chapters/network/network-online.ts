/**
 * Chapter 6, "Play online": a lockstep session over a real WebSocket to the relay of
 * `fixedstep serve` (`/ws`). Open the same room in two tabs (the room name is in the address:
 * `#/network?room=…`); a bot plays each side. Shows the connection, the round trip, the tick and
 * the hash of the state at the last checkpoint, and whether the relay saw a desync.
 */
import {
  LockstepSession,
  connectWebSocket,
  hex64,
  performanceClock,
  type NetSession,
  type Simulation,
} from 'fixedstep';
import type { Game } from '@fixedstep/games';
import { SceneCanvas } from '../../ui/canvas.js';
import { button } from '../../ui/controls.js';
import { h, setAttr, setText } from '../../ui/dom.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import { gameDef } from '../../games-view/games.js';
import { ASPECT, drawGame, drawMessage } from '../../games-view/render.js';
import { BOT_EVERY, CHECKPOINT_TICKS } from './network-lab.js';
import { QuickMatchControl } from './network-quick-match.js';

/** A room name the relay accepts. */
const ROOM_NAME = /^[A-Za-z0-9_.-]{1,32}$/;
const DEFAULT_TICKS = 3600;

/**
 * Room, match length and whether to join at once, from the address:
 * `#/network?room=abc&ticks=600&join=1`.
 */
export function onlineOptions(hash: string): {
  room: string | undefined;
  ticks: number;
  join: boolean;
} {
  const q = hash.includes('?') ? new URLSearchParams(hash.slice(hash.indexOf('?') + 1)) : undefined;
  const room = q?.get('room') ?? undefined;
  const ticks = Number(q?.get('ticks') ?? '');
  const valid = room !== undefined && ROOM_NAME.test(room);
  return {
    room: valid ? room : undefined,
    ticks: Number.isInteger(ticks) && ticks >= CHECKPOINT_TICKS ? ticks : DEFAULT_TICKS,
    join: valid && q?.get('join') === '1',
  };
}

/** The address that opens `room` in another tab and joins it there. */
export function roomLink(room: string, ticks: number): string {
  const q = new URLSearchParams({ room });
  if (ticks !== DEFAULT_TICKS) q.set('ticks', String(ticks));
  q.set('join', '1');
  return `#/network?${q.toString()}`;
}

export class OnlinePanel {
  readonly el: HTMLElement;
  private readonly roomInput: HTMLInputElement;
  private readonly joinBtn: HTMLButtonElement;
  private readonly tabLink: HTMLAnchorElement;
  private readonly canvas: SceneCanvas;
  private readonly out: Record<string, Readout> = {};
  private session: NetSession | undefined;
  private raf = 0;
  private state = 'offline';
  private stopAt: number;
  // Quick match: the server names a fresh room for two waiting tabs; join it as if typed.
  private readonly quick = new QuickMatchControl((match) => {
    if (this.session) this.leave();
    this.roomInput.value = match.room;
    this.updateLink();
    this.join();
  });

  constructor() {
    const opts = onlineOptions(location.hash);
    this.stopAt = opts.ticks;
    this.roomInput = h('input', {
      type: 'text',
      id: 'net-room',
      'data-testid': 'control-room',
      value: opts.room ?? `room-${Math.floor(Math.random() * 1e6).toString(36)}`,
      maxlength: 32,
      pattern: '[A-Za-z0-9_.\\-]{1,32}',
      spellcheck: 'false',
    });
    this.joinBtn = button('Join room', 'control-join', () => {
      if (this.session) this.leave();
      else this.join();
    });
    this.tabLink = h(
      'a',
      {
        class: 'net-tab-link',
        target: '_blank',
        rel: 'noopener',
        'data-testid': 'link-room-tab',
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
      label: 'Your machine in the online room',
      testId: 'canvas-online',
      // Joined, the panel draws on every animation frame; before that, when it changes or resizes.
      onResize: () => {
        if (!this.session) this.render();
      },
    });
    this.canvas.canvas.style.setProperty('--aspect', String(ASPECT.ctf ?? 1.5));
    const row = (label: string, id: string, hash = false) => {
      const r = new Readout('dd', `online-${id}`, { hash });
      this.out[id] = r;
      return [h('dt', {}, label), r.el];
    };
    this.el = h(
      'section',
      { class: 'bench net-online', 'aria-labelledby': 'net-online-title' },
      h('h2', { id: 'net-online-title' }, 'Play online: two tabs, one server'),
      h(
        'p',
        { class: 'section-intro' },
        'The same lockstep session over a real WebSocket to this server’s relay. Join a room here, then open this page with the same room in another tab or on another computer: the match starts when both players are in. A bot plays each side; the hashes at each checkpoint must be the same in both tabs.',
      ),
      h(
        'div',
        { class: 'controls', role: 'group', 'aria-label': 'Online room' },
        h(
          'div',
          { class: 'control-group' },
          h('label', { class: 'control-label', for: 'net-room' }, 'Room'),
          this.roomInput,
          this.joinBtn,
          this.tabLink,
          this.quick.el,
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
          ...row('Tick', 'tick'),
          ...row('Checkpoint tick', 'checkpoint'),
          ...row('Hash there', 'hash', true),
          ...row(`Hash at tick ${this.stopAt} (end)`, 'final-hash', true),
          ...row('Desyncs reported', 'desyncs'),
        ),
      ),
    );
    this.render();
    if (opts.join) this.join();
  }

  private updateLink(): void {
    const room = this.roomInput.value.trim();
    const ok = ROOM_NAME.test(room);
    this.tabLink.hidden = !ok;
    if (ok) this.tabLink.href = roomLink(room, this.stopAt);
  }

  private join(): void {
    const room = this.roomInput.value.trim();
    if (!ROOM_NAME.test(room)) {
      this.state = 'bad room name';
      this.render();
      return;
    }
    const def = gameDef('ctf');
    const url = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`;
    this.state = 'connecting';
    setText(this.joinBtn, 'Leave');
    this.roomInput.disabled = true;
    this.render();
    connectWebSocket(url)
      .then((transport) => {
        let held = 0;
        const session: NetSession = new LockstepSession({
          transport,
          clock: performanceClock(),
          room,
          game: def.info.id,
          gameVersion: def.info.version,
          input: def.input,
          players: 2,
          stopAt: this.stopAt,
          createSimulation: (w) => def.create(def.decodeConfig(w.config)),
          localInput: (tick: number, sim: Simulation) => {
            if (tick % BOT_EVERY === 0) held = def.bot(sim as Game, session.welcome?.slot ?? 0);
            return held;
          },
          onEvent: (e) => {
            if (e.type === 'closed') this.state = `closed (${e.reason})`;
            if (e.type === 'error') this.state = `error: ${e.error.message}`;
          },
        });
        this.session = session;
        const frame = () => {
          this.raf = requestAnimationFrame(frame);
          session.frame();
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
    this.state = 'offline';
    setText(this.joinBtn, 'Join room');
    this.roomInput.disabled = false;
    this.render();
  }

  /** Show the connection's numbers and draw the machine (or what it is waiting for). */
  private render(): void {
    const s = this.session;
    const o = this.out;
    const state = s
      ? s.phase === 'closed'
        ? this.state
        : s.finished
          ? 'finished'
          : s.phase === 'waiting'
            ? 'waiting for the other player'
            : s.phase
      : this.state;
    o.state?.set(state, state);
    const slot = s?.welcome?.slot;
    o.slot?.set(slot === undefined ? '—' : String(slot + 1), slot === undefined ? '' : slot + 1);
    o.rtt?.set(s ? fmt.millis(s.stats.rtt) : '—', s?.stats.rtt ?? '');
    o.tick?.set(s ? fmt.count(s.tick) : '—', s?.tick ?? '');
    const confirmed = s ? s.confirmedStateTick() : -1;
    const checkpoint =
      confirmed >= CHECKPOINT_TICKS
        ? Math.floor(confirmed / CHECKPOINT_TICKS) * CHECKPOINT_TICKS
        : -1;
    o.checkpoint?.set(checkpoint < 0 ? '—' : fmt.count(checkpoint), checkpoint);
    const hash = s && checkpoint >= 0 ? s.hashAt(checkpoint) : undefined;
    o.hash?.set(hash === undefined ? '—' : hex64(hash), hash === undefined ? '' : hex64(hash));
    const fin = s?.finished ? s.hashAt(this.stopAt) : undefined;
    o['final-hash']?.set(fin === undefined ? '—' : hex64(fin), fin === undefined ? '' : hex64(fin));
    const desyncs = s?.desyncs.length ?? 0;
    o.desyncs?.set(fmt.count(desyncs), desyncs);
    o.desyncs?.warn(desyncs > 0);
    setAttr(this.el, 'data-state', s?.phase ?? 'offline');
    if (this.canvas.fit()) {
      const g = s?.simulation as Game | undefined;
      if (g && s) {
        drawGame(this.canvas, g, {
          alpha: s.alpha,
          nowMs: performance.now(),
          badge: { text: `tick ${s.tick}`, tone: 'info' },
        });
      } else {
        drawMessage(this.canvas, this.message());
      }
    }
  }

  /** What the canvas says while there is no game to draw. */
  private message(): string[] {
    const s = this.session;
    if (s?.phase === 'closed') return ['The connection closed.', 'Join the room again to play.'];
    if (s) return ['Waiting for the other player…', 'Open this room in a second tab to start.'];
    if (this.state === 'connecting') return ['Connecting to the server…'];
    if (this.state !== 'offline') {
      return [`Could not join: ${this.state}.`, 'Check the room name and the server.'];
    }
    return [
      'Not in a room.',
      'Press “Join room”, then open the room in a second tab:',
      'the match starts when both players are in.',
    ];
  }

  destroy(): void {
    this.quick.cancel();
    this.leave();
    this.canvas.destroy();
  }
}
