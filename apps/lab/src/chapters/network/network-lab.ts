/**
 * Chapter 6, network — the model, without the DOM. Two players play one game over simulated
 * links (seeded latency, jitter and loss) on a virtual clock, three times: through the relay core
 * with lockstep sessions, with rollback sessions, and through a state-sync room that runs the game
 * itself (network-state.ts) — same game, same seed, same link settings. The page draws both
 * players' machines of each and reads the numbers from here.
 */
import {
  LockstepSession,
  Relay,
  Random,
  RollbackSession,
  relayGameOf,
  type Correction,
  type LinkConditions,
  type NetSession,
  type SimulatedLink,
} from 'fixedstep';
import type { Game, RegisteredGame } from '@fixedstep/games';
import { gameDef } from '../../games-view/games.js';
import { agreementOf } from '../../shell/simulated-machines.js';
import {
  CHECKPOINT_TICKS,
  DEFAULT_NET_SETTINGS,
  NET_MODES,
  TwoPlayerMatch,
  linkOf,
  playerShift,
  type MachineView,
  type MatchReadouts,
  type ModelMatch,
  type ModelNumbers,
  type NetMode,
  type NetSettings,
} from './network-model.js';
import { StateSyncMatch } from './network-state.js';

export {
  BOT_EVERY,
  CHECKPOINT_TICKS,
  DEFAULT_NET_SETTINGS,
  NET_GAMES,
  NET_MODES,
  linkOf,
} from './network-model.js';
export type {
  MatchReadouts,
  ModelNumbers,
  NetGameId,
  NetMode,
  NetSettings,
} from './network-model.js';

/**
 * One input-sync match: the relay and two sessions of one kind (lockstep or rollback), over two
 * simulated links, on its own event scheduler (virtual ms).
 */
export class NetMatch extends TwoPlayerMatch {
  readonly relay: Relay;
  readonly sessions: [NetSession, NetSession];
  readonly links: [SimulatedLink, SimulatedLink];
  readonly def: RegisteredGame;
  private readonly before: Game;
  private readonly after: Game;

  constructor(
    readonly mode: 'lockstep' | 'rollback',
    settings: NetSettings,
  ) {
    super(settings);
    const def = gameDef(settings.game);
    this.def = def;
    this.before = def.create({ seed: settings.seed, players: 2 });
    this.after = def.create({ seed: settings.seed, players: 2 });
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
      const link = this.newLink(slot);
      this.relay.accept(link.b);
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
        localInput: this.playerInput(def, () => session.welcome?.slot ?? slot),
        onCorrection: (c: Correction) => {
          this.correction(c);
        },
      };
      const session: NetSession =
        mode === 'lockstep' ? new LockstepSession(options) : new RollbackSession(options);
      // Display frames at 60 Hz, the two machines out of phase (unless real frames drive them).
      this.display(slot * 7.3, () => {
        this.frame(session);
      });
      return [session, link];
    };
    const [s0, l0] = make(0);
    const [s1, l1] = make(1);
    this.sessions = [s0, s1];
    this.links = [l0, l1];
  }

  protected drawAll(): void {
    for (const s of this.sessions) this.frame(s);
  }

  private frame(session: NetSession): void {
    const now = this.scheduler.now;
    session.frame(now);
    // Player 1 (slot 0) sees its input once its machine stepped past the tick; the other player
    // once the input is confirmed there and the state after it computed (rollback: the rollback
    // done).
    const [a, b] = this.sessions;
    const own = a.welcome?.slot === 0 ? a : b;
    const other = own === a ? b : a;
    const otherTick = this.mode === 'lockstep' ? other.tick : other.confirmedStateTick();
    this.probe.frame(now, own.tick, otherTick);
  }

  /** A rollback's correction: how far it moved a drawn player. */
  private correction(c: Correction): void {
    try {
      this.before.load(c.before);
      this.after.load(c.after);
    } catch {
      return;
    }
    this.noteCorrection(playerShift(this.before, this.after));
  }

  /** The game a machine shows (undefined before its welcome). */
  game(i: 0 | 1): Game | undefined {
    return this.sessions[i].simulation as Game | undefined;
  }

  view(i: 0 | 1): MachineView | undefined {
    const g = this.game(i);
    const s = this.sessions[i];
    return g ? { game: g, alpha: s.alpha, tick: s.tick, slot: s.welcome?.slot ?? i } : undefined;
  }

  readouts(): MatchReadouts {
    const [a, b] = this.sessions;
    const desyncs = this.relay.room('lab')?.desyncs.length ?? 0;
    return {
      ...agreementOf(a, b, CHECKPOINT_TICKS, desyncs, this.links),
      mode: this.mode,
      ticks: [a.tick, b.tick],
      inputDelay: Math.max(a.stats.inputDelay, b.stats.inputDelay),
      rollbacks: a.stats.rollbacks + b.stats.rollbacks,
      maxDepth: Math.max(a.stats.maxRollbackDepth, b.stats.maxRollbackDepth),
      stalls: a.stats.stalls + b.stats.stalls,
      rttMs: Math.max(a.stats.rtt, b.stats.rtt),
      renderDelayMs: 0,
      lead: Math.max(a.stats.lead, b.stats.lead),
      snapshots: 0,
    };
  }
}

/**
 * The three matches, side by side, on one virtual clock. The links are always simulated; the
 * machines' displays are simulated 60 Hz ones, or — with {@link realClock} — the page's own
 * animation frames, which move the virtual clock at the page's pace ({@link realFrame}).
 */
export class NetworkLab {
  settings: NetSettings;
  matches: { statesync: StateSyncMatch; lockstep: NetMatch; rollback: NetMatch };
  private time = 0;
  private real = false;
  private realBase: number | undefined;

  constructor(settings: Partial<NetSettings> = {}) {
    this.settings = { ...DEFAULT_NET_SETTINGS, ...settings };
    this.matches = this.build();
  }

  private build(): NetworkLab['matches'] {
    const matches = {
      statesync: new StateSyncMatch(this.settings),
      lockstep: new NetMatch('lockstep', this.settings),
      rollback: new NetMatch('rollback', this.settings),
    };
    for (const m of NET_MODES) matches[m].realFrames = this.real;
    return matches;
  }

  /** The match of a model. */
  match(mode: NetMode): ModelMatch {
    return this.matches[mode];
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

  /** Start the matches again from zero with the current settings. */
  restart(): void {
    this.time = 0;
    this.realBase = undefined;
    this.matches = this.build();
  }

  /** Change the links now (every match, both players, both directions). */
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
      statesync: this.matches.statesync.readouts(),
      lockstep: this.matches.lockstep.readouts(),
      rollback: this.matches.rollback.readouts(),
    };
  }

  /** The comparison table's numbers, one row per model. */
  compare(): ModelNumbers[] {
    return NET_MODES.map((m) => this.matches[m].numbers());
  }
}
