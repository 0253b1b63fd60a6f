/**
 * The in-process checks of `fixedstep check`, each on a fresh simulation of the user's game with
 * the seeded input script ({@link inputScript}):
 *
 * - **guard** — every step (and create, save, load, hash) under the determinism guard: a clock,
 *   `Math.random`, `crypto` or engine-dependent `Math` (sin, cos, atan2, exp, pow, hypot …)
 *   called during a step is named, with the tick;
 * - **twins** — two simulations created alike and stepped alike must agree at every tick: catches
 *   a step that reads anything outside its own state (random, clock, module-level variables);
 * - **sync test** — GGPO's sync test (`SyncTestSession`): every tick save, step, load, step again
 *   and compare — catches state `save()` forgets and iteration over something whose order
 *   depends on history;
 * - **round trip** — save A, load into a fresh B, then step both with the same inputs: equal
 *   states at every tick, and `save()` after `load(save())` byte-equal.
 *
 * Each reports the first tick whose state differs and, with the game's `stateSchema`, the column
 * and row (the field) of the first differing byte.
 * @module
 */
import {
  DeterminismError,
  FORBIDDEN_FUNCTIONS,
  SyncTestSession,
  diffSnapshots,
  guardSimulation,
  hex64,
  readStateValue,
  withDeterminismGuard,
  type AnyGameDefinition,
  type Simulation,
  type StateColumnType,
} from 'fixedstep';
import { createForPlan, inputScript, type CheckPlan } from './script.js';

/** The checks, in the order they run and are reported. */
export type CheckId = 'guard' | 'twins' | 'sync-test' | 'round-trip';

/** One check's verdict. */
export interface CheckResult {
  readonly check: string;
  /** pass; fail (not deterministic); error (the game threw); skipped (an engine not installed). */
  readonly status: 'pass' | 'fail' | 'error' | 'skipped';
  /** One line: what was found, or what was checked. */
  readonly summary: string;
  /** The first tick whose state differs (the state after that many steps), when one does. */
  readonly tick?: number;
  /** Where: the field (with a state schema), or the byte offset. */
  readonly field?: string;
  /** For a trapped call: e.g. `Math.sin`. */
  readonly call?: string;
  /** More lines: values, the likely cause, what to do. */
  readonly details: readonly string[];
}

/** Where two states first differ, in words: the field with a schema, else the byte. */
export interface StateDifference {
  /** `pos.x[3]` with a schema, else `byte 120`. */
  readonly field: string;
  /** Lines for the report: the values on each side. */
  readonly details: string[];
}

/** How many other differing fields a report lists. */
const MAX_FIELDS_LISTED = 8;

function viewOf(bytes: Uint8Array): DataView {
  return new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
}

function sizeOf(type: string): number {
  return type === 'f64' ? 8 : type.endsWith('32') ? 4 : type.endsWith('16') ? 2 : 1;
}

/** A number with every bit shown: floats as their shortest round-trip text and the bits. */
function showNumber(bytes: Uint8Array, at: number, type: string): string {
  const size = sizeOf(type);
  if (at + size > bytes.length) return '(missing)';
  const v = readStateValue(viewOf(bytes), at, type as StateColumnType);
  if (type !== 'f32' && type !== 'f64') return String(v);
  let hex = '';
  for (let i = size - 1; i >= 0; i--) hex += bytes[at + i]!.toString(16).padStart(2, '0');
  return `${String(v)} (0x${hex})`;
}

/**
 * Names where `expected` and `actual` (two `save()` results of one game) first differ: the
 * column and row of the game's `stateSchema`, with both values, or the byte offset.
 */
export function describeDifference(
  game: AnyGameDefinition,
  expected: Uint8Array,
  actual: Uint8Array,
  labels: readonly [string, string] = ['expected', 'actual'],
): StateDifference {
  const diff = diffSnapshots(expected, actual);
  const at = diff.firstOffset;
  const sizes =
    expected.length === actual.length
      ? `${diff.differingBytes} of ${expected.length} bytes differ`
      : `the states have ${expected.length} and ${actual.length} bytes`;
  const schema = game.stateSchema;
  const locate = (offset: number) =>
    schema?.locate(expected, offset) ?? schema?.locate(actual, offset);
  const place = locate(at);
  if (place !== undefined) {
    const nameOf = (p: { column: string; row: number; count: number }) =>
      p.count === 1 && p.row === 0 ? p.column : `${p.column}[${p.row}]`;
    const name = nameOf(place);
    // The other fields that differ too (the first is often a consequence of the one that matters).
    const others: string[] = [];
    let more = false;
    for (const [from, to] of diff.ranges) {
      for (let offset = from; offset < to; offset++) {
        const p = locate(offset);
        if (p === undefined) continue;
        const n = nameOf(p);
        if (n !== name && !others.includes(n)) {
          if (others.length < MAX_FIELDS_LISTED) others.push(n);
          else more = true;
        }
        offset = Math.max(offset, p.offset + sizeOf(p.type) - 1); // on to the next number
      }
    }
    return {
      field: name,
      details: [
        `field ${name} (${place.type}, column "${place.column}" row ${place.row} of ${place.count}, byte ${place.offset}); ${sizes}`,
        `  ${labels[0]}: ${showNumber(expected, place.offset, place.type)}`,
        `  ${labels[1]}: ${showNumber(actual, place.offset, place.type)}`,
        ...(others.length > 0
          ? [`  also differ: ${others.join(', ')}${more || diff.truncated ? ' …' : ''}`]
          : []),
      ],
    };
  }
  const hexAt = (b: Uint8Array) =>
    at < b.length ? `0x${b[at]!.toString(16).padStart(2, '0')}` : '(past the end)';
  return {
    field: `byte ${at}`,
    details: [
      `byte ${at} of the save() bytes; ${sizes}`,
      `  ${labels[0]}: ${hexAt(expected)}`,
      `  ${labels[1]}: ${hexAt(actual)}`,
      game.stateSchema === undefined
        ? '  (give the game a stateSchema made with defineStateSchema and the field is named)'
        : "  (the state schema does not describe these bytes: check it against the game's save())",
    ],
  };
}

function errorText(e: unknown): string {
  return e instanceof Error ? `${e.name}: ${e.message}` : String(e);
}

function threw(check: string, what: string, tick: number | undefined, e: unknown): CheckResult {
  return {
    check,
    status: 'error',
    summary: `the game threw ${what}${tick === undefined ? '' : ` at tick ${tick}`}: ${errorText(e)}`,
    ...(tick !== undefined ? { tick } : {}),
    details: e instanceof Error && e.stack ? e.stack.split('\n').slice(1, 4) : [],
  };
}

/** Progress: called with ticks done in this check. */
export type TickProgress = (ticks: number) => void;

/** Every step (and create, save, load, hash) under the determinism guard. */
export function guardCheck(
  game: AnyGameDefinition,
  plan: CheckPlan,
  progress?: TickProgress,
): CheckResult {
  const check = 'guard';
  const script = inputScript(game, plan);
  let tick: number | undefined;
  try {
    const sim = guardSimulation(withDeterminismGuard(() => createForPlan(game, plan)));
    for (tick = 0; tick < plan.ticks; tick++) {
      sim.step(script[tick]!);
      sim.hash();
      if (tick % 60 === 59) {
        // save and load are guarded too: a clock read while saving is as bad as one in a step.
        sim.load(sim.save());
      }
      progress?.(tick + 1);
    }
  } catch (e) {
    if (e instanceof DeterminismError) {
      const forbidden = FORBIDDEN_FUNCTIONS.find((f) => `${f.object}.${f.property}` === e.call);
      const what =
        forbidden?.kind === 'math'
          ? 'engine math: its last bit differs between JavaScript engines'
          : forbidden?.kind === 'clock'
            ? 'a clock: every run reads another time'
            : 'unseeded randomness: every run draws other numbers';
      return {
        check,
        status: 'fail',
        summary: `${e.call} called during ${tick === undefined ? 'create' : `the step of tick ${tick}`} — ${what}`,
        ...(tick !== undefined ? { tick } : {}),
        call: e.call,
        details: [`instead: ${forbidden?.advice ?? 'keep it out of the simulation'}`],
      };
    }
    return threw(check, tick === undefined ? 'in create' : 'in a step', tick, e);
  }
  return {
    check,
    status: 'pass',
    summary: `${plan.ticks} guarded ticks: no clock, Math.random, crypto or engine math called`,
    details: [],
  };
}

/** Two simulations created alike and stepped alike agree at every tick. */
export function twinsCheck(
  game: AnyGameDefinition,
  plan: CheckPlan,
  progress?: TickProgress,
): CheckResult {
  const check = 'twins';
  const script = inputScript(game, plan);
  let tick: number | undefined;
  let a: Simulation<unknown>;
  let b: Simulation<unknown>;
  try {
    a = createForPlan(game, plan);
    b = createForPlan(game, plan);
    for (tick = 0; tick <= plan.ticks; tick++) {
      const sa = a.save();
      const sb = b.save();
      if (!equalBytes(sa, sb)) {
        const d = describeDifference(game, sa, sb, ['first', 'second']);
        return {
          check,
          status: 'fail',
          summary: `two runs from the same setup with the same inputs differ after tick ${tick}, at ${d.field}`,
          tick,
          field: d.field,
          details: [
            ...d.details,
            'likely: the step reads something outside the state (Math.random, a clock, a module-level variable shared by both runs)',
          ],
        };
      }
      if (tick === plan.ticks) break;
      a.step(script[tick]!);
      b.step(script[tick]!);
      progress?.(tick + 1);
    }
  } catch (e) {
    return threw(check, tick === undefined ? 'in create' : 'in a step', tick, e);
  }
  return {
    check,
    status: 'pass',
    summary: `two runs agree at all ${plan.ticks} ticks`,
    details: [],
  };
}

/** GGPO's sync test: every tick save, step, load, step again and compare. */
export function syncTestCheck(
  game: AnyGameDefinition,
  plan: CheckPlan,
  progress?: TickProgress,
): CheckResult {
  const check = 'sync-test';
  const script = inputScript(game, plan);
  let tick: number | undefined;
  try {
    const session = new SyncTestSession(createForPlan(game, plan), { throwOnMismatch: false });
    for (tick = 0; tick < plan.ticks; tick++) {
      if (!session.step(script[tick]!)) break;
      progress?.(tick + 1);
    }
    const m = session.mismatch;
    if (m !== undefined) {
      const d = describeDifference(game, m.expectedState, m.actualState, [
        'first run',
        m.kind === 'load' ? 'after load' : 'rerun',
      ]);
      return {
        check,
        status: 'fail',
        summary:
          m.kind === 'load'
            ? `load() did not restore the state of tick ${m.tick}: save() after load differs at ${d.field}`
            : `resimulating tick ${m.tick - 1} from its loaded state gave another state at tick ${m.tick}, at ${d.field}`,
        tick: m.tick,
        field: d.field,
        details: [
          ...d.details,
          `hashes: ${hex64(m.expected)} first run, ${hex64(m.actual)} ${m.kind === 'load' ? 'after load' : 'rerun'}`,
          m.kind === 'load'
            ? 'likely: load() leaves a field as it was, or save() writes something load() does not read back'
            : 'likely: the step uses state that save() does not write (a field, a cache, the order of a Set or Map) — or reads something outside the state',
        ],
      };
    }
  } catch (e) {
    return threw(check, tick === undefined ? 'in create' : 'in a step, save or load', tick, e);
  }
  return {
    check,
    status: 'pass',
    summary: `${plan.ticks} ticks saved, loaded and resimulated: equal states`,
    details: [],
  };
}

/** Save A, load into a fresh B, step both alike: equal states every tick. */
export function roundTripCheck(
  game: AnyGameDefinition,
  plan: CheckPlan,
  progress?: TickProgress,
): CheckResult {
  const check = 'round-trip';
  const script = inputScript(game, plan);
  // Load part-way through, once the state holds more than the start does.
  const at = Math.max(1, Math.floor(plan.ticks / 3));
  let tick: number | undefined;
  try {
    const a = createForPlan(game, plan);
    for (tick = 0; tick < at && tick < plan.ticks; tick++) {
      a.step(script[tick]!);
      progress?.(tick + 1);
    }
    const saved = a.save();
    const b = createForPlan(game, plan);
    b.load(saved);
    const again = b.save();
    if (!equalBytes(saved, again)) {
      const d = describeDifference(game, saved, again, ['saved', 'after load']);
      return {
        check,
        status: 'fail',
        summary: `save() after load(save()) is not the same bytes (tick ${tick}), at ${d.field}`,
        tick,
        field: d.field,
        details: [...d.details, 'likely: load() does not read back everything save() writes'],
      };
    }
    if (b.tick !== a.tick) {
      return {
        check,
        status: 'fail',
        summary: `after load the tick is ${b.tick}, saved at ${a.tick}`,
        tick,
        details: ['load() must restore the tick too'],
      };
    }
    for (; tick < plan.ticks; tick++) {
      a.step(script[tick]!);
      b.step(script[tick]!);
      const sa = a.save();
      const sb = b.save();
      if (!equalBytes(sa, sb)) {
        const d = describeDifference(game, sa, sb, ['saved run', 'loaded copy']);
        return {
          check,
          status: 'fail',
          summary: `a copy loaded at tick ${at} differs from the original after tick ${tick + 1}, at ${d.field}`,
          tick: tick + 1,
          field: d.field,
          details: [
            ...d.details,
            'likely: the step uses state save() does not write (a field, a cache, a float kept at more precision than saved, the order of a Set or Map)',
          ],
        };
      }
      progress?.(tick + 1);
    }
  } catch (e) {
    return threw(check, 'in a step, save or load', tick, e);
  }
  return {
    check,
    status: 'pass',
    summary: `saved at tick ${at}, loaded into a fresh copy: equal bytes, and equal states for ${plan.ticks - at} more ticks`,
    details: [],
  };
}

function equalBytes(a: Uint8Array, b: Uint8Array): boolean {
  if (a.length !== b.length) return false;
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
  return true;
}
