/**
 * Chapter 6, "Play online": a lockstep session over a real WebSocket to the relay of
 * `fixedstep serve` (`/ws`). Open the same room in two tabs (the room name is in the address:
 * `#/network?room=…`); a person plays each side — by keyboard, or by the on-screen controls on a
 * touch screen, both through one `InputSampler` — or, when asked, a bot. Each screen marks its own
 * player "YOU" and shows that player's HUD. The match ends when the game does (see
 * `network-online-end.ts`), with the same final screen and hash in both tabs. Shows the
 * connection, the round trip, the tick, the hash of the state at the last checkpoint and at the
 * end, and whether the relay saw a desync.
 */
import {
  InputSampler,
  LockstepSession,
  attachKeyboard,
  connectWebSocket,
  hex64,
  performanceClock,
  type ButtonInput,
  type KeyboardEventLike,
  type KeyboardHost,
  type NetSession,
  type Transport,
  type Simulation,
} from 'fixedstep';
import { CtfGame, type Game } from '@fixedstep/games';
import { toggle } from '../../ui/controls.js';
import { h, setAttr } from '../../ui/dom.js';
import * as fmt from '../../ui/format.js';
import { gameDef, keyLabel, keyMap } from '../../games-view/games.js';
import { drawGame, drawMessage } from '../../games-view/render.js';
import { attachTouchPad } from '../../games-view/touch-pad.js';
import { BOT_EVERY, CHECKPOINT_TICKS } from './network-lab.js';
import { QuickMatchControl } from './network-quick-match.js';
import { watchEnd, type MatchEnd } from './network-online-end.js';
import { connectPeerToPeer, type P2pConnection } from './network-online-p2p.js';
import { OnlineRoomPanel, ROOM_NAME, serverSocketUrl } from './network-online-room.js';

/**
 * Room, a shorter match and whether to join at once, from the address:
 * `#/network?room=abc&ticks=600&join=1`. Without `ticks` (or with one shorter than a checkpoint)
 * the match lasts until the game ends it (`ticks: undefined`).
 */
export function onlineOptions(hash: string): {
  room: string | undefined;
  ticks: number | undefined;
  join: boolean;
  p2p: boolean;
  invite: Uint8Array | undefined;
} {
  const q = hash.includes('?') ? new URLSearchParams(hash.slice(hash.indexOf('?') + 1)) : undefined;
  const room = q?.get('room') ?? undefined;
  const ticks = Number(q?.get('ticks') ?? '');
  const valid = room !== undefined && ROOM_NAME.test(room);
  return {
    room: valid ? room : undefined,
    ticks: Number.isInteger(ticks) && ticks >= CHECKPOINT_TICKS ? ticks : undefined,
    join: valid && q?.get('join') === '1',
    p2p: q?.get('p2p') === '1',
    invite: fromHex(q?.get('invite') ?? ''),
  };
}

/** 32 hex digits as 16 bytes (an invite token), or undefined. */
function fromHex(hex: string): Uint8Array | undefined {
  if (!/^[0-9a-f]{32}$/.test(hex)) return undefined;
  return Uint8Array.from({ length: 16 }, (_, i) => parseInt(hex.slice(2 * i, 2 * i + 2), 16));
}

/**
 * The address that opens `room` (a match of `ticks`, if shorter than the game) in another tab and
 * joins it there — peer to peer with the host's `invite`.
 */
export function roomLink(
  room: string,
  ticks: number | undefined,
  p2p = false,
  invite?: Uint8Array,
): string {
  const q = new URLSearchParams({ room });
  if (ticks !== undefined) q.set('ticks', String(ticks));
  if (p2p) q.set('p2p', '1');
  if (p2p && invite !== undefined) {
    q.set('invite', Array.from(invite, (b) => b.toString(16).padStart(2, '0')).join(''));
  }
  q.set('join', '1');
  return `#/network?${q.toString()}`;
}

/** The game's buttons and their keys, as printed on the keys: `Fire: Space / J`. */
function keysText(def: ReturnType<typeof gameDef>): string[] {
  return def.info.buttons.map((b) => `${b.name}: ${b.keys.map(keyLabel).join(' / ')}`);
}

type KeyListener = (e: KeyboardEventLike) => void;

/**
 * The panel `el` as a keyboard host: its keys while the focus is inside it, and a "blur" (every
 * held key let go) when the focus leaves it or the window loses focus — so a key released
 * elsewhere never stays down in the match.
 */
function panelKeys(el: HTMLElement): KeyboardHost {
  const blurs = new Map<KeyListener, { out: (e: FocusEvent) => void; win: (e: Event) => void }>();
  return {
    addEventListener(type: 'keydown' | 'keyup' | 'blur', fn: KeyListener): void {
      if (type !== 'blur') {
        el.addEventListener(type, fn);
        return;
      }
      const pair = {
        out: (e: FocusEvent) => {
          if (!(e.relatedTarget instanceof Node && el.contains(e.relatedTarget))) fn(e as never);
        },
        win: (e: Event) => {
          fn(e as never);
        },
      };
      blurs.set(fn, pair);
      el.addEventListener('focusout', pair.out);
      window.addEventListener('blur', pair.win);
    },
    removeEventListener(type: 'keydown' | 'keyup' | 'blur', fn: KeyListener): void {
      if (type !== 'blur') {
        el.removeEventListener(type, fn);
        return;
      }
      const pair = blurs.get(fn);
      if (!pair) return;
      blurs.delete(fn);
      el.removeEventListener('focusout', pair.out);
      window.removeEventListener('blur', pair.win);
    },
  };
}

export class OnlinePanel extends OnlineRoomPanel<NetSession> {
  readonly el: HTMLElement;
  private readonly stopAt: number | undefined;
  private readonly def = gameDef('ctf');
  /** This player's buttons, from the keyboard and the on-screen controls, stamped with their time. */
  private readonly sampler = new InputSampler<ButtonInput>(this.def.input);
  private readonly touch: HTMLElement;
  private readonly detachTouch: () => void;
  private detachKeys: (() => void) | undefined;
  /** Whether a bot plays this side (an explicit choice; people play by default). */
  private bot = false;
  /** Whether to play peer to peer (WebRTC, the relay in the first page) instead of through the server's relay. */
  private p2p: boolean;
  private p2pConn: P2pConnection | undefined;
  /** A peer-to-peer room's invite: from the link that opened this tab, or from hosting it. */
  private invite: Uint8Array | undefined;
  private via = '';
  /** Where the match ended, and its final state to draw. */
  private end: { end: MatchEnd; game: Game } | undefined;
  /** A quick match's ticket: it seats this tab in the room the matchmaker set up. */
  private ticket: Uint8Array | undefined;
  // Quick match: the server names a fresh room for two waiting tabs; join it with the ticket.
  private readonly quick = new QuickMatchControl((match) => {
    if (this.session) this.leave();
    this.roomInput.value = match.room;
    this.ticket = match.ticket;
    this.updateLink();
    this.join();
  });

  constructor() {
    const opts = onlineOptions(location.hash);
    super({
      kind: '',
      room: opts.room ?? `room-${Math.floor(Math.random() * 1e6).toString(36)}`,
      canvasLabel: 'Your machine in the online room',
      waiting: ['Waiting for the other player…', 'Open this room in a second tab.'],
      // Short lines: they fit the canvas of a 390 px phone.
      idle: [
        'Not in a room.',
        'Press “Join room”, then open',
        'the room in a second tab: the',
        'match starts when both are in.',
      ],
    });
    this.stopAt = opts.ticks;
    this.p2p = opts.p2p;
    this.invite = opts.invite;
    const bot = toggle('A bot plays my side', 'control-online-bot', false, (on) => {
      this.bot = on;
    });
    const p2p = toggle('Peer to peer (WebRTC)', 'control-online-p2p', this.p2p, (on) => {
      this.p2p = on;
      this.updateLink();
    });
    p2p.title = 'Data channels between the two browsers; this server only introduces them';
    this.updateLink();
    // On-screen controls: shown on touch screens (and with `?touch=1`), through the same sampler.
    this.touch = h('div', {
      class: 'touch-controls net-touch',
      'data-testid': 'online-touch-controls',
    });
    if (new URLSearchParams(location.hash.split('?')[1] ?? '').get('touch') === '1') {
      this.touch.classList.add('always');
    }
    this.detachTouch = attachTouchPad(
      this.touch,
      this.def.info.id,
      this.sampler,
      (e) => e.timeStamp,
    );
    // Focusable: the keys work while the focus is in this panel (click the game).
    this.canvas.canvas.tabIndex = 0;
    this.el = this.section({
      id: 'net-online',
      title: 'Play online: two tabs, one server',
      intro:
        'The same lockstep session over a real WebSocket to this server’s relay (or, with “Peer to peer”, over WebRTC data channels between the two browsers), played by two people. Join a room here, then open this page with the same room in another tab or on another computer: the match starts when both players are in and ends when the game does (the clock runs out or a team captures 5 flags). Each screen marks its own player YOU; the hashes at each checkpoint and at the end must be the same in both tabs.',
      controlsLabel: 'Online room',
      controls: [
        this.roomGroup(this.tabLink, this.quick.el),
        h('div', { class: 'control-group' }, bot, p2p),
      ],
      body: [
        h(
          'ul',
          { class: 'net-keys', 'data-testid': 'online-keys', 'aria-label': 'Keys' },
          h(
            'li',
            {},
            'Click the game, then play with the keys (or the controls under it on a phone):',
          ),
          ...keysText(this.def).map((t) => h('li', {}, t)),
        ),
        this.machine(
          [this.touch],
          [
            this.row('Connection', 'state'),
            this.row('Transport', 'via'),
            this.row('You are', 'slot'),
            this.row('Your kills, flags', 'you'),
            this.row('Round trip', 'rtt'),
            this.row('Tick', 'tick'),
            this.row('Checkpoint tick', 'checkpoint'),
            this.row('Hash there', 'hash', true),
            this.row('The end', 'end'),
            this.row('Hash at the end', 'final-hash', true),
            this.row('Desyncs reported', 'desyncs'),
          ],
        ),
      ],
    });
    this.render();
    if (opts.join) this.join();
  }

  protected link(room: string): string {
    return roomLink(room, this.stopAt, this.p2p, this.invite);
  }

  protected override joining(): void {
    this.end = undefined;
  }

  protected open(room: string): Promise<NetSession> {
    const def = this.def;
    const ws = serverSocketUrl(location, '');
    const connect: Promise<Transport> = this.p2p
      ? connectPeerToPeer(`${ws}/signal`, room, def, this.invite).then((c) => {
          this.p2pConn = c;
          // The host's invite goes into the second tab's link.
          this.invite = c.invite;
          this.updateLink();
          this.via = {
            host: 'WebRTC, hosting',
            webrtc: 'WebRTC, direct',
            server: 'WebRTC fallback: through the server',
          }[c.via];
          return c.transport;
        })
      : // The room in the URL: a balancer sends every player of a room to one server process.
        connectWebSocket(`${ws}/ws/${room}`).then((t) => {
          this.via = 'WebSocket to the relay';
          return t;
        });
    const ticket = this.p2p ? undefined : this.ticket;
    this.ticket = undefined;
    return connect.then((transport) => {
      let held = 0;
      // Every event stamped up to now belongs to the tick being issued now.
      const now = { isBeforeUpdateEnd: (t: number) => t <= performance.now() };
      this.sampler.clear();
      this.detachKeys = attachKeyboard(panelKeys(this.el), this.sampler, keyMap(def.info));
      const session: NetSession = new LockstepSession({
        transport,
        clock: performanceClock(),
        room,
        game: def.info.id,
        gameVersion: def.info.version,
        input: def.input,
        players: 2,
        ...(ticket === undefined ? {} : { ticket }),
        ...(this.stopAt === undefined ? {} : { stopAt: this.stopAt }),
        createSimulation: (w) => {
          const config = def.decodeConfig(w.config);
          return watchEnd(def.create(config), this.stopAt ?? Infinity, (end) => {
            const game = def.create(config);
            game.load(end.bytes);
            this.end = { end, game };
          });
        },
        localInput: (tick: number, sim: Simulation) => {
          const input = this.sampler.sample(now, 0);
          if (!this.bot) return input;
          if (tick % BOT_EVERY === 0) held = def.bot(sim as Game, session.welcome?.slot ?? 0);
          return held;
        },
        onEvent: (e) => {
          this.noteEvent(e);
        },
      });
      return session;
    });
  }

  protected override started(): void {
    this.canvas.canvas.focus({ preventScroll: true });
  }

  protected frame(session: NetSession): void {
    session.frame();
    // Over: the relay already has every input up to the end, so the other player reaches the
    // same end without us. Leave the room; the final screen stays.
    if (this.end) this.finish();
  }

  /** The game is over: stop playing and leave the room, keeping the numbers and the final screen. */
  private finish(): void {
    this.stopFrames();
    this.detachKeys?.();
    this.detachKeys = undefined;
    this.session?.leave();
    this.state = 'finished';
  }

  protected override left(): void {
    this.detachKeys?.();
    this.detachKeys = undefined;
    this.sampler.clear();
    // Hosting peer to peer, the relay ran here until now (not at the end: the other player may
    // still be receiving the last ticks from it).
    if (this.p2pConn?.via === 'host') this.invite = undefined; // the room it hosted is gone
    this.p2pConn?.close();
    this.p2pConn = undefined;
    this.via = '';
    this.end = undefined;
  }

  /** Show the connection's numbers and draw the machine (or what it is waiting for). */
  protected render(): void {
    const s = this.session;
    const o = this.out;
    const end = this.end;
    const state = end
      ? 'finished'
      : s
        ? s.phase === 'closed'
          ? this.state
          : s.phase === 'waiting'
            ? 'waiting for the other player'
            : s.phase
        : this.state;
    o.state?.set(state, state);
    o.via?.set(this.via || '—', this.via);
    const slot = s?.welcome?.slot;
    o.slot?.set(
      slot === undefined ? '—' : `player ${slot + 1} (${slot % 2 === 0 ? 'red' : 'blue'})`,
      slot === undefined ? '' : slot + 1,
    );
    const g = end?.game ?? (s?.simulation as Game | undefined);
    const st = g instanceof CtfGame && slot !== undefined ? g.state : undefined;
    const kills = st?.kills[slot ?? 0];
    const flags = st?.captures[slot ?? 0];
    o.you?.set(
      kills === undefined ? '—' : `${fmt.count(kills)} kills, ${fmt.count(flags ?? 0)} flags`,
      kills === undefined ? '' : `${kills},${flags ?? 0}`,
    );
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
    o.end?.set(
      end ? `tick ${fmt.count(end.end.tick)}, ${end.end.reason}` : '—',
      end ? end.end.tick : '',
    );
    o['final-hash']?.set(end?.end.hash ?? '—', end?.end.hash ?? '');
    const desyncs = s?.desyncs.length ?? 0;
    o.desyncs?.set(fmt.count(desyncs), desyncs);
    o.desyncs?.warn(desyncs > 0);
    setAttr(this.el, 'data-state', end ? 'finished' : (s?.phase ?? 'offline'));
    // The player this screen marks "YOU" (1-based), for a reader of the page.
    setAttr(this.canvas.canvas, 'data-you', slot === undefined ? '' : String(slot + 1));
    const x = st?.x[slot ?? 0];
    setAttr(this.canvas.canvas, 'data-you-x', x === undefined ? '' : x.toFixed(1));
    if (this.canvas.fit()) {
      if (g && s) {
        drawGame(this.canvas, g, {
          alpha: end ? 1 : s.alpha,
          nowMs: performance.now(),
          badge: { text: `tick ${end ? end.end.tick : s.tick}`, tone: end ? 'good' : 'info' },
          you: slot ?? 0,
        });
      } else {
        drawMessage(this.canvas, this.message());
      }
    }
  }

  override destroy(): void {
    this.quick.cancel();
    super.destroy();
    this.detachTouch();
  }
}
