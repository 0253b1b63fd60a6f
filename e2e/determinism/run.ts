/**
 * Runs the scenes and packs the traces — the one function every engine calls (the browser page
 * wraps it; Node calls it directly), so every engine's answer has the same shape.
 */
import { springKernelsAvailable, worldKernelsAvailable } from 'fixedstep';
import { bytesToHex, sceneStateAt, traceScene, type TraceScene } from '@fixedstep/games';

/** One scene's result in one engine. */
export interface SceneResult {
  id: string;
  ticks: number;
  /** The trace: 16 hex digits per tick (see `traceScene`); empty if the scene threw. */
  trace: string;
  /** What the scene threw, if it did. */
  error?: string;
  /** Wall time, ms. */
  ms: number;
}

/** Every scene's result in one engine. */
export interface EngineRun {
  scenes: SceneResult[];
  /** Wall time of the whole run, ms. */
  ms: number;
  /** Whether this engine ran SpringModel's WebAssembly kernel (else the JavaScript one). */
  wasm: boolean;
  /** Whether it ran PhysicsWorld's WebAssembly kernels (the big piles), else its JavaScript loops. */
  worldWasm: boolean;
}

function now(): number {
  return typeof performance !== 'undefined' ? performance.now() : Date.now();
}

function errorText(e: unknown): string {
  return e instanceof Error ? `${e.name}: ${e.message}` : String(e);
}

/** Traces one scene, catching what it throws. */
export function runScene(scene: TraceScene): SceneResult {
  const start = now();
  try {
    const trace = traceScene(scene);
    return { id: scene.id, ticks: scene.ticks, trace, ms: now() - start };
  } catch (e) {
    return { id: scene.id, ticks: scene.ticks, trace: '', error: errorText(e), ms: now() - start };
  }
}

function select(scenes: readonly TraceScene[], ids?: readonly string[]): TraceScene[] {
  if (!ids) return [...scenes];
  return ids.map((id) => {
    const s = scenes.find((x) => x.id === id);
    if (!s) throw new Error(`no scene ${id}`);
    return s;
  });
}

/** Traces `ids` (default: every scene), in order. */
export function runScenes(scenes: readonly TraceScene[], ids?: readonly string[]): EngineRun {
  const start = now();
  const results = select(scenes, ids).map(runScene);
  return {
    scenes: results,
    ms: now() - start,
    wasm: springKernelsAvailable(),
    worldWasm: worldKernelsAvailable(),
  };
}

/** The same, yielding to the event loop between scenes (Node, while browsers are driven). */
export async function runScenesYielding(
  scenes: readonly TraceScene[],
  ids?: readonly string[],
): Promise<EngineRun> {
  const start = now();
  const results: SceneResult[] = [];
  for (const scene of select(scenes, ids)) {
    await new Promise<void>((resolve) => setTimeout(resolve, 0));
    results.push(runScene(scene));
  }
  return {
    scenes: results,
    ms: now() - start,
    wasm: springKernelsAvailable(),
    worldWasm: worldKernelsAvailable(),
  };
}

/** The state bytes of scene `id` after tick `tick`, as hex. */
export function stateHex(scenes: readonly TraceScene[], id: string, tick: number): string {
  const [scene] = select(scenes, [id]);
  return bytesToHex(sceneStateAt(scene!, tick));
}

/** What the browser page exposes on `window.fixedstepDeterminism`. */
export interface DeterminismPageApi {
  readonly ready: true;
  /** The scene ids, in order. */
  ids(): string[];
  /** JSON of an {@link EngineRun}. */
  run(ids?: string[]): string;
  /** Hex of a state (see {@link stateHex}). */
  state(id: string, tick: number): string;
}
