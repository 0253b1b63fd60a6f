/**
 * Chapter 10, rigid bodies — the model, without the DOM. Rapier's deterministic build under
 * fixedstep (`@fixedstep/rapier`), on the lab's virtual clock:
 *
 * - {@link KnockOver}: the adapter's `towerScene()` — a tower of rotating boxes and a ball that
 *   FIRE launches at it — stepped by a `FixedLoop` from an `InputSampler` (the page's button, key
 *   and taps land on ticks exactly like the library's input pipeline puts them), drawn through an
 *   `InterpolationBuffer` of positions and angles, recorded with `ReplayRecorder.forGame`, and the
 *   hash of every tick kept.
 * - {@link ReplayRun}: that recording played back by re-simulation (`ReplayPlayer`), every
 *   tick's hash compared with the live run's.
 * - {@link TowerNet}: two machines playing {@link duelScene} (the same tower, a ball on each side)
 *   through the real relay core with `RollbackSession`s, over `SimulatedLink`s with latency,
 *   jitter and loss: each fires from its side, rollbacks happen, the confirmed hashes agree.
 * - {@link WorldsSideBySide}: the same scene in fixedstep's own `PhysicsWorld` (axis-aligned
 *   boxes that never rotate) next to Rapier's.
 *
 * Everything runs on one {@link DisplayClock} (a simulated 60 Hz display, or the page's real
 * frames), so two labs driven the same way are identical. Rapier's WebAssembly must be loaded
 * first: build it with {@link openRigidLab}.
 */
import {
  ByteReader,
  ByteWriter,
  FixedLoop,
  InputSampler,
  InterpolationBuffer,
  PhysicsWorld,
  Random,
  Relay,
  ReplayPlayer,
  ReplayRecorder,
  RollbackSession,
  SimulatedLink,
  dcos,
  dsin,
  gameSetup,
  hex64,
  packButtons,
  readReplay,
  gameCatalog,
  setupFromReplayHeader,
  setupFromWelcome,
  wasPressed,
  type ButtonInput,
  type LinkConditions,
  type Replay,
  type ReplayMismatch,
  type Simulation,
  type WelcomeMessage,
} from 'fixedstep';
import {
  RapierSimulation,
  TowerButtons,
  buildTower,
  checkButtons,
  loadRapier,
  rapierGame,
  towerScene,
  type RapierModule,
  type RapierSceneDef,
  type Tower,
  type World,
} from '@fixedstep/rapier';
import { DisplayClock, OnDisplayClock, type DisplaySpec } from '../../shell/display-clock.js';
import { SimulatedMachines, agreementOf, type Agreement } from '../../shell/simulated-machines.js';

/** Ticks per second of every simulation on this page. */
export const TICK_RATE = 60;
/** The FIRE button (bit 0 of a `ButtonInput`, as the adapter's tower defines it). */
export const FIRE = TowerButtons.FIRE;
/** A tick on which FIRE went down. */
const FIRE_PRESS = packButtons(1 << FIRE, 1 << FIRE);
/** The simulated display everything is drawn on unless the real clock is chosen. */
export const DISPLAY: DisplaySpec = { hz: 60, jitter: 0 };
/**
 * The loops start their clocks half a tick before the moment they are created, so the 60 Hz
 * display's frames fall in the middle of ticks (one tick a frame), as a real display's frames fall
 * anywhere; frames exactly on tick boundaries would take 0 or 2 ticks by the last bit of their times.
 */
export const LOOP_PHASE_MS = 1000 / TICK_RATE / 2;
/** A box counts as turned over past this angle, radians (10°). */
export const TURNED_RAD = (10 / 180) * Math.PI;
/** Hashes are compared over the network at ticks this far apart (1 s). */
export const CHECKPOINT_TICKS = 60;
/** The seed written into replays and rooms (Rapier's scenes draw no random numbers). */
const SEED = 1;

// ------------------------------------------------------------------------------------ bodies

/** One body as drawn: a box (half extents) or a ball (radius), and whose it is. */
export interface BodyShape {
  readonly kind: 'box' | 'ball';
  /** Half width and half height of a box; the radius (twice) of a ball. Metres. */
  readonly halfWidth: number;
  readonly halfHeight: number;
  /** The player whose ball it is (0, 1), or -1 for a box. */
  readonly owner: number;
}

/** Where a world is drawn: `[minX, minY, maxX, maxY]`, metres. */
export type Bounds = readonly [number, number, number, number];

/**
 * The last two ticks' poses (x, y, angle) of a fixed list of bodies, blended by the loop's alpha
 * for drawing — positions and angles (the shorter way round). Render-side only: it reads the
 * world after each tick and never writes it.
 */
export class BodyTrack {
  private readonly buffer: InterpolationBuffer;

  constructor(readonly shapes: readonly BodyShape[]) {
    this.buffer = new InterpolationBuffer({
      fields: 3,
      capacity: shapes.length,
      angleFields: [2],
    });
  }

  /** A tick ran: store every body's pose (`pose(i)` gives body i's x, y and angle). */
  record(pose: (i: number) => readonly [number, number, number]): void {
    const b = this.buffer;
    b.beginTick();
    for (let i = 0; i < this.shapes.length; i++) {
      const [x, y, a] = pose(i);
      b.store(i, x, y, a);
    }
  }

  /**
   * Every body's pose `alpha` of the way from the previous tick to the current one: body i's x,
   * y and angle at `3i`, `3i + 1`, `3i + 2`.
   */
  poses(alpha: number): Float64Array {
    return this.buffer.interpolate(alpha);
  }
}

/** The shape of a Rapier body's first collider (a ball or a cuboid; anything else as its AABB). */
function rapierShape(world: World, rapier: RapierModule, handle: number, owner: number): BodyShape {
  const c = world.getRigidBody(handle).collider(0);
  if (c.shapeType() === rapier.ShapeType.Ball) {
    const r = c.radius();
    return { kind: 'ball', halfWidth: r, halfHeight: r, owner };
  }
  const e = c.halfExtents();
  if (e === null) throw new Error(`rigid bodies: body ${handle} is neither a ball nor a box`);
  return { kind: 'box', halfWidth: e.x, halfHeight: e.y, owner };
}

/** The pose of Rapier body `handle`. */
function rapierPose(world: World, handle: number): [number, number, number] {
  const b = world.getRigidBody(handle);
  const t = b.translation();
  return [t.x, t.y, b.rotation()];
}

/** A track of `handles` in `world`, with the poses of the world as it is now. */
function rapierTrack(
  world: World,
  rapier: RapierModule,
  handles: readonly number[],
  owners: readonly number[],
): BodyTrack {
  const track = new BodyTrack(handles.map((h, i) => rapierShape(world, rapier, h, owners[i]!)));
  track.record((i) => rapierPose(world, handles[i]!));
  return track;
}

/** An angle wrapped into (−π, π]. */
function wrapAngle(a: number): number {
  let x = a % (2 * Math.PI);
  if (x > Math.PI) x -= 2 * Math.PI;
  else if (x <= -Math.PI) x += 2 * Math.PI;
  return x;
}

/** What the tower's boxes look like now: how many turned over, and how high the highest point is. */
export interface TowerShape {
  /** Boxes in the tower. */
  boxes: number;
  /** Boxes turned more than {@link TURNED_RAD} from where they started. */
  turned: number;
  /** The largest turn of any box from its start, degrees (0–180). */
  maxTurnDeg: number;
  /** The highest point of any box above the ground, m. */
  top: number;
}

/**
 * The shape of a tower from its boxes' poses. Deterministic in every engine: the corners come
 * from fixedstep's `dsin`/`dcos`, not `Math`'s.
 */
export function towerShape(
  shapes: readonly BodyShape[],
  pose: (i: number) => readonly [number, number, number],
): TowerShape {
  let boxes = 0;
  let turned = 0;
  let maxTurn = 0;
  let top = 0;
  for (let i = 0; i < shapes.length; i++) {
    const s = shapes[i]!;
    if (s.kind !== 'box') continue;
    boxes++;
    const [, y, angle] = pose(i);
    const turn = Math.abs(wrapAngle(angle));
    if (turn > TURNED_RAD) turned++;
    if (turn > maxTurn) maxTurn = turn;
    const high = y + Math.abs(s.halfWidth * dsin(angle)) + Math.abs(s.halfHeight * dcos(angle));
    if (high > top) top = high;
  }
  return { boxes, turned, maxTurnDeg: (maxTurn * 180) / Math.PI, top };
}

// ------------------------------------------------------------------------------------ scenes

/** A static box drawn as scenery: centre and half extents, m. */
export interface StaticBox {
  readonly x: number;
  readonly y: number;
  readonly halfWidth: number;
  readonly halfHeight: number;
}

/** `towerScene()`'s ground (a 60 m slab whose top is y = 0), and where its tower is drawn. */
export const TOWER_STATICS: readonly StaticBox[] = [
  { x: 0, y: -0.5, halfWidth: 30, halfHeight: 0.5 },
];
export const TOWER_BOUNDS: Bounds = [-5, -0.6, 11, 5];

/** The duel's floor and its two end walls; where it is drawn. */
export const DUEL_STATICS: readonly StaticBox[] = [
  { x: 0, y: -0.5, halfWidth: 8.5, halfHeight: 0.5 },
  { x: -8.25, y: 2.5, halfWidth: 0.25, halfHeight: 2 },
  { x: 8.25, y: 2.5, halfWidth: 0.25, halfHeight: 2 },
];
export const DUEL_BOUNDS: Bounds = [-8.6, -0.6, 8.6, 4.6];

/** The leaning tower's ground; where it is drawn. */
export const LEANING_STATICS: readonly StaticBox[] = [
  { x: 0, y: -0.5, halfWidth: 20, halfHeight: 0.5 },
];
export const LEANING_BOUNDS: Bounds = [-3, -0.6, 9.5, 6.2];

/** The tower as a game definition: `towerScene()` of the adapter, one player. */
export const TOWER_GAME = rapierGame<Tower>({
  id: 'rapier-tower',
  minPlayers: 1,
  maxPlayers: 1,
  scene: () => towerScene(),
});

/** What {@link duelScene}'s build returns. */
export interface Duel {
  /** The boxes' body handles, bottom row first. */
  readonly boxes: readonly number[];
  /** Each player's ball (player 0 on the left, player 1 on the right). */
  readonly balls: readonly [number, number];
  /** Where each ball waits and is launched from, m. */
  readonly homes: readonly [{ x: number; y: number }, { x: number; y: number }];
  /** Shots each player fired (user state: saved and hashed). */
  readonly shots: [number, number];
}

/** Launch speed of a duel ball, m/s (the tower scene's). */
const DUEL_SPEED = 14;

/**
 * The network demo's scene: the tower of `towerScene()` (8 rows of two 0.5 m boxes) in the middle
 * of a floor walled at both ends, and one ball per player — player 0's on the left, player 1's on
 * the right. A press of FIRE puts that player's ball back on its spot and launches it at the
 * tower: each machine fires from its side. Everything it does is a function of the inputs and the
 * tick, through Rapier's API; the shots are user state.
 */
export function duelScene(): RapierSceneDef<number, Duel> {
  return {
    id: 'rapier-tower-duel',
    players: 2,
    tickRate: TICK_RATE,
    build(world, rapier): Duel {
      for (const w of DUEL_STATICS) {
        world.createCollider(
          rapier.ColliderDesc.cuboid(w.halfWidth, w.halfHeight)
            .setTranslation(w.x, w.y)
            .setFriction(0.8),
        );
      }
      // Two columns of eight, centred on x = 0.
      const side = 0.5;
      const boxes = buildTower(world, rapier, {
        x0: -0.5 * side * 1.02,
        rows: 8,
        columns: 2,
        side,
      });
      const radius = 0.3;
      const homes: Duel['homes'] = [
        { x: -6, y: radius },
        { x: 6, y: radius },
      ];
      const balls = homes.map((home) => {
        const ball = world.createRigidBody(
          rapier.RigidBodyDesc.dynamic().setTranslation(home.x, home.y).setCcdEnabled(true),
        );
        world.createCollider(
          rapier.ColliderDesc.ball(radius).setDensity(4).setFriction(0.4).setRestitution(0.2),
          ball,
        );
        return ball.handle;
      });
      return { boxes, balls: [balls[0]!, balls[1]!], homes, shots: [0, 0] };
    },
    applyInputs(world, inputs, _tick, duel) {
      for (const p of [0, 1] as const) {
        if (!wasPressed(inputs[p]!, FIRE)) continue;
        const ball = world.getRigidBody(duel.balls[p]);
        ball.setTranslation(duel.homes[p], true);
        ball.setRotation(0, true);
        ball.setLinvel({ x: 0, y: 0 }, true);
        ball.setAngvel(0, true);
        // Impulse = mass × Δv: from rest the ball leaves at DUEL_SPEED towards the tower, 15 % up.
        const m = ball.mass();
        const toward = p === 0 ? 1 : -1;
        ball.applyImpulse({ x: toward * m * DUEL_SPEED, y: m * DUEL_SPEED * 0.15 }, true);
        duel.shots[p]++;
      }
    },
    checkInput: checkButtons,
    saveState: (duel) => new ByteWriter(8).u32(duel.shots[0]).u32(duel.shots[1]).finish(),
    loadState(duel, bytes) {
      const r = new ByteReader(bytes);
      const a = r.u32();
      const b = r.u32();
      r.end();
      duel.shots[0] = a;
      duel.shots[1] = b;
    },
  };
}

/** The duel as a game definition, for the relay, the sessions and their rooms. */
export const DUEL_GAME = rapierGame<Duel>({
  id: 'rapier-tower-duel',
  minPlayers: 2,
  maxPlayers: 2,
  scene: () => duelScene(),
});

/** What {@link leaningScene}'s build returns. */
export interface Leaning {
  readonly boxes: readonly number[];
}

/** Boxes of the leaning tower, each 1 m × 0.5 m and 0.5 m to the right of the one below. */
export const LEANING_BOXES = 11;

/**
 * docs/physics-world.md's leaning tower in Rapier: 11 boxes of 1 m × 0.5 m, each 0.5 m to the
 * right of the one below, on the ground — the centre of mass 2 m past the base's edge. No inputs.
 */
export function leaningScene(): RapierSceneDef<number, Leaning> {
  return {
    id: 'rapier-leaning-tower',
    tickRate: TICK_RATE,
    build(world, rapier): Leaning {
      for (const w of LEANING_STATICS) {
        world.createCollider(
          rapier.ColliderDesc.cuboid(w.halfWidth, w.halfHeight).setTranslation(w.x, w.y),
        );
      }
      const boxes: number[] = [];
      for (let k = 0; k < LEANING_BOXES; k++) {
        const body = world.createRigidBody(
          rapier.RigidBodyDesc.dynamic().setTranslation(0.5 * k, 0.25 + 0.5 * k),
        );
        world.createCollider(
          rapier.ColliderDesc.cuboid(0.5, 0.25).setDensity(1).setFriction(0.6),
          body,
        );
        boxes.push(body.handle);
      }
      return { boxes };
    },
    checkInput: checkButtons,
  };
}

// ------------------------------------------------------------------------------- the live run

/** What the live run shows. */
export interface KnockReadouts extends TowerShape {
  tick: number;
  shots: number;
  /** The state hash at this tick (16 hex digits). */
  hash: string;
  /** Bytes of the recording so far (inputs and a hash every second: no state). */
  replayBytes: number;
}

/**
 * The knock-over, live: `towerScene()` stepped by a `FixedLoop` from the display's frames, its
 * input sampled per tick from an `InputSampler` (presses pushed with their time on this run's
 * time line), recorded as it goes, every tick's hash kept for the replay to be compared with.
 */
export class KnockOver {
  readonly sim: RapierSimulation<number, Tower>;
  readonly loop = new FixedLoop({ step: TOWER_GAME.tickRate });
  readonly sampler = new InputSampler<ButtonInput>(TOWER_GAME.input);
  readonly recorder: ReplayRecorder;
  readonly track: BodyTrack;
  /** The balls first, then the boxes. */
  readonly handles: readonly number[];
  private hashes = new BigUint64Array(1024);
  private readonly inputs: ButtonInput[] = [0];

  constructor(rapier: RapierModule, startMs = 0) {
    this.sim = TOWER_GAME.create(gameSetup(TOWER_GAME, 1, SEED));
    this.recorder = ReplayRecorder.forGame(TOWER_GAME, { seed: SEED }, ['you'], {
      checkpointEvery: CHECKPOINT_TICKS,
    });
    this.recorder.start(this.sim);
    this.hashes[0] = this.sim.hash();
    const s = this.sim.scene;
    this.handles = [s.ball, ...s.boxes];
    this.track = rapierTrack(
      this.sim.world,
      rapier,
      this.handles,
      this.handles.map((_, i) => (i === 0 ? 0 : -1)),
    );
    this.loop.frame(startMs - LOOP_PHASE_MS);
  }

  get tick(): number {
    return this.sim.tick;
  }

  /** FIRE went down (or up) at `timeMs` on the lab's time line: it lands on the tick that spans it. */
  press(timeMs: number, down: boolean): void {
    this.sampler.push(timeMs, FIRE, down);
  }

  /** The hash after `tick` (0: the start), or undefined for a tick not reached yet. */
  hashAt(tick: number): bigint | undefined {
    return Number.isInteger(tick) && tick >= 0 && tick <= this.sim.tick
      ? this.hashes[tick]
      : undefined;
  }

  /** One display frame at `t` ms: the ticks it owes, each with its sampled input. */
  frame(t: number): void {
    const n = this.loop.frame(t);
    for (let j = 0; j < n; j++) {
      this.inputs[0] = this.sampler.sample(this.loop, j);
      this.sim.step(this.inputs);
      this.recorder.record(this.inputs, this.sim);
      const w = this.sim.world;
      this.track.record((i) => rapierPose(w, this.handles[i]!));
      this.keepHash(this.sim.tick, this.sim.hash());
    }
  }

  private keepHash(tick: number, h: bigint): void {
    if (tick >= this.hashes.length) {
      const grown = new BigUint64Array(this.hashes.length * 2);
      grown.set(this.hashes);
      this.hashes = grown;
    }
    this.hashes[tick] = h;
  }

  /** The recording so far: a replay file (inputs and checkpoint hashes). */
  replayFile(): Uint8Array {
    return this.recorder.finish();
  }

  readouts(): KnockReadouts {
    const w = this.sim.world;
    return {
      ...towerShape(this.track.shapes, (i) => rapierPose(w, this.handles[i]!)),
      tick: this.sim.tick,
      shots: this.sim.scene.shots,
      hash: hex64(this.hashes[this.sim.tick]!),
      replayBytes: this.recorder.finish().length,
    };
  }

  dispose(): void {
    this.sim.dispose();
  }
}

// ------------------------------------------------------------------------------------ replay

/** What the replay shows. */
export interface ReplayReadouts {
  /** The replay's tick now, and its last. */
  tick: number;
  ticks: number;
  /** Whether it played to its end. */
  ended: boolean;
  /** The replay's hash at its tick, and the live run's hash at that same tick. */
  hash: string;
  liveHash: string;
  /** Ticks whose hash was compared with the live run's (tick 0 included), and how many differed. */
  compared: number;
  different: number;
  /** The first tick whose hashes differed, or -1. */
  firstDifferent: number;
  /** Checkpoint hashes stored in the file that the re-simulation passed, and any it did not reproduce. */
  checkpoints: number;
  mismatches: number;
  /** The file: bytes, and bytes per second of play. */
  bytes: number;
  bytesPerSecond: number;
  shots: number;
}

/**
 * The live run's recording played back by re-simulation: a `ReplayPlayer` builds the tower from
 * the file's header with the game definition and steps it with the recorded inputs, on the same
 * display as the live run. After every tick its hash is compared with the hash the live run had at
 * that tick; the player also checks the file's own checkpoint hashes.
 */
export class ReplayRun {
  readonly bytes: Uint8Array;
  readonly replay: Replay;
  readonly player: ReplayPlayer;
  readonly track: BodyTrack;
  private readonly sims: RapierSimulation<number, Tower>[] = [];
  private current: RapierSimulation<number, Tower> | undefined;
  private readonly handles: readonly number[];
  private compared = 0;
  private different = 0;
  private firstDifferent = -1;
  private readonly mismatches: ReplayMismatch[] = [];

  constructor(
    bytes: Uint8Array,
    private readonly live: KnockOver,
    rapier: RapierModule,
    startMs: number,
  ) {
    this.bytes = bytes;
    this.replay = readReplay(bytes);
    this.player = new ReplayPlayer(
      this.replay,
      (header) => {
        // The header's game, version, tick rate, input schema and players, checked.
        const sim = TOWER_GAME.create(setupFromReplayHeader(TOWER_GAME, header));
        this.sims.push(sim);
        this.current = sim;
        return sim;
      },
      {
        onTick: (tick) => {
          this.afterTick(tick);
        },
        onMismatch: (m) => this.mismatches.push(m),
      },
    );
    const sim = this.sim;
    this.handles = [sim.scene.ball, ...sim.scene.boxes];
    this.track = rapierTrack(
      sim.world,
      rapier,
      this.handles,
      this.handles.map((_, i) => (i === 0 ? 0 : -1)),
    );
    this.compare(0, sim.hash());
    this.player.play();
    this.player.frame(startMs - LOOP_PHASE_MS);
  }

  /** The simulation being played (the one the player built; it only steps and loads it). */
  get sim(): RapierSimulation<number, Tower> {
    if (this.current === undefined) throw new Error('ReplayRun: the player built no simulation');
    return this.current;
  }

  /** How far between its last two ticks to draw: the player's loop alpha while it plays. */
  get alpha(): number {
    return this.player.isPlaying ? this.player.loop.alpha : 1;
  }

  frame(t: number): void {
    this.player.frame(t);
  }

  private afterTick(tick: number): void {
    const sim = this.sim;
    const w = sim.world;
    this.track.record((i) => rapierPose(w, this.handles[i]!));
    this.compare(tick, sim.hash());
  }

  private compare(tick: number, h: bigint): void {
    this.compared++;
    if (this.live.hashAt(tick) !== h) {
      this.different++;
      if (this.firstDifferent < 0) this.firstDifferent = tick;
    }
  }

  readouts(): ReplayReadouts {
    const sim = this.sim;
    const tick = this.player.tick;
    const live = this.live.hashAt(tick);
    const ticks = this.replay.tickCount;
    return {
      tick,
      ticks,
      ended: this.player.ended,
      hash: hex64(sim.hash()),
      liveHash: live === undefined ? '' : hex64(live),
      compared: this.compared,
      different: this.different,
      firstDifferent: this.firstDifferent,
      checkpoints: Math.floor(tick / this.replay.checkpointEvery) + 1,
      mismatches: this.mismatches.length,
      bytes: this.bytes.length,
      bytesPerSecond: ticks > 0 ? (this.bytes.length * TICK_RATE) / ticks : 0,
      shots: sim.scene.shots,
    };
  }

  dispose(): void {
    for (const s of this.sims) s.dispose();
  }
}

// ------------------------------------------------------------------------------------ network

/**
 * A duel simulation that also keeps the poses of its last two ticks for drawing. The network
 * sessions step, save, load and hash it like the Rapier simulation it wraps (a rollback loads a
 * state and steps again: the poses follow); the poses are never part of the state.
 */
export class DrawnDuel implements Simulation {
  readonly track: BodyTrack;
  readonly handles: readonly number[];

  constructor(
    readonly sim: RapierSimulation<number, Duel>,
    rapier: RapierModule,
  ) {
    const s = sim.scene;
    this.handles = [...s.balls, ...s.boxes];
    this.track = rapierTrack(sim.world, rapier, this.handles, [0, 1, ...s.boxes.map(() => -1)]);
  }

  get tick(): number {
    return this.sim.tick;
  }

  step(inputs: readonly ButtonInput[]): void {
    this.sim.step(inputs);
    const w = this.sim.world;
    this.track.record((i) => rapierPose(w, this.handles[i]!));
  }

  save(): Uint8Array {
    return this.sim.save();
  }

  load(bytes: Uint8Array): void {
    this.sim.load(bytes);
  }

  hash(): bigint {
    return this.sim.hash();
  }
}

/** Latency, jitter and loss of both machines' links (both directions). */
export type LinkSettings = LinkConditions;

export const DEFAULT_LINK: Readonly<LinkSettings> = { latencyMs: 80, jitterMs: 20, loss: 0.02 };

/**
 * The bots' script: player 0 fires at 1 s, 5 s, 9 s …, player 1 at 3 s, 7 s, 11 s … (a press on
 * one tick), so the machines take turns every 2 s.
 */
export function botFires(tick: number, player: number): boolean {
  return tick % 240 === 60 + 120 * player;
}

/** The relay's room of the duel. */
const NET_ROOM = 'rigid-bodies';

/** One machine of the duel as the page shows it. */
export interface MachineReadouts {
  /** Its slot in the room (0: the left ball), or -1 before the welcome. */
  slot: number;
  tick: number;
  rollbacks: number;
  /** The deepest rollback, ticks, and all the ticks re-simulated by rollbacks. */
  maxDepth: number;
  resimulated: number;
  rttMs: number;
  /** Shots fired by player 0 and player 1, as this machine's simulation counts them now. */
  shots: [number, number];
}

/** What the network section shows: the machines, and whether they agree (the relay's desyncs). */
export interface NetReadouts extends Agreement {
  /** The machine of player 0 (left ball), then of player 1 (right ball). */
  machines: [MachineReadouts, MachineReadouts];
}

/**
 * Two machines playing the duel through the relay core with rollback sessions, each on its own
 * {@link SimulatedLink} (seeded latency, jitter and loss), on one virtual clock. The relay gives
 * each machine its slot (its player: 0 fires the left ball, 1 the right one); each player fires
 * from an `InputSampler` of its slot (the page's buttons) and, with {@link bots}, on the bots'
 * script. A remote press is predicted as "not pressed", so it arrives as a rollback.
 */
export class TowerNet extends SimulatedMachines {
  readonly relay: Relay;
  /** The machines, in the order they connected (their slots are in their welcomes). */
  readonly sessions: [RollbackSession, RollbackSession];
  readonly links: [SimulatedLink, SimulatedLink];
  /** Each player's input, by slot: the machine with that slot samples it. */
  readonly samplers: [InputSampler, InputSampler] = [
    new InputSampler<ButtonInput>(DUEL_GAME.input),
    new InputSampler<ButtonInput>(DUEL_GAME.input),
  ];
  /** The bots fire on their script ({@link botFires}). */
  bots = true;
  private readonly drawn: (DrawnDuel | undefined)[] = [undefined, undefined];

  constructor(rapier: RapierModule, link: LinkSettings) {
    super();
    const clock = this.scheduler.clock;
    const random = new Random(SEED ^ 0x9e3779b9);
    this.relay = new Relay({
      clock,
      randomU32: () => random.nextU32(),
      catalog: gameCatalog([DUEL_GAME]),
    });
    const tickMs = 1000 / DUEL_GAME.tickRate;
    this.scheduler.every(
      tickMs / 2,
      () => {
        this.relay.update(clock.now());
      },
      tickMs / 2,
    );
    // Every event pushed up to now belongs to the tick being issued now.
    const now = { isBeforeUpdateEnd: (t: number) => t <= this.scheduler.now };
    const make = (i: 0 | 1): [RollbackSession, SimulatedLink] => {
      const simulated = new SimulatedLink({ scheduler: this.scheduler, seed: 7919 + i, ...link });
      this.relay.accept(simulated.b);
      const session: RollbackSession = new RollbackSession({
        transport: simulated.a,
        clock,
        room: NET_ROOM,
        game: DUEL_GAME,
        players: 2,
        seed: SEED,
        name: `machine${i + 1}`,
        createSimulation: (w: WelcomeMessage) => {
          const d = new DrawnDuel(DUEL_GAME.create(setupFromWelcome(w)), rapier);
          this.drawn[i]?.sim.dispose(); // a second welcome replaces the simulation
          this.drawn[i] = d;
          return d;
        },
        localInput: (tick: number) => {
          const slot = session.welcome?.slot ?? i;
          const input = this.samplers[slot === 1 ? 1 : 0].sample(now, 0);
          return this.bots && botFires(tick, slot) ? (input | FIRE_PRESS) >>> 0 : input;
        },
      });
      // Display frames at 60 Hz, the two machines out of phase (unless real frames drive them).
      this.display(i * 7.3, () => {
        session.frame(this.scheduler.now);
      });
      return [session, simulated];
    };
    const [s0, l0] = make(0);
    const [s1, l1] = make(1);
    this.sessions = [s0, s1];
    this.links = [l0, l1];
  }

  protected drawAll(): void {
    for (const s of this.sessions) s.frame(this.scheduler.now);
  }

  /** Player `slot` pressed (or let go of) FIRE at virtual `timeMs`. */
  press(slot: 0 | 1, timeMs: number, down: boolean): void {
    this.samplers[slot].push(timeMs, FIRE, down);
  }

  /** The session of the machine that plays `slot` (the connection order until the welcomes). */
  sessionOf(slot: 0 | 1): RollbackSession {
    return this.sessions.find((s) => s.welcome?.slot === slot) ?? this.sessions[slot];
  }

  /** The simulation of the machine that plays `slot`, with its poses (undefined before its welcome). */
  machine(slot: 0 | 1): DrawnDuel | undefined {
    const s = this.sessionOf(slot);
    return s.simulation === undefined ? undefined : this.drawn[this.sessions.indexOf(s)];
  }

  /** How far between its last two ticks the machine of `slot` draws. */
  alpha(slot: 0 | 1): number {
    return this.sessionOf(slot).alpha;
  }

  /** Both machines, by slot; the checkpoint both have confirmed and their hashes there. */
  readouts(): NetReadouts {
    const a = this.sessionOf(0);
    const b = this.sessionOf(1);
    const desyncs = this.relay.room(NET_ROOM)?.desyncs.length ?? 0;
    const machine = (slot: 0 | 1): MachineReadouts => {
      const s = this.sessionOf(slot);
      const d = this.machine(slot);
      return {
        slot: s.welcome?.slot ?? -1,
        tick: s.tick,
        rollbacks: s.stats.rollbacks,
        maxDepth: s.stats.maxRollbackDepth,
        resimulated: s.stats.resimulatedTicks,
        rttMs: s.stats.rtt,
        shots: d ? [d.sim.scene.shots[0], d.sim.scene.shots[1]] : [0, 0],
      };
    };
    return {
      machines: [machine(0), machine(1)],
      ...agreementOf(a, b, CHECKPOINT_TICKS, desyncs, this.links),
    };
  }

  dispose(): void {
    for (const d of this.drawn) d?.sim.dispose();
  }
}

// ---------------------------------------------------------------------------- the two worlds

/** The scenes of the side-by-side. */
export type WorldsScene = 'knock' | 'lean';
export const WORLDS_SCENES: readonly WorldsScene[] = ['knock', 'lean'];
/** In the knock scene both worlds' balls are launched at this tick (0.5 s). */
export const WORLDS_FIRE_TICK = 30;

/** One world of the side-by-side, as the page shows it. */
export interface WorldReadouts extends TowerShape {
  tick: number;
  /** The bytes of a `save()` now, and per dynamic body. */
  snapshotBytes: number;
  bytesPerBody: number;
  /** Dynamic bodies (boxes and the ball). */
  bodies: number;
}

/** The tower of `towerScene()` built in fixedstep's own world: the same boxes, ground and ball. */
function ownTower(): { world: PhysicsWorld; ball: number; boxes: number[] } {
  const world = new PhysicsWorld({ friction: 0.6 });
  for (const w of TOWER_STATICS) world.addStaticBox(w.x, w.y, w.halfWidth, w.halfHeight);
  const side = 0.5;
  const half = side / 2;
  const boxes: number[] = [];
  for (let row = 0; row < 8; row++) {
    for (let col = 0; col < 2; col++) {
      boxes.push(
        world.createBox({
          x: 4 + col * side * 1.02,
          y: half + row * side * 1.001,
          halfWidth: half * 0.98,
          halfHeight: half * 0.98,
        }),
      );
    }
  }
  const ball = world.createCircle({ x: -4, y: 0.3, radius: 0.3, density: 4, bullet: true });
  return { world, ball, boxes };
}

/** docs/physics-world.md's leaning tower in fixedstep's own world. */
function ownLeaning(): { world: PhysicsWorld; boxes: number[] } {
  const world = new PhysicsWorld({ friction: 0.6 });
  for (const w of LEANING_STATICS) world.addStaticBox(w.x, w.y, w.halfWidth, w.halfHeight);
  const boxes: number[] = [];
  for (let k = 0; k < LEANING_BOXES; k++) {
    boxes.push(
      world.createBox({ x: 0.5 * k, y: 0.25 + 0.5 * k, halfWidth: 0.5, halfHeight: 0.25 }),
    );
  }
  return { world, boxes };
}

/**
 * The same scene in both worlds, stepped tick by tick on one `FixedLoop`: the tower knocked by
 * the ball (launched in both at {@link WORLDS_FIRE_TICK} with the same speed), or the leaning
 * tower. Rapier's boxes turn and fall; the own world's cannot turn — by design — so its tower
 * slides apart or stays up.
 */
export class WorldsSideBySide {
  readonly rapier: RapierSimulation<number, Tower> | RapierSimulation<number, Leaning>;
  readonly own: PhysicsWorld;
  readonly tracks: [rapier: BodyTrack, own: BodyTrack];
  readonly loop = new FixedLoop({ step: TICK_RATE });
  /** Where both are drawn, and the ground. */
  readonly bounds: Bounds;
  readonly statics: readonly StaticBox[];
  private readonly rapierHandles: readonly number[];
  private readonly ownIds: readonly number[];
  private readonly ownBall: number | undefined;
  private readonly inputs: ButtonInput[] = [0];
  private cached: { tick: number; rapier: number; own: number } | undefined;

  constructor(
    readonly scene: WorldsScene,
    rapier: RapierModule,
    startMs: number,
  ) {
    if (scene === 'knock') {
      const sim = TOWER_GAME.create(gameSetup(TOWER_GAME, 1, SEED));
      this.rapier = sim;
      this.rapierHandles = [sim.scene.ball, ...sim.scene.boxes];
      const own = ownTower();
      this.own = own.world;
      this.ownIds = [own.ball, ...own.boxes];
      this.ownBall = own.ball;
      this.bounds = TOWER_BOUNDS;
      this.statics = TOWER_STATICS;
    } else {
      const sim = new RapierSimulation(leaningScene());
      this.rapier = sim;
      this.rapierHandles = sim.scene.boxes;
      const own = ownLeaning();
      this.own = own.world;
      this.ownIds = own.boxes;
      this.ownBall = undefined;
      this.bounds = LEANING_BOUNDS;
      this.statics = LEANING_STATICS;
    }
    const owners = this.rapierHandles.map((_, i) => (scene === 'knock' && i === 0 ? 0 : -1));
    const w = this.rapier.world;
    const rapierTrack_ = rapierTrack(w, rapier, this.rapierHandles, owners);
    const own = this.own;
    const ownTrack = new BodyTrack(
      this.ownIds.map((id, i): BodyShape => {
        const ball = !own.isBox(id);
        return {
          kind: ball ? 'ball' : 'box',
          halfWidth: own.halfWidth[id]!,
          halfHeight: own.halfHeight[id]!,
          owner: owners[i]!,
        };
      }),
    );
    this.tracks = [rapierTrack_, ownTrack];
    this.recordOwn();
    this.loop.frame(startMs - LOOP_PHASE_MS);
  }

  get tick(): number {
    return this.rapier.tick;
  }

  private recordOwn(): void {
    const own = this.own;
    this.tracks[1].record((i) => {
      const id = this.ownIds[i]!;
      return [own.x[id]!, own.y[id]!, 0];
    });
  }

  /** One tick of both worlds. */
  private stepBoth(): void {
    const fire = this.scene === 'knock' && this.rapier.tick === WORLDS_FIRE_TICK;
    this.inputs[0] = fire ? FIRE_PRESS : 0;
    if (fire && this.ownBall !== undefined) {
      // The tower scene's launch: an impulse of mass × 14 m/s along +x, 15 % of it up.
      const m = 1 / this.own.invMass[this.ownBall]!;
      this.own.applyImpulse(this.ownBall, m * 14, m * 14 * 0.15);
    }
    (this.rapier as RapierSimulation<number, unknown>).step(this.inputs);
    this.own.step();
    const w = this.rapier.world;
    this.tracks[0].record((i) => rapierPose(w, this.rapierHandles[i]!));
    this.recordOwn();
  }

  frame(t: number): void {
    const n = this.loop.frame(t);
    for (let j = 0; j < n; j++) this.stepBoth();
  }

  /** Both worlds now: Rapier's first. */
  readouts(): [WorldReadouts, WorldReadouts] {
    const tick = this.rapier.tick;
    if (this.cached?.tick !== tick) {
      this.cached = { tick, rapier: this.rapier.save().length, own: this.own.save().length };
    }
    const w = this.rapier.world;
    const own = this.own;
    const rapierBodies = this.rapierHandles.length;
    const ownBodies = this.ownIds.length;
    return [
      {
        ...towerShape(this.tracks[0].shapes, (i) => rapierPose(w, this.rapierHandles[i]!)),
        tick,
        snapshotBytes: this.cached.rapier,
        bytesPerBody: this.cached.rapier / rapierBodies,
        bodies: rapierBodies,
      },
      {
        ...towerShape(this.tracks[1].shapes, (i) => {
          const id = this.ownIds[i]!;
          return [own.x[id]!, own.y[id]!, 0];
        }),
        tick: own.tick,
        snapshotBytes: this.cached.own,
        bytesPerBody: this.cached.own / ownBodies,
        bodies: ownBodies,
      },
    ];
  }

  dispose(): void {
    this.rapier.dispose();
  }
}

// ------------------------------------------------------------------------------ the chapter

/**
 * The whole chapter's model: the live knock-over, its replay (once asked for), the network duel
 * and the two worlds side by side, all fed by one display clock.
 */
export class RigidLab extends OnDisplayClock {
  knock: KnockOver;
  replay: ReplayRun | undefined;
  net: TowerNet;
  worlds: WorldsSideBySide;
  private link: LinkSettings;
  private worldsScene: WorldsScene = 'knock';
  private bots = true;
  protected clock: DisplayClock;
  private real = false;

  /** Needs Rapier loaded (`await loadRapier()`, or build it with {@link openRigidLab}). */
  constructor(
    private readonly rapier: RapierModule,
    link: Partial<LinkSettings> = {},
  ) {
    super();
    this.link = { ...DEFAULT_LINK, ...link };
    this.clock = this.newClock();
    this.knock = new KnockOver(rapier);
    this.net = this.newNet();
    this.worlds = new WorldsSideBySide(this.worldsScene, rapier, 0);
  }

  private newClock(): DisplayClock {
    return new DisplayClock(this.real ? 'real' : DISPLAY, (t) => {
      this.frame(t);
    });
  }

  private newNet(): TowerNet {
    const net = new TowerNet(this.rapier, this.link);
    net.bots = this.bots;
    net.realFrames = this.real;
    return net;
  }

  get linkSettings(): Readonly<LinkSettings> {
    return this.link;
  }

  get worldsSceneName(): WorldsScene {
    return this.worldsScene;
  }

  get botsOn(): boolean {
    return this.bots;
  }

  get realClock(): boolean {
    return this.real;
  }

  /** Switch between the simulated 60 Hz display and the page's real frames, going on from now. */
  setRealClock(on: boolean): void {
    this.real = on;
    this.clock.setDisplay(on ? 'real' : DISPLAY);
    this.net.realFrames = on;
  }

  private frame(t: number): void {
    this.knock.frame(t);
    this.replay?.frame(t);
    this.worlds.frame(t);
    if (this.real) this.net.realFrame(t);
    else this.net.advanceTo(t);
  }

  /** FIRE on the live tower went down or up at `timeMs` (the lab's time). */
  fire(timeMs: number, down: boolean): void {
    this.knock.press(timeMs, down);
  }

  /** Play the recording so far from its first tick (replacing a replay that plays). */
  startReplay(): ReplayRun {
    this.replay?.dispose();
    this.replay = new ReplayRun(this.knock.replayFile(), this.knock, this.rapier, this.timeMs);
    return this.replay;
  }

  /** Start the two worlds again (now), with `scene`. */
  setWorldsScene(scene: WorldsScene): void {
    this.worldsScene = scene;
    this.worlds.dispose();
    this.worlds = new WorldsSideBySide(scene, this.rapier, this.timeMs);
  }

  /** Change the network's links now (both machines, both directions). */
  setLink(c: Partial<LinkSettings>): void {
    this.link = { ...this.link, ...c };
    this.net.setLink(this.link);
  }

  /** Let the bots fire on their script, or not (from now on). */
  setBots(on: boolean): void {
    this.bots = on;
    this.net.bots = on;
  }

  /** Everything back to time zero with the current settings. */
  restart(): void {
    this.dispose();
    this.clock = this.newClock();
    this.knock = new KnockOver(this.rapier);
    this.replay = undefined;
    this.net = this.newNet();
    this.worlds = new WorldsSideBySide(this.worldsScene, this.rapier, 0);
  }

  /** Free every Rapier world (WebAssembly memory). */
  dispose(): void {
    this.knock.dispose();
    this.replay?.dispose();
    this.net.dispose();
    this.worlds.dispose();
  }
}

/** Loads Rapier's WebAssembly (once) and builds the chapter's model. */
export async function openRigidLab(link: Partial<LinkSettings> = {}): Promise<RigidLab> {
  const rapier = await loadRapier();
  return new RigidLab(rapier, link);
}
