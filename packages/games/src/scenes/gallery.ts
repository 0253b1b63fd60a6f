/**
 * The shooting gallery: targets slide along their lanes and bounce at the ends; players fire
 * hit-scan shots at a lane and a position — the state-sync demo of lag compensation. A shot's input
 * says how far back the shooter's screen was (`rewind`, ticks: the issued tick minus the session's
 * `renderTick`); with compensation on, the server judges it against where the target was then
 * ({@link LagHistory}), otherwise against where it is now.
 * @module
 */
import {
  ByteReader,
  ByteWriter,
  LagHistory,
  PlayerInput,
  defineGame,
  defineInput,
  defineStateSchema,
  fnv1a64,
  type GameDefinition,
  type GameSetup,
  type Simulation,
} from 'fixedstep';

/** "GALY". */
const MAGIC = 0x594c4147;
/** Lanes, one target each. */
export const GALLERY_LANES = 4;
/** A lane's length, units. */
export const GALLERY_WIDTH = 100;
/** A shot hits when it lands within this of the target's centre, units. */
export const GALLERY_HIT_RADIUS = 2;
/** The furthest back a shot is judged: 30 ticks (500 ms). */
export const GALLERY_MAX_REWIND = 30;
const STEP = 1 / 60;
const SPEEDS = [24, -31, 38, -45];

/** The gallery's input: fire, the lane, where along it, and how far back the shooter's screen was. */
export const GALLERY_INPUT = defineInput({
  buttons: ['fire'],
  axes: {
    lane: { min: 0, max: GALLERY_LANES - 1, bits: 2 },
    aim: { min: 0, max: GALLERY_WIDTH, bits: 14 },
    rewind: { min: 0, max: 31.9375, bits: 9 },
  },
});

/** One shot as the server judged it (server memory, not state). */
export interface GalleryShot {
  player: number;
  /** The tick whose input fired it. */
  tick: number;
  /** The tick it was judged at (its tick minus the rewind, bounded; its tick without compensation). */
  judgedAt: number;
  hit: boolean;
}

/** The shooting gallery (1–4 players). */
export class Gallery implements Simulation<PlayerInput> {
  tick = 0;
  readonly x = new Float64Array(GALLERY_LANES);
  readonly vx = new Float64Array(GALLERY_LANES);
  readonly shots: Uint32Array;
  readonly hits: Uint32Array;
  /** Every shot judged since the game was made (a server's log; not state). */
  readonly log: GalleryShot[] = [];
  private readonly history = new LagHistory({
    entities: GALLERY_LANES,
    fields: 1,
    maxRewindTicks: GALLERY_MAX_REWIND,
  });
  private readonly sample = new Float64Array(1);
  private readonly writer = new ByteWriter(128);

  constructor(
    readonly players: number,
    /** Judge shots at the time the shooter saw (true), or at the server's present. */
    readonly compensate: boolean,
  ) {
    this.shots = new Uint32Array(players);
    this.hits = new Uint32Array(players);
    for (let i = 0; i < GALLERY_LANES; i++) {
      this.x[i] = ((i + 1) * GALLERY_WIDTH) / (GALLERY_LANES + 1);
      this.vx[i] = SPEEDS[i]!;
    }
    this.history.record(0, this.x);
  }

  step(inputs: readonly PlayerInput[]): void {
    const lane = GALLERY_INPUT.axis.lane;
    const aim = GALLERY_INPUT.axis.aim;
    const rewind = GALLERY_INPUT.axis.rewind;
    for (let p = 0; p < this.players; p++) {
      const input = inputs[p];
      if (!input?.wasPressed(0)) continue;
      const l = input.axis(lane);
      const at = this.compensate
        ? this.history.judgedAt(this.tick - input.axis(rewind))
        : this.tick;
      const x = this.compensate ? this.history.sample(at, l, this.sample)[0]! : this.x[l]!;
      const hit = Math.abs(x - input.axis(aim)) <= GALLERY_HIT_RADIUS;
      this.shots[p]!++;
      if (hit) this.hits[p]!++;
      this.log.push({ player: p, tick: this.tick, judgedAt: at, hit });
    }
    for (let i = 0; i < GALLERY_LANES; i++) {
      let x = this.x[i]! + this.vx[i]! * STEP;
      if (x < 0 || x > GALLERY_WIDTH) {
        this.vx[i] = -this.vx[i]!;
        x = x < 0 ? -x : 2 * GALLERY_WIDTH - x;
      }
      this.x[i] = x;
    }
    this.tick++;
    this.history.record(this.tick, this.x);
  }

  save(): Uint8Array {
    const w = this.writer.reset();
    w.u32(MAGIC).u32(this.tick).u8(this.players);
    w.f64s(this.x).f64s(this.vx).ints(this.shots).ints(this.hits);
    return w.finish();
  }

  /** Restore a state (the lag history, server memory, is kept). */
  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    if (r.u32() !== MAGIC) throw new RangeError('not a gallery state');
    const tick = r.u32();
    const players = r.u8();
    if (players !== this.players)
      throw new RangeError(`a state of ${players} players, not ${this.players}`);
    const x = new Float64Array(GALLERY_LANES);
    const vx = new Float64Array(GALLERY_LANES);
    const shots = new Uint32Array(players);
    const hits = new Uint32Array(players);
    r.f64s(x);
    r.f64s(vx);
    r.ints(shots);
    r.ints(hits);
    r.end();
    for (const v of [...x, ...vx])
      if (!Number.isFinite(v)) throw new RangeError('a number is not finite');
    this.tick = tick;
    this.x.set(x);
    this.vx.set(vx);
    this.shots.set(shots);
    this.hits.set(hits);
  }

  hash(): bigint {
    return fnv1a64(this.save());
  }
}

/** The gallery's schema: positions to 1/256 unit, speeds exact (they only flip). */
export const GALLERY_SCHEMA = defineStateSchema({
  columns: [
    { name: 'magic', type: 'u32', group: 'head' },
    { name: 'tick', type: 'u32', group: 'head' },
    { name: 'players', type: 'u8', group: 'head' },
    {
      name: 'x',
      type: 'f64',
      count: GALLERY_LANES,
      group: 'targets',
      precision: 1 / 256,
      min: -1,
      max: GALLERY_WIDTH + 1,
    },
    { name: 'vx', type: 'f64', count: GALLERY_LANES, group: 'targets' },
    { name: 'shots', type: 'u32', count: { of: 'players', max: 4 }, group: 'scores' },
    { name: 'hits', type: 'u32', count: { of: 'players', max: 4 }, group: 'scores' },
  ],
});

/** The gallery as a game; `compensate` judges shots at the time their shooter saw. */
export function galleryGame(compensate: boolean): Readonly<GameDefinition<PlayerInput, Gallery>> {
  return defineGame<PlayerInput, Gallery>({
    id: compensate ? 'gallery' : 'gallery-uncompensated',
    version: 1,
    tickRate: 60,
    input: GALLERY_INPUT,
    minPlayers: 1,
    maxPlayers: 4,
    create: (setup: GameSetup) => new Gallery(setup.players, compensate),
    stateSchema: GALLERY_SCHEMA,
  });
}
