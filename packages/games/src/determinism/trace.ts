/**
 * Per-tick hash traces: the evidence that a simulation "always behaves the same".
 *
 * A {@link TraceScene} is anything that can be stepped one tick at a time and saved as canonical
 * bytes. Its trace is the FNV-1a 64 of the `save()` bytes after every tick, as 16 hex digits,
 * concatenated: `trace.slice(16·(t − 1), 16·t)` is the hash after tick t (t = 1 … ticks). The same
 * code computes it in Node and in every browser, so two traces are comparable tick for tick.
 */
import { fnv1a64Hex } from 'fixedstep';
import type { StateField } from './state-fields.js';

/** One run of a scene, stepped by the caller. */
export interface TraceRun {
  /** Step exactly one tick and return the canonical state bytes after it (a copy or a view valid until the next call). */
  next(): Uint8Array;
}

/** A scene the catalogue traces. */
export interface TraceScene {
  /** Stable id, `group/name` (e.g. `physics/circles-250`, `game/runner/bot`, `ball/loop-rig@144hz`). */
  readonly id: string;
  /** What it is, for reports. */
  readonly title: string;
  /** Ticks compared by default. */
  readonly ticks: number;
  /**
   * The scene whose trace this one must equal tick for tick (in the same engine and across
   * engines): a display-rate variant names its fixed-step scene, a replay its recorded match.
   */
  readonly sameAs?: string;
  /**
   * Not a promise, a measurement: the scene shows something that is *expected* to differ between
   * engines (e.g. `Math.sin`). Reported, never failed on.
   */
  readonly informational?: boolean;
  /** Start a fresh run from tick 0. */
  start(): TraceRun;
  /** Names the fields of a saved state of this scene, for mismatch reports. */
  fields?(state: Uint8Array): readonly StateField[] | undefined;
}

/** Hex digits per tick in a trace. */
export const TRACE_HASH_DIGITS = 16;

/** The trace of `scene` over `ticks` ticks (default: the scene's own count). */
export function traceScene(scene: TraceScene, ticks = scene.ticks): string {
  const run = scene.start();
  const parts: string[] = [];
  for (let t = 0; t < ticks; t++) parts.push(fnv1a64Hex(run.next()));
  return parts.join('');
}

/** The state bytes of `scene` after tick `tick` (1-based: after that many steps), as a copy. */
export function sceneStateAt(scene: TraceScene, tick: number): Uint8Array {
  if (!(Number.isInteger(tick) && tick >= 1)) {
    throw new RangeError(`sceneStateAt: tick must be an integer ≥ 1, got ${String(tick)}`);
  }
  const run = scene.start();
  let bytes: Uint8Array = new Uint8Array(0);
  for (let t = 0; t < tick; t++) bytes = run.next();
  return bytes.slice();
}

/** Number of ticks in a trace string. */
export function traceLength(trace: string): number {
  return Math.floor(trace.length / TRACE_HASH_DIGITS);
}

/** The hash after tick `tick` (1-based) of a trace, or undefined past its end. */
export function traceHashAt(trace: string, tick: number): string | undefined {
  if (tick < 1 || tick > traceLength(trace)) return undefined;
  return trace.slice((tick - 1) * TRACE_HASH_DIGITS, tick * TRACE_HASH_DIGITS);
}

/**
 * The first tick (1-based) at which two traces differ, comparing up to the shorter length; then,
 * if one is shorter, the tick after its end. 0 when they are identical.
 */
export function firstDifferentTick(expected: string, actual: string): number {
  const n = Math.min(expected.length, actual.length);
  if (expected.slice(0, n) !== actual.slice(0, n)) {
    // Bisect on hash boundaries: string comparison of halves is fast in every engine.
    let lo = 0;
    let hi = Math.ceil(n / TRACE_HASH_DIGITS);
    while (hi - lo > 1) {
      const mid = (lo + hi) >>> 1;
      const end = mid * TRACE_HASH_DIGITS;
      if (expected.slice(0, end) === actual.slice(0, end)) lo = mid;
      else hi = mid;
    }
    return hi;
  }
  if (expected.length === actual.length) return 0;
  return traceLength(expected.slice(0, n)) + 1;
}

/** Lower-case hex of bytes (for shipping states out of a browser). */
export function bytesToHex(bytes: Uint8Array): string {
  let s = '';
  for (let i = 0; i < bytes.length; i++) s += bytes[i]!.toString(16).padStart(2, '0');
  return s;
}

/** The bytes of {@link bytesToHex}'s output. */
export function hexToBytes(hex: string): Uint8Array {
  if (hex.length % 2 !== 0 || /[^0-9a-f]/i.test(hex)) {
    throw new RangeError('hexToBytes: not an even-length hex string');
  }
  const out = new Uint8Array(hex.length / 2);
  for (let i = 0; i < out.length; i++) out[i] = parseInt(hex.slice(2 * i, 2 * i + 2), 16);
  return out;
}
