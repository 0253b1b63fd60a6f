/**
 * Tick-for-tick comparison of every engine's traces with Node's, and of every display-rate or
 * replay scene with the scene it must equal. A difference is diagnosed: the states of both sides
 * at the first differing tick are fetched and the first differing field is named.
 */
import {
  diffStates,
  firstDifferentTick,
  hexToBytes,
  traceHashAt,
  traceLength,
  type TraceScene,
} from '@fixedstep/games';
import { runScenes, stateHex, type EngineRun, type SceneResult } from './run.js';
import type { EngineId } from './engines/session.js';

/** A trace that differs from the one it must equal. */
export interface Mismatch {
  engine: EngineId;
  scene: string;
  /** `node` (the same scene's trace in Node) or the id of the scene it must equal (same engine). */
  against: string;
  /** First differing tick, 1-based (the state after that many steps); 0 if the scene threw. */
  tick: number;
  /** The two hashes at that tick: the reference's, then this engine's. */
  expected?: string;
  actual?: string;
  /** The first differing field and both values (or why it could not be named). */
  detail: string;
}

/** An informational scene's comparison (e.g. `Math.sin`): how many ticks differ from Node. */
export interface InformationalResult {
  scene: string;
  ticks: number;
  differingTicks: number;
  firstTick: number;
  detail: string;
}

/** How one engine compared. */
export interface EngineComparison {
  engine: EngineId;
  /** Required scenes compared (traces present on both sides). */
  scenes: number;
  /** Ticks compared over the required scenes (against Node, or against the reference scene for Node). */
  ticks: number;
  mismatches: Mismatch[];
  informational: InformationalResult[];
}

/** Fetches the hex state of a scene after a tick in one engine. */
export type StateFetcher = (scene: string, tick: number) => Promise<string>;

/** Most mismatches diagnosed (state fetched and decoded) per engine; the rest are listed. */
const MAX_DIAGNOSED = 12;

function byId(run: EngineRun): Map<string, SceneResult> {
  return new Map(run.scenes.map((s) => [s.id, s]));
}

async function describe(
  scene: TraceScene,
  referenceState: () => Promise<string>,
  actualState: () => Promise<string>,
): Promise<string> {
  try {
    const a = hexToBytes(await referenceState());
    const b = hexToBytes(await actualState());
    return diffStates(a, b, scene.fields?.(a)).summary;
  } catch (e) {
    return `(could not fetch the states to compare: ${e instanceof Error ? e.message : String(e)})`;
  }
}

function countDifferingTicks(a: string, b: string): number {
  const n = Math.max(traceLength(a), traceLength(b));
  let count = 0;
  for (let t = 1; t <= n; t++) if (traceHashAt(a, t) !== traceHashAt(b, t)) count++;
  return count;
}

/**
 * Compares `run` (engine `engine`) with Node's `reference` run: every required scene tick for tick,
 * and every scene with `sameAs` against that scene in the same engine. For Node itself pass the
 * same run as both; only the `sameAs` relations are then checked.
 */
export async function compareEngine(options: {
  engine: EngineId;
  scenes: readonly TraceScene[];
  run: EngineRun;
  reference: EngineRun;
  state: StateFetcher;
  referenceState: StateFetcher;
}): Promise<EngineComparison> {
  const { engine, scenes, state, referenceState } = options;
  const mine = byId(options.run);
  const ref = byId(options.reference);
  const isNode = options.run === options.reference;
  const out: EngineComparison = { engine, scenes: 0, ticks: 0, mismatches: [], informational: [] };
  let diagnosed = 0;
  const diagnose = async (
    scene: TraceScene,
    a: () => Promise<string>,
    b: () => Promise<string>,
  ): Promise<string> => {
    if (diagnosed >= MAX_DIAGNOSED) return '(not diagnosed: too many mismatches)';
    diagnosed++;
    return describe(scene, a, b);
  };

  for (const scene of scenes) {
    const r = mine.get(scene.id);
    const n = ref.get(scene.id);
    if (!r || !n) {
      out.mismatches.push({
        engine,
        scene: scene.id,
        against: 'node',
        tick: 0,
        detail: `missing from ${!r ? engine : 'node'}'s run`,
      });
      continue;
    }
    if (r.error !== undefined || n.error !== undefined) {
      if (scene.informational) {
        if (!isNode) {
          out.informational.push({
            scene: scene.id,
            ticks: 0,
            differingTicks: 0,
            firstTick: 0,
            detail: `threw: ${r.error ?? n.error ?? ''}`,
          });
        }
        continue;
      }
      out.mismatches.push({
        engine,
        scene: scene.id,
        against: r.error !== undefined ? engine : 'node',
        tick: 0,
        detail: `threw: ${r.error ?? n.error ?? ''}`,
      });
      continue;
    }
    if (scene.informational) {
      if (isNode) continue;
      const first = firstDifferentTick(n.trace, r.trace);
      out.informational.push({
        scene: scene.id,
        ticks: traceLength(r.trace),
        differingTicks: first === 0 ? 0 : countDifferingTicks(n.trace, r.trace),
        firstTick: first,
        detail:
          first === 0
            ? 'identical to Node'
            : await describe(
                scene,
                () => referenceState(scene.id, first),
                () => state(scene.id, first),
              ),
      });
      continue;
    }
    out.scenes++;
    if (!isNode) {
      out.ticks += Math.min(traceLength(r.trace), traceLength(n.trace));
      const first = firstDifferentTick(n.trace, r.trace);
      if (first !== 0) {
        out.mismatches.push({
          engine,
          scene: scene.id,
          against: 'node',
          tick: first,
          expected: traceHashAt(n.trace, first),
          actual: traceHashAt(r.trace, first),
          detail: await diagnose(
            scene,
            () => referenceState(scene.id, first),
            () => state(scene.id, first),
          ),
        });
      }
    }
    if (scene.sameAs !== undefined) {
      const base = mine.get(scene.sameAs);
      if (base?.error !== undefined || !base) continue; // reported on its own line
      if (isNode) out.ticks += Math.min(traceLength(r.trace), traceLength(base.trace));
      const first = firstDifferentTick(base.trace, r.trace);
      if (first !== 0) {
        const sameAs = scene.sameAs;
        out.mismatches.push({
          engine,
          scene: scene.id,
          against: sameAs,
          tick: first,
          expected: traceHashAt(base.trace, first),
          actual: traceHashAt(r.trace, first),
          detail: await diagnose(
            scene,
            () => state(sameAs, first),
            () => state(scene.id, first),
          ),
        });
      }
    }
  }
  return out;
}

/**
 * {@link compareEngine} of two sets of scenes run here in Node: `scenes` as if engine `engine` had
 * run them, against `reference` as Node's — how the suite's tests stand in for an engine that
 * differs.
 */
export function compareInNode(
  engine: EngineId,
  reference: readonly TraceScene[],
  scenes: readonly TraceScene[],
): Promise<EngineComparison> {
  return compareEngine({
    engine,
    scenes: reference,
    run: runScenes(scenes),
    reference: runScenes(reference),
    state: (id, tick) => Promise.resolve(stateHex(scenes, id, tick)),
    referenceState: (id, tick) => Promise.resolve(stateHex(reference, id, tick)),
  });
}

/** One line per mismatch, for test failures and the report. */
export function formatMismatch(m: Mismatch): string {
  if (m.tick === 0) return `${m.engine} · ${m.scene}: ${m.detail}`;
  const vs = m.against === 'node' ? 'Node' : `${m.against} (same engine)`;
  return (
    `${m.engine} · ${m.scene}: differs from ${vs} first at tick ${String(m.tick)} ` +
    `(hash ${m.actual ?? '?'} vs ${m.expected ?? '?'}) — ${m.detail}`
  );
}
