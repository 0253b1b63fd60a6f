/**
 * Chapter 6, network — the model, without the DOM. Two players play one game through the real
 * relay core over simulated links (seeded latency, jitter and loss) on a virtual clock: once with
 * lockstep sessions, once with rollback sessions, same game, same seed, same link settings. The
 * page draws both players' machines of each and reads the numbers from here.
 */
import {
  EventScheduler,
  LockstepSession,
  Relay,
  Random,
  RollbackSession,
  SimulatedLink,
  hex64,
  relayGameOf,
  type LinkConditions,
  type NetSession,
  type Simulation,
} from 'fixedstep';
import type { Game, GameDefinition } from '@fixedstep/games';
import { gameDef } from '../../games-view/games.js';

export type NetMode = 'lockstep' | 'rollback';
export const NET_MODES: readonly NetMode[] = ['lockstep', 'rollback'];
export const NET_GAMES = ['ctf', 'survival'] as const;
export type NetGameId = (typeof NET_GAMES)[number];

/** Hashes are compared at checkpoints this many ticks apart (1 s at 60 Hz). */
export const CHECKPOINT_TICKS = 60;
/** Bots re-decide every this many ticks and hold in between (a human-like 100 ms). */
export const BOT_EVERY = 6;

export interface NetSettings {
  game: NetGameId;
  seed: number;
  latencyMs: number;
  jitterMs: number;
  /** 0–1. */
  loss: number;
  /** Player 0 on the keyboard instead of its bot. */
  keyboard: boolean;
}

export const DEFAULT_NET_SETTINGS: Readonly<NetSettings> = {
  game: 'ctf',
  seed: 7,
  latencyMs: 80,
  jitterMs: 20,
  loss: 0.02,
  keyboard: false,
};

export function linkOf(s: NetSettings): LinkConditions {
  return { latencyMs: s.latencyMs, jitterMs: s.jitterMs, loss: s.loss };
}

/** What the page shows of one match. */
export interface MatchReadouts {
  mode: NetMode;
  ticks: [number, number];
  /** Lockstep: input delay now, ticks (the larger of the two players'). */
  inputDelay: number;
  /** Rollback: rollbacks of both players, and the deepest, ticks. */
  rollbacks: number;
  maxDepth: number;
  stalls: number;
  rttMs: number;
  /** The last checkpoint both machines have a confirmed state of (-1: none yet). */
  checkpoint: number;
  hashes: [string, string];
  /** Both machines have a hash at the checkpoint, equal, and the relay saw no desync. */
  equal: boolean;
  desyncs: number;
  /** Messages lost on all links so far. */
  lost: number;
  sent: number;
}

/**
 * One match: the relay and two sessions of one kind, over two simulated links, on its own
 * event scheduler (virtual ms).
 */
export class NetMatch {
  readonly scheduler = new EventScheduler(0);
  readonly relay: Relay;
  readonly sessions: [NetSession, NetSession];
  readonly links: [SimulatedLink, SimulatedLink];
  readonly def: GameDefinition;
  /** Buttons held on the keyboard (player 0 when `settings.keyboard`). */
  keys = 0;
  /**
   * Real display frames: both machines draw when the page does ({@link realFrame}) instead of
   * on their simulated 60 Hz displays.
   */
  realFrames = false;

  constructor(
    readonly mode: NetMode,
    readonly settings: NetSettings,
  ) {
    const def = gameDef(settings.game);
    this.def = def;
    const clock = this.scheduler.clock;
    const random = new Random(settings.seed ^ 0x9e3779b9);
    const game = relayGameOf(def);
    this.relay = new Relay({
      clock,
      randomU32: () => random.nextU32(),
      catalog: (id, version) =>
        id === game.id && version === game.version
          ? game
          : { code: 'UNKNOWN_GAME', message: `no game "${id}" v${version} here` },
    });
    const tickMs = 1000 / def.info.tickRate;
    this.scheduler.every(
      tickMs / 2,
      () => {
        this.relay.update(clock.now());
      },
      tickMs / 2,
    );
    const make = (slot: 0 | 1): [NetSession, SimulatedLink] => {
      const link = new SimulatedLink({
        scheduler: this.scheduler,
        seed: settings.seed * 7919 + slot,
        ...linkOf(settings),
      });
      this.relay.accept(link.b);
      let held = 0;
      let prevKeys = 0;
      const options = {
        transport: link.a,
        clock,
        room: 'lab',
        game: def.info.id,
        gameVersion: def.info.version,
        input: def.input,
        players: 2,
        seed: settings.seed,
        name: `player${slot + 1}`,
        createSimulation: (w: { config: Uint8Array }) => def.create(def.decodeConfig(w.config)),
        localInput: (tick: number, sim: Simulation) => {
          const me = session.welcome?.slot ?? slot;
          if (settings.keyboard && me === 0) {
            // Held buttons in the low half, this tick's new presses in the high half.
            const down = this.keys;
            const input = (down | ((down & ~prevKeys) << 16)) >>> 0;
            prevKeys = down;
            return input;
          }
          if (tick % BOT_EVERY === 0) held = def.bot(sim as Game, me);
          return held;
        },
      };
      const session: NetSession =
        mode === 'lockstep' ? new LockstepSession(options) : new RollbackSession(options);
      // Display frames at 60 Hz, the two machines out of phase (unless real frames drive them).
      this.scheduler.every(
        1000 / 60,
        () => {
          if (!this.realFrames) session.frame(this.scheduler.now);
        },
        slot * 7.3,
      );
      return [session, link];
    };
    const [s0, l0] = make(0);
    const [s1, l1] = make(1);
    this.sessions = [s0, s1];
    this.links = [l0, l1];
  }

  get nowMs(): number {
    return this.scheduler.now;
  }

  advanceTo(ms: number): void {
    if (ms > this.scheduler.now) this.scheduler.runUntil(ms);
  }

  /** A real display frame at virtual `ms`: the links and the relay run to then, both machines draw. */
  realFrame(ms: number): void {
    this.advanceTo(ms);
    for (const s of this.sessions) s.frame(this.scheduler.now);
  }

  setLink(c: LinkConditions): void {
    for (const l of this.links) l.setConditions(c);
  }

  /** The game a machine shows (undefined before its welcome). */
  game(i: 0 | 1): Game | undefined {
    return this.sessions[i].simulation as Game | undefined;
  }

  readouts(): MatchReadouts {
    const [a, b] = this.sessions;
    const confirmed = Math.min(a.confirmedStateTick(), b.confirmedStateTick());
    const checkpoint =
      confirmed >= CHECKPOINT_TICKS
        ? Math.floor(confirmed / CHECKPOINT_TICKS) * CHECKPOINT_TICKS
        : -1;
    const hashOf = (s: NetSession): string => {
      if (checkpoint < 0) return '';
      const h = s.hashAt(checkpoint);
      return h === undefined ? '' : hex64(h);
    };
    const hashes: [string, string] = [hashOf(a), hashOf(b)];
    const desyncs = this.relay.room('lab')?.desyncs.length ?? 0;
    let lost = 0;
    let sent = 0;
    for (const l of this.links) {
      for (const d of l.stats) {
        lost += d.lost;
        sent += d.sent;
      }
    }
    return {
      mode: this.mode,
      ticks: [a.tick, b.tick],
      inputDelay: Math.max(a.stats.inputDelay, b.stats.inputDelay),
      rollbacks: a.stats.rollbacks + b.stats.rollbacks,
      maxDepth: Math.max(a.stats.maxRollbackDepth, b.stats.maxRollbackDepth),
      stalls: a.stats.stalls + b.stats.stalls,
      rttMs: Math.max(a.stats.rtt, b.stats.rtt),
      checkpoint,
      hashes,
      equal: hashes[0] !== '' && hashes[0] === hashes[1] && desyncs === 0,
      desyncs,
      lost,
      sent,
    };
  }
}

/**
 * Both matches, side by side, on one virtual clock. The links are always simulated; the machines'
 * displays are simulated 60 Hz ones, or — with {@link realClock} — the page's own animation
 * frames, which move the virtual clock at the page's pace ({@link realFrame}).
 */
export class NetworkLab {
  settings: NetSettings;
  matches: Record<NetMode, NetMatch>;
  private time = 0;
  private real = false;
  private realBase: number | undefined;

  constructor(settings: Partial<NetSettings> = {}) {
    this.settings = { ...DEFAULT_NET_SETTINGS, ...settings };
    this.matches = this.build();
  }

  private build(): Record<NetMode, NetMatch> {
    const matches = {
      lockstep: new NetMatch('lockstep', this.settings),
      rollback: new NetMatch('rollback', this.settings),
    };
    for (const m of NET_MODES) matches[m].realFrames = this.real;
    return matches;
  }

  get timeMs(): number {
    return this.time;
  }

  /** The machines draw on the page's real animation frames instead of simulated 60 Hz ones. */
  get realClock(): boolean {
    return this.real;
  }

  /** Switch the machines' displays, going on from now; the real time line is pinned to now at its first frame. */
  setRealClock(on: boolean): void {
    this.real = on;
    this.realBase = undefined;
    for (const m of NET_MODES) this.matches[m].realFrames = on;
  }

  /** Simulated displays: move the virtual clock to `ms`. */
  advanceTo(ms: number): void {
    this.time = Math.max(this.time, ms);
    for (const m of NET_MODES) this.matches[m].advanceTo(this.time);
  }

  advanceBy(ms: number): void {
    this.advanceTo(this.time + ms);
  }

  /** Real clock: one animation frame at `realMs` on the driver's time line (ignored otherwise). */
  realFrame(realMs: number): void {
    if (!this.real) return;
    this.realBase ??= realMs - this.time;
    this.time = Math.max(this.time, realMs - this.realBase);
    for (const m of NET_MODES) this.matches[m].realFrame(this.time);
  }

  /** Start both matches again from zero with the current settings. */
  restart(): void {
    this.time = 0;
    this.realBase = undefined;
    this.matches = this.build();
  }

  /** Change the links now (both matches, both players, both directions). */
  setLink(c: Partial<LinkConditions>): void {
    this.settings = { ...this.settings, ...c };
    for (const m of NET_MODES) this.matches[m].setLink(linkOf(this.settings));
  }

  /** Change the game, seed or keyboard: the matches start again. */
  reset(s: Partial<NetSettings>): void {
    this.settings = { ...this.settings, ...s };
    this.restart();
  }

  setKeys(keys: number): void {
    for (const m of NET_MODES) this.matches[m].keys = keys;
  }

  readouts(): Record<NetMode, MatchReadouts> {
    return {
      lockstep: this.matches.lockstep.readouts(),
      rollback: this.matches.rollback.readouts(),
    };
  }
}
