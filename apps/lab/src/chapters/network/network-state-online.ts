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
import { toggle } from '../../ui/controls.js';
import { setAttr } from '../../ui/dom.js';
import * as fmt from '../../ui/format.js';
import { gameDef, keyMap } from '../../games-view/games.js';
import { drawGame, drawMessage } from '../../games-view/render.js';
import { BOT_EVERY, CHECKPOINT_TICKS } from './network-model.js';
import { SnapshotDisplay, arenaRender } from './network-state.js';
import { OnlineRoomPanel, ROOM_NAME, serverSocketUrl } from './network-online-room.js';

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

export class StateOnlinePanel extends OnlineRoomPanel<StateSyncSession<ButtonInput, Game>> {
  readonly el: HTMLElement;
  private readonly def = gameDef('ctf');
  private readonly display = new SnapshotDisplay(this.def);
  private readonly at: number;
  private hashAt: string | undefined;
  private keyboard = false;
  private keys = 0;
  private readonly onKey: (e: KeyboardEvent) => void;

  constructor() {
    const opts = stateOnlineOptions(location.hash);
    super({
      kind: 'state-',
      room: opts.room ?? `state-${Math.floor(Math.random() * 1e6).toString(36)}`,
      canvasLabel: 'Your machine in the state-sync room',
      waiting: ['Waiting for the server’s world…'],
      idle: [
        'Not in a room.',
        'Press “Join room”: the server starts the game at once;',
        'open the room in a second tab to play against it.',
      ],
    });
    this.at = opts.at;
    const keys = toggle('Play with the keyboard', 'control-state-keyboard', false, (on) => {
      this.keyboard = on;
      this.keys = 0;
    });
    keys.title = 'WASD or arrows to move, Space to shoot; off: a bot plays your side';
    this.updateLink();
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
    this.el = this.section({
      id: 'net-state-online',
      title: 'Play online: state sync, two tabs, one server',
      intro:
        'The server runs capture the flag in this room; each tab sends only its buttons and draws the world the server sends back. Join a room here, then open it in another tab or on another computer. Your player answers at once; the other one is drawn a little in the past, between two of the server’s snapshots.',
      controlsLabel: 'State-sync room',
      controls: [this.roomGroup(keys, this.tabLink)],
      body: [
        this.machine(
          [],
          [
            this.row('Connection', 'state'),
            this.row('Player', 'slot'),
            this.row('Round trip', 'rtt'),
            this.row('Predicted tick', 'tick'),
            this.row('Server snapshot tick', 'snapshot'),
            this.row('Render delay', 'render-delay'),
            this.row('Received', 'down'),
            this.row('Corrections', 'corrections'),
            this.row(`Server world at tick ${this.at}`, 'hash-at', true),
          ],
        ),
      ],
    });
    this.render();
    if (opts.room !== undefined) this.join();
  }

  protected link(room: string): string {
    return stateRoomLink(room, this.at);
  }

  protected open(room: string): Promise<StateSyncSession<ButtonInput, Game>> {
    const def = this.def;
    return connectWebSocket(serverSocketUrl(location, `/state/${room}`)).then((transport) => {
      let held = 0;
      let prev = 0;
      const session: StateSyncSession<ButtonInput, Game> = new StateSyncSession<ButtonInput, Game>({
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
          this.noteEvent(e);
        },
      });
      return session;
    });
  }

  protected frame(session: StateSyncSession<ButtonInput, Game>): void {
    session.frame();
    session.render();
  }

  protected override left(): void {
    this.hashAt = undefined;
  }

  protected render(): void {
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

  override destroy(): void {
    window.removeEventListener('keydown', this.onKey);
    window.removeEventListener('keyup', this.onKey);
    super.destroy();
  }
}
