/**
 * The input script of `fixedstep check` and a run of a game under it: the one code every engine
 * runs (Node imports it; the browser page bundles it with the user's module), so every engine
 * steps the same game with the same inputs. Browser-safe: it imports only `fixedstep`.
 * @module
 */
import { Random, gameSetup, hex64, packButtons, type AnyGameDefinition } from 'fixedstep';

/** What one check runs: which game, how long, with which seeded inputs. */
export interface CheckPlan {
  readonly gameId: string;
  /** Ticks to step. */
  readonly ticks: number;
  /** The seed of the game's setup and of the input script (u32). */
  readonly seed: number;
  /** Players in the run. */
  readonly players: number;
}

/** A button flips about once in this many ticks; an axis moves about once in this many. */
const BUTTON_FLIP_ODDS = 8;
const AXIS_MOVE_ODDS = 8;

/** Players a check runs: two when the game allows it (interactions), else its only count. */
export function checkPlayers(game: AnyGameDefinition): number {
  return Math.min(game.maxPlayers, Math.max(game.minPlayers, 2));
}

/**
 * The seeded random input script: `ticks` ticks of one input per player. Buttons are held for
 * a while and released (a press is flagged on the tick a button goes down); axes jump to a random
 * level now and then and stay. Every value is a valid input of the game's schema. Same plan, same
 * inputs, in every engine (integer arithmetic on a xoshiro128** stream only).
 */
export function inputScript(game: AnyGameDefinition, plan: CheckPlan): unknown[][] {
  const schema = game.input;
  const random = new Random((plan.seed ^ 0x5eed5c41) >>> 0);
  const buttons = Math.min(schema.buttons.length, 16);
  const down = new Array<number>(plan.players).fill(0);
  const words = Array.from({ length: plan.players }, () => new Uint32Array(schema.words));
  const script: unknown[][] = [];
  for (let t = 0; t < plan.ticks; t++) {
    const tick: unknown[] = [];
    for (let p = 0; p < plan.players; p++) {
      const before = down[p]!;
      let now = before;
      for (let b = 0; b < buttons; b++) {
        if (random.int(BUTTON_FLIP_ODDS) === 0) now ^= 1 << b;
      }
      down[p] = now;
      const w = words[p]!;
      w[0] = packButtons(now, now & ~before);
      for (let a = 0; a < schema.axes.length; a++) {
        if (random.int(AXIS_MOVE_ODDS) !== 0) continue;
        const axis = schema.axes[a]!;
        let step = random.int(2 ** axis.bits);
        // The one field of a centred axis that is no level: its centre instead.
        if (axis.kind === 'centred' && step === 1 << (axis.bits - 1)) step = 0;
        schema.writeAxis(w, 0, a, step);
      }
      tick.push(schema.decode(w, 0));
    }
    script.push(tick);
  }
  return script;
}

/** The game's simulation at tick 0 for the plan. */
export function createForPlan(game: AnyGameDefinition, plan: CheckPlan) {
  return game.create(gameSetup(game, plan.players, plan.seed));
}

/** What a run of the script gave in one engine. */
export interface TraceResult {
  /** The state hash after each tick, 16 hex digits a tick. */
  trace: string;
  /** What the game threw, and at which tick (the step from that tick), if it did. */
  error?: string;
  errorTick?: number;
}

function errorText(e: unknown): string {
  return e instanceof Error ? `${e.name}: ${e.message}` : String(e);
}

/** Runs the script and records the hash after every tick. */
export function traceGame(game: AnyGameDefinition, plan: CheckPlan): TraceResult {
  const script = inputScript(game, plan);
  let trace = '';
  let tick = 0;
  try {
    const sim = createForPlan(game, plan);
    for (; tick < plan.ticks; tick++) {
      sim.step(script[tick]!);
      trace += hex64(sim.hash());
    }
    return { trace };
  } catch (e) {
    return { trace, error: errorText(e), errorTick: tick };
  }
}

/** The state bytes after `tick` ticks of the script (0: the state `create` made). */
export function stateAt(game: AnyGameDefinition, plan: CheckPlan, tick: number): Uint8Array {
  const script = inputScript(game, { ...plan, ticks: tick });
  const sim = createForPlan(game, plan);
  for (let t = 0; t < tick; t++) sim.step(script[t]!);
  return sim.save();
}

/** Bytes as lowercase hex (for the page's answers). */
export function toHex(bytes: Uint8Array): string {
  let s = '';
  for (const b of bytes) s += b.toString(16).padStart(2, '0');
  return s;
}

/** Hex back to bytes. */
export function fromHex(hex: string): Uint8Array {
  const out = new Uint8Array(hex.length >> 1);
  for (let i = 0; i < out.length; i++) out[i] = parseInt(hex.slice(2 * i, 2 * i + 2), 16);
  return out;
}
