/**
 * Chapter 6, network — the talk's own model: a state-sync room runs the game on the "server" and
 * sends both players' machines the world (delta-coded) and the clock, over the same simulated
 * links as the other two models. Each machine predicts its own player and draws everything else
 * between two snapshots, a render delay behind. No DOM.
 */
import {
  Random,
  StateSyncRoom,
  StateSyncSession,
  fnv1a64,
  hex64,
  type ButtonInput,
  type SimulatedLink,
  type StateSyncRender,
} from 'fixedstep';
import {
  ArenaGame,
  SurvivalGame,
  type ArenaState,
  type Game,
  type RegisteredGame,
} from '@fixedstep/games';
import { gameDef } from '../../games-view/games.js';
import { lossOf } from '../../shell/simulated-machines.js';
import {
  CHECKPOINT_TICKS,
  TELEPORT_UNITS,
  TwoPlayerMatch,
  type MachineView,
  type MatchReadouts,
  type NetSettings,
  type PlayerState,
} from './network-model.js';

function arenaState(game: Game): ArenaState {
  if (!(game instanceof ArenaGame)) throw new RangeError(`${game.info.id} is not an arena game`);
  return (game as ArenaGame<ArenaState>).state;
}

function players(game: Game): PlayerState {
  return arenaState(game);
}

/**
 * What a state-sync machine draws of an arena game as numbers: every player slot's (x, y). Its own
 * slot comes from its prediction; the rest between snapshots.
 */
export function arenaRender(def: RegisteredGame): StateSyncRender<Game> {
  const slots = players(def.create({ seed: 1, players: def.info.minPlayers })).x.length;
  return {
    fields: 2,
    entities: slots,
    read(sim, out) {
      const st = players(sim);
      for (let p = 0; p < slots; p++) {
        out[2 * p] = st.x[p]!;
        out[2 * p + 1] = st.y[p]!;
      }
    },
    teleport: TELEPORT_UNITS,
  };
}

/**
 * The display of a snapshot pair: `display` holds the newer state; its "previous" positions are
 * set from `older`, for what exists in both (players alive in both, bullets and enemies of the
 * same serial), so the renderer's blend at `alpha` draws between the two snapshots.
 */
export function blendFrom(display: Game, older: Game): void {
  const d = arenaState(display);
  const o = arenaState(older);
  for (let p = 0; p < d.x.length; p++) {
    const both = d.alive[p] === 1 && o.alive[p] === 1;
    d.prevX[p] = both ? o.x[p]! : d.x[p]!;
    d.prevY[p] = both ? o.y[p]! : d.y[p]!;
  }
  const db = d.bullets;
  const ob = o.bullets;
  for (let i = 0; i < db.capacity; i++) {
    const both = db.alive[i] === 1 && ob.alive[i] === 1 && db.serial[i] === ob.serial[i];
    db.prevX[i] = both ? ob.x[i]! : db.x[i]!;
    db.prevY[i] = both ? ob.y[i]! : db.y[i]!;
  }
  if (display instanceof SurvivalGame && older instanceof SurvivalGame) {
    const ds = display.state;
    const os = older.state;
    for (let e = 0; e < ds.ex.length; e++) {
      const both =
        ds.enemyAlive[e] === 1 && os.enemyAlive[e] === 1 && ds.enemySerial[e] === os.enemySerial[e];
      ds.enemyPrevX[e] = both ? os.ex[e]! : ds.ex[e]!;
      ds.enemyPrevY[e] = both ? os.ey[e]! : ds.ey[e]!;
    }
  }
}

/**
 * What a state-sync machine draws: the two snapshots around its render tick (the newer loaded, its
 * "previous" positions from the older, blended at `alpha`), with its own player moved to its
 * prediction plus the correction offset.
 */
export class SnapshotDisplay {
  private display: Game | undefined;
  private older: Game | undefined;

  constructor(private readonly def: RegisteredGame) {}

  view(
    s: StateSyncSession<ButtonInput, Game>,
  ): { game: Game; alpha: number; tick: number } | undefined {
    const w = s.welcome;
    if (!w || !s.simulation) return undefined;
    const every = w.snapshotEvery;
    const r = s.renderTick;
    const t0 = Math.floor(r / every) * every;
    let a = s.snapshotAt(t0);
    let b = s.snapshotAt(t0 + every);
    let alpha = (r - t0) / every;
    if (!a || !b) {
      // Not both here (the newer is late, or one was lost): hold the newest snapshot.
      b = s.snapshotState;
      a = b;
      alpha = 0;
    }
    if (!a || !b) return undefined;
    const setup = { seed: w.seed, players: w.players };
    this.display ??= this.def.create(setup);
    this.older ??= this.def.create(setup);
    this.display.load(b);
    this.older.load(a);
    blendFrom(this.display, this.older);
    const st = players(this.display);
    const out = s.drawn;
    for (const e of s.ownedEntities) {
      if (st.alive[e] !== 1) continue;
      st.x[e] = st.prevX[e] = out[2 * e]!;
      st.y[e] = st.prevY[e] = out[2 * e + 1]!;
    }
    return { game: this.display, alpha: Math.min(1, Math.max(0, alpha)), tick: s.tick };
  }
}

interface Machine {
  session: StateSyncSession<ButtonInput, Game>;
  link: SimulatedLink;
  display: SnapshotDisplay;
}

/**
 * One state-sync match: the room and two machines, over two simulated links, on its own event
 * scheduler (virtual ms).
 */
export class StateSyncMatch extends TwoPlayerMatch {
  readonly mode = 'statesync' as const;
  readonly room: StateSyncRoom<Game>;
  readonly machines: [Machine, Machine];
  readonly links: [SimulatedLink, SimulatedLink];
  readonly def: RegisteredGame;
  /** The server's hash at every checkpoint tick. */
  private readonly serverHashes = new Map<number, string>();
  private checkpoint = -1;
  private hashes: [string, string] = ['', ''];

  constructor(settings: NetSettings) {
    super(settings);
    const def = gameDef(settings.game);
    this.def = def;
    const clock = this.scheduler.clock;
    const random = new Random(settings.seed ^ 0x51a7e5);
    this.room = new StateSyncRoom<Game>({
      game: def,
      name: 'lab',
      clock,
      players: 2,
      seed: settings.seed,
      randomU32: () => random.nextU32(),
    });
    this.scheduler.every(4, () => {
      this.room.update(clock.now());
      const t = this.room.tick;
      if (t % CHECKPOINT_TICKS === 0 && !this.serverHashes.has(t)) {
        this.serverHashes.set(t, hex64(this.room.simulation.hash()));
      }
    });
    const render = arenaRender(def);
    const make = (slot: 0 | 1): Machine => {
      const link = this.newLink(slot);
      this.room.accept(link.b);
      const session: StateSyncSession<ButtonInput, Game> = new StateSyncSession<ButtonInput, Game>({
        transport: link.a,
        clock,
        room: 'lab',
        game: def,
        players: 2,
        seed: settings.seed,
        name: `player${slot + 1}`,
        render,
        onCorrection: (c) => {
          this.noteCorrection(c.size);
        },
        localInput: this.playerInput(def, () => session.welcome?.slot ?? slot),
      });
      // The two machines out of phase, and after the server's first join (slot 0 joins first).
      this.display(slot * 7.3 + 1, () => {
        this.frame(slot);
      });
      return { session, link, display: new SnapshotDisplay(def) };
    };
    const m0 = make(0);
    const m1 = make(1);
    this.machines = [m0, m1];
    this.links = [m0.link, m1.link];
  }

  protected drawAll(): void {
    this.frame(0);
    this.frame(1);
  }

  private frame(i: 0 | 1): void {
    const s = this.machines[i].session;
    const now = this.scheduler.now;
    s.frame(now);
    s.render(now);
    // Which machine is player 1's (slot 0): its own screen shows its prediction; the other's
    // draws slot 0 between snapshots.
    const [a, b] = this.machines;
    const own = a.session.welcome?.slot === 0 ? a.session : b.session;
    const other = own === a.session ? b.session : a.session;
    this.probe.frame(now, own.simulation ? own.tick : 0, Math.floor(other.renderTick));
    this.noteCheckpoint();
  }

  private noteCheckpoint(): void {
    const [a, b] = this.machines.map((m) => m.session);
    const newest = Math.min(a!.snapshotTick, b!.snapshotTick);
    if (newest < CHECKPOINT_TICKS) return;
    const c = Math.floor(newest / CHECKPOINT_TICKS) * CHECKPOINT_TICKS;
    if (c <= this.checkpoint) return;
    const sa = a!.snapshotAt(c);
    const sb = b!.snapshotAt(c);
    // A lost snapshot: keep the last checkpoint both machines had.
    if (!sa || !sb) return;
    this.checkpoint = c;
    this.hashes = [hex64(fnv1a64(sa)), hex64(fnv1a64(sb))];
  }

  readouts(): MatchReadouts {
    const [a, b] = this.machines.map((m) => m.session) as [
      StateSyncSession<ButtonInput, Game>,
      StateSyncSession<ButtonInput, Game>,
    ];
    const server = this.serverHashes.get(this.checkpoint);
    const { lost, sent } = lossOf(this.links);
    return {
      mode: this.mode,
      ticks: [a.tick, b.tick],
      inputDelay: 0,
      rollbacks: 0,
      maxDepth: 0,
      stalls: a.stats.stallFrames + b.stats.stallFrames,
      rttMs: Math.max(a.stats.rtt, b.stats.rtt),
      checkpoint: this.checkpoint,
      hashes: this.hashes,
      equal:
        this.hashes[0] !== '' && this.hashes[0] === this.hashes[1] && this.hashes[0] === server,
      desyncs: a.stats.badSnapshots + b.stats.badSnapshots,
      lost,
      sent,
      renderDelayMs: Math.max(a.renderDelayMs, b.renderDelayMs),
      lead: Math.max(a.stats.lead, b.stats.lead),
      snapshots:
        a.stats.fullSnapshots +
        a.stats.deltaSnapshots +
        b.stats.fullSnapshots +
        b.stats.deltaSnapshots,
    };
  }

  /** What machine `i` draws (see {@link SnapshotDisplay}). */
  view(i: 0 | 1): MachineView | undefined {
    const m = this.machines[i];
    const v = m.display.view(m.session);
    return v ? { ...v, slot: m.session.welcome?.slot ?? i } : undefined;
  }
}
