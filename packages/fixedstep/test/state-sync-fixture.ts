/**
 * A small arena for the state-sync tests: up to four discs that walk by their buttons, push each
 * other apart, and feel a seeded gust now and then. Positions are floats, so a client that adds
 * its floats in another order — or feels an extra tiny force — drifts from the server.
 */
import {
  ByteReader,
  ByteWriter,
  EventScheduler,
  Random,
  SimulatedLink,
  StateSyncRoom,
  StateSyncSession,
  defineGame,
  defineInput,
  fnv1a64,
  isDown,
  type ButtonInput,
  type GameDefinition,
  type GameSetup,
  type LinkConditions,
  type Simulation,
  type StateSyncRender,
  type StateSyncRoomOptions,
  type StateSyncSessionOptions,
} from 'fixedstep';

export const ARENA_INPUT = defineInput({ buttons: ['left', 'right', 'up', 'down'] });
const MAGIC = 0x41524e41; // "ANRA"
/** Units per second a disc walks. */
export const SPEED = 30;
/** Disc radius (units). */
export const RADIUS = 2;
/** The arena is [0, SIZE]². */
export const SIZE = 100;
const DT = 1 / 60;
/** How far the conveyor shoves disc 0 (units). */
export const SHOVE = 3;

/** How a client's copy of the arena may differ from the server's (the non-deterministic game). */
export interface Drift {
  /** Added to every disc's x each tick (units). */
  force?: number;
  /** Sum the step's terms in another order (differs from the server's in the last bits). */
  reorder?: boolean;
  /** Multiplies the walking speed (a modified client that gives itself speed). */
  speed?: number;
  /** Forget the conveyor: the rule that shoves disc 0 three units down at tick 150, 450, 750 … */
  noShove?: boolean;
}

export class Arena implements Simulation {
  tick = 0;
  readonly x: Float64Array;
  readonly y: Float64Array;
  readonly rng: Random;
  /** Server-only stat: how often `step` ran (tests count steps). */
  steps = 0;
  /** Hash of the state after each step, when recording (the server's history). */
  history: Map<number, bigint> | undefined;
  /** Every disc's (x, y) after each step, when recording. */
  trail: Map<number, Float64Array> | undefined;

  constructor(
    readonly players: number,
    seed: number,
    readonly drift: Drift = {},
  ) {
    this.x = new Float64Array(players);
    this.y = new Float64Array(players);
    this.rng = new Random(seed);
    for (let p = 0; p < players; p++) {
      this.x[p] = 20 + 20 * p;
      this.y[p] = 30 + 10 * (p % 2);
    }
  }

  step(inputs: readonly ButtonInput[]): void {
    const n = this.players;
    const v = SPEED * DT * (this.drift.speed ?? 1);
    const gust = this.tick % 90 === 0 ? this.rng.range(-1, 1) : 0;
    for (let p = 0; p < n; p++) {
      const b = inputs[p] ?? 0;
      const dx = (isDown(b, 1) ? v : 0) - (isDown(b, 0) ? v : 0);
      const dy = (isDown(b, 3) ? v : 0) - (isDown(b, 2) ? v : 0);
      const fx = gust * 0.1 + (this.drift.force ?? 0);
      this.x[p] = this.drift.reorder ? this.x[p]! + (dx + fx) : this.x[p]! + dx + fx;
      this.y[p] = this.y[p]! + dy;
    }
    // The conveyor: a rule of the game that a drifting client may not know.
    if (this.tick % 300 === 150 && !this.drift.noShove) this.y[0] = this.y[0]! + SHOVE;
    // Push overlapping discs apart, in index order.
    for (let a = 0; a < n; a++) {
      for (let b = a + 1; b < n; b++) {
        const ex = this.x[b]! - this.x[a]!;
        const ey = this.y[b]! - this.y[a]!;
        const d2 = ex * ex + ey * ey;
        if (d2 >= 4 * RADIUS * RADIUS || d2 === 0) continue;
        const d = Math.sqrt(d2);
        const push = (2 * RADIUS - d) / 2 / d;
        this.x[a] = this.x[a]! - ex * push;
        this.y[a] = this.y[a]! - ey * push;
        this.x[b] = this.x[b]! + ex * push;
        this.y[b] = this.y[b]! + ey * push;
      }
    }
    for (let p = 0; p < n; p++) {
      this.x[p] = Math.min(SIZE, Math.max(0, this.x[p]!));
      this.y[p] = Math.min(SIZE, Math.max(0, this.y[p]!));
    }
    this.tick++;
    this.steps++;
    this.history?.set(this.tick, this.hash());
    this.trail?.set(this.tick, this.positions());
  }

  /** Every disc's (x, y), interleaved (what {@link ARENA_RENDER} draws). */
  positions(): Float64Array {
    const out = new Float64Array(2 * this.players);
    for (let p = 0; p < this.players; p++) {
      out[2 * p] = this.x[p]!;
      out[2 * p + 1] = this.y[p]!;
    }
    return out;
  }

  save(): Uint8Array {
    const w = new ByteWriter(32 + 16 * this.players);
    w.u32(MAGIC).u32(this.tick).u8(this.players).ints(this.rng.getState());
    return w.f64s(this.x).f64s(this.y).finish();
  }

  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    if (r.u32('magic') !== MAGIC) throw new RangeError('not an arena state');
    const tick = r.u32('tick');
    const n = r.u8('players');
    if (n !== this.players)
      throw new RangeError(`an arena of ${n} players, this one has ${this.players}`);
    const s = new Uint32Array(4);
    r.ints(s);
    const x = new Float64Array(n);
    const y = new Float64Array(n);
    r.f64s(x);
    r.f64s(y);
    r.end();
    for (let p = 0; p < n; p++) {
      if (!(Number.isFinite(x[p]) && Number.isFinite(y[p])))
        throw new RangeError(`disc ${p} is not finite`);
    }
    this.tick = tick;
    this.rng.setState(s);
    this.x.set(x);
    this.y.set(y);
  }

  hash(): bigint {
    return fnv1a64(this.save());
  }
}

/** The arena's game definition; `drift` makes the copy a client builds differ. */
export function arenaGame(drift?: Drift): GameDefinition<ButtonInput, Arena> {
  return defineGame<ButtonInput, Arena>({
    id: 'arena',
    version: 1,
    tickRate: 60,
    input: ARENA_INPUT,
    minPlayers: 1,
    maxPlayers: 4,
    create: (setup: GameSetup) => new Arena(setup.players, setup.seed, drift),
    // Walks a square: a quarter of a lap each 120 ticks, a different phase per player.
    bot: (sim, player) => scripted(sim.tick, player),
  });
}

/** A deterministic input: walk a square, a different phase per player. */
export function scripted(tick: number, player: number): ButtonInput {
  const leg = (Math.floor(tick / 120) + player) % 4;
  return 1 << [1, 3, 0, 2][leg]!;
}

/** Draw each disc at (x, y). */
export const ARENA_RENDER: StateSyncRender<Arena> = {
  fields: 2,
  entities: 4,
  read(sim, out) {
    out.fill(0);
    for (let p = 0; p < sim.players; p++) {
      out[2 * p] = sim.x[p]!;
      out[2 * p + 1] = sim.y[p]!;
    }
  },
  teleport: 20,
};

/** A room and clients on simulated links, on one event scheduler. */
export class World {
  readonly scheduler = new EventScheduler(0);
  readonly room: StateSyncRoom<Arena>;
  readonly clients: StateSyncSession<ButtonInput, Arena>[] = [];
  readonly links: SimulatedLink[] = [];
  private linkSeed = 1;

  constructor(
    readonly game: GameDefinition<ButtonInput, Arena>,
    readonly link: Partial<LinkConditions>,
    room: Partial<StateSyncRoomOptions<Arena>> = {},
  ) {
    const random = new Random(99);
    this.room = new StateSyncRoom<Arena>({
      game,
      name: 'r',
      clock: this.scheduler.clock,
      players: 2,
      seed: 7,
      randomU32: () => random.nextU32(),
      ...room,
    });
    const server = this.room.simulation;
    server.history = new Map([[0, server.hash()]]);
    server.trail = new Map([[0, server.positions()]]);
    // The server updates every 4 ms (as the CLI's worker does).
    this.scheduler.every(4, () => this.room.update(this.scheduler.now));
  }

  /** A client on a link of its own (display frames at 60 Hz, each client out of phase). */
  client(
    options: Partial<StateSyncSessionOptions<ButtonInput, Arena>> = {},
    link: Partial<LinkConditions> = this.link,
  ): StateSyncSession<ButtonInput, Arena> {
    const l = new SimulatedLink({ scheduler: this.scheduler, seed: this.linkSeed++ * 31, ...link });
    this.links.push(l);
    this.room.accept(l.b);
    const index = this.clients.length;
    const session: StateSyncSession<ButtonInput, Arena> = new StateSyncSession<ButtonInput, Arena>({
      transport: l.a,
      clock: this.scheduler.clock,
      room: 'r',
      game: this.game,
      render: ARENA_RENDER,
      localInput: (tick) => scripted(tick, session.welcome?.slot ?? 0),
      // A spectator is invited: it brings the room's invite token.
      ...(options.role === 'spectator' ? { invite: this.room.invite } : {}),
      ...options,
    });
    this.clients.push(session);
    const frames = this.scheduler.every(
      1000 / 60,
      () => {
        if (session.phase === 'closed') frames.cancel();
        else this.onFrame(session, index);
      },
      this.scheduler.now + 3.1 * (index + 1),
    );
    return session;
  }

  /** Called on every display frame of a client (tests hook in here). */
  onFrame: (session: StateSyncSession<ButtonInput, Arena>, index: number) => void = (s) => {
    s.frame(this.scheduler.now);
    s.render(this.scheduler.now);
  };

  run(ms: number): void {
    this.scheduler.runFor(ms);
  }
}
