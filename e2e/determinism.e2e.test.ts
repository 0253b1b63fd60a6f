/**
 * Proof of determinism across JavaScript engines and display rates (docs/determinism.md).
 *
 * The trace catalogue of `@fixedstep/games` (math helpers, the PRNG, the ball through LoopRig,
 * the physics world, a spring rope under six integrators, every registered game: bot match,
 * replay, timestamped inputs on five jittery, hitching displays) is computed by the same code in
 * Node, headless Chromium (V8), Firefox ESR (SpiderMonkey) and WebKitGTK (JavaScriptCore), and
 * compared hash by hash, tick by tick. A difference names the first tick, the engine, the scene and
 * the first differing field of the saved state. An engine that is not installed is skipped, and
 * the summary and `artifacts/determinism/report.{json,md}` say why; an engine that is installed
 * but cannot run fails its test.
 *
 * `FIXEDSTEP_ENGINES=node,chromium` limits the run to some engines.
 */
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { startServer, type RunningServer } from '@fixedstep/server';
import {
  GAMES,
  TRACE_DISPLAY_RATES,
  firstDifferentTick,
  rateLabel,
  traceScene,
  type TraceScene,
} from '@fixedstep/games';
import { buildPage } from './determinism/build.js';
import { compareEngine, formatMismatch, type EngineComparison } from './determinism/compare.js';
import { openChromium } from './determinism/engines/chromium.js';
import { openFirefox } from './determinism/engines/firefox.js';
import { ENGINE_NAMES, type EngineId, type EngineSession } from './determinism/engines/session.js';
import { openWebKit } from './determinism/engines/webkit.js';
import {
  catalogueSummary,
  consoleSummary,
  writeReport,
  type DeterminismReport,
  type EngineReport,
} from './determinism/report.js';
import { runScenesYielding, stateHex, type EngineRun } from './determinism/run.js';
import { determinismScenes } from './determinism/scenes.js';

const repo = fileURLToPath(new URL('..', import.meta.url));
const artifacts = path.join(repo, 'artifacts', 'determinism');

interface FoundEngine {
  ok: boolean;
  reason?: string;
  path?: string;
  driver?: string;
  browser?: string;
  xvfb?: string;
}
type Browsers = 'chromium' | 'firefox' | 'webkit';
const enginesModule = (await import(
  pathToFileURL(path.join(repo, 'scripts', 'engines.mjs')).href
)) as { findEngines(): Record<Browsers, FoundEngine> };
const found = enginesModule.findEngines();

const BROWSERS: readonly Browsers[] = ['chromium', 'firefox', 'webkit'];
const selected = process.env.FIXEDSTEP_ENGINES?.split(',').map((s) => s.trim());

/** Why an engine is skipped, or undefined if it runs. */
function skipReason(id: EngineId): string | undefined {
  if (selected && !selected.includes(id)) {
    return `not selected (FIXEDSTEP_ENGINES=${process.env.FIXEDSTEP_ENGINES ?? ''})`;
  }
  if (id === 'node') return undefined;
  const f = found[id];
  return f.ok
    ? undefined
    : `not installed: ${f.reason ?? 'unknown'} (run \`node scripts/engines.mjs --install\` as root)`;
}

function open(id: Browsers, url: string): Promise<EngineSession> {
  const f = found[id];
  if (id === 'chromium') return openChromium(f.path!, url);
  if (id === 'firefox') return openFirefox(f.path!, url);
  return openWebKit({ driver: f.driver!, browser: f.browser!, xvfb: f.xvfb! }, url);
}

function sceneTimes(run: EngineRun): Record<string, number> {
  return Object.fromEntries(run.scenes.map((s) => [s.id, Math.round(s.ms)]));
}

function errorText(e: unknown): string {
  return e instanceof Error ? e.message : String(e);
}

interface Outcome {
  report: EngineReport;
  comparison?: EngineComparison;
  /** Set when the engine is installed but could not be started or could not trace. */
  error?: string;
}

const outcomes = new Map<EngineId, Outcome>();
let scenes: TraceScene[] = [];
let nodeRun: EngineRun | undefined;
let server: RunningServer | undefined;
const sessions: EngineSession[] = [];

beforeAll(async () => {
  const t0 = performance.now();
  scenes = await determinismScenes();
  const dist = await buildPage();
  server = await startServer({ port: 0, host: '127.0.0.1', root: dist });
  const url = `http://127.0.0.1:${String(server.port)}/`;

  // The browsers start together (Node idle, so their start-up times are their own), then trace
  // in their own processes while Node traces here.
  const opened = new Map<Browsers, Promise<EngineSession>>();
  for (const id of BROWSERS) {
    if (skipReason(id) === undefined) opened.set(id, open(id, url));
  }
  await Promise.allSettled(opened.values());
  const browserWork = new Map<Browsers, Promise<{ session: EngineSession; run: EngineRun }>>();
  for (const [id, p] of opened) {
    browserWork.set(
      id,
      p.then(async (session) => {
        sessions.push(session);
        // No second chance: a scene that throws — a WebAssembly trap included — fails like any
        // other difference (docs/determinism.md, "A trap is a failure").
        return { session, run: await session.run() };
      }),
    );
  }
  for (const p of browserWork.values()) p.catch(() => undefined);
  await new Promise((resolve) => setTimeout(resolve, 20)); // let the run requests go out

  nodeRun = await runScenesYielding(scenes);
  const reference = nodeRun;
  const nodeState = (id: string, tick: number) => Promise.resolve(stateHex(scenes, id, tick));
  const nodeComparison = await compareEngine({
    engine: 'node',
    scenes,
    run: reference,
    reference,
    state: nodeState,
    referenceState: nodeState,
  });
  outcomes.set('node', {
    comparison: nodeComparison,
    report: {
      id: 'node',
      name: ENGINE_NAMES.node,
      status: nodeComparison.mismatches.length === 0 ? 'passed' : 'failed',
      version: `Node ${process.version}`,
      jsVersion: `V8 ${process.versions.v8}`,
      wasm: reference.wasm,
      worldWasm: reference.worldWasm,
      userAgent: `Node.js/${process.version} (${process.platform}; ${process.arch})`,
      startMs: 0, // Node is already running
      runMs: reference.ms,
      sceneMs: sceneTimes(reference),
      scenes: nodeComparison.scenes,
      ticks: nodeComparison.ticks,
      mismatches: nodeComparison.mismatches,
      informational: [],
    },
  });

  for (const id of BROWSERS) {
    const reason = skipReason(id);
    if (reason !== undefined) {
      outcomes.set(id, {
        report: {
          id,
          name: ENGINE_NAMES[id],
          status: 'skipped',
          reason,
          mismatches: [],
          informational: [],
        },
      });
      continue;
    }
    try {
      const { session, run } = await browserWork.get(id)!;
      const comparison = await compareEngine({
        engine: id,
        scenes,
        run,
        reference,
        state: (scene, tick) => session.state(scene, tick),
        referenceState: nodeState,
      });
      outcomes.set(id, {
        comparison,
        report: {
          id,
          name: ENGINE_NAMES[id],
          status: comparison.mismatches.length === 0 ? 'passed' : 'failed',
          version: session.version,
          jsVersion: session.jsVersion,
          wasm: run.wasm,
          worldWasm: run.worldWasm,
          userAgent: session.userAgent,
          startMs: session.startMs,
          runMs: run.ms,
          sceneMs: sceneTimes(run),
          scenes: comparison.scenes,
          ticks: comparison.ticks,
          mismatches: comparison.mismatches,
          informational: comparison.informational,
        },
      });
    } catch (e) {
      const error = errorText(e);
      outcomes.set(id, {
        error,
        report: {
          id,
          name: ENGINE_NAMES[id],
          status: 'failed',
          reason: error,
          mismatches: [],
          informational: [],
        },
      });
    }
  }
  await Promise.allSettled(sessions.map((s) => s.close()));
  sessions.length = 0;

  const notes: string[] = [];
  for (const s of scenes) {
    if (!s.id.endsWith('/sampled')) continue;
    const bot = reference.scenes.find((x) => x.id === s.id.replace(/\/sampled$/, '/bot'));
    const sampled = reference.scenes.find((x) => x.id === s.id);
    if (!bot || !sampled || bot.error !== undefined || sampled.error !== undefined) continue;
    const d = firstDifferentTick(bot.trace, sampled.trace);
    notes.push(
      d === 0
        ? `\`${s.id}\`: the bot’s inputs sent as timestamped presses give the bot match’s own trace.`
        : `\`${s.id}\`: the bot’s inputs as timestamped presses differ from the bot match from tick ${String(d)} ` +
            '(a bot input that no key can produce: a button down without a press after a tick up).',
    );
  }
  const report: DeterminismReport = {
    generatedAt: new Date().toISOString(),
    totalMs: performance.now() - t0,
    host: `${os.type()} ${os.release()} ${os.arch()}, ${String(os.cpus().length)} CPUs`,
    catalogue: catalogueSummary(scenes),
    engines: (['node', ...BROWSERS] as const).map((id) => outcomes.get(id)!.report),
    notes,
  };
  const files = writeReport(artifacts, report);
  // Quiet when every engine agrees (or was skipped, which its test reports): the summary and the
  // first mismatches are printed only when an engine failed. The full report is always written.
  if (report.engines.some((e) => e.status === 'failed')) console.log(consoleSummary(report, files));
}, 170_000);

afterAll(async () => {
  await Promise.allSettled(sessions.map((s) => s.close()));
  await server?.close();
});

function assertSame(id: EngineId): void {
  const o = outcomes.get(id);
  if (!o) throw new Error(`${id} did not run (see the set-up error above)`);
  if (o.error !== undefined) {
    throw new Error(`${ENGINE_NAMES[id]} is installed but could not run the traces: ${o.error}`);
  }
  const c = o.comparison!;
  expect(c.scenes, 'required scenes compared').toBe(scenes.filter((s) => !s.informational).length);
  expect(c.mismatches.map(formatMismatch), `${ENGINE_NAMES[id]}: mismatches`).toEqual([]);
  // The piles (circlesInBox(250)) ran PhysicsWorld's WebAssembly kernels, not only its JavaScript
  // loops: both modules compile and instantiate here (Chromium refuses more than 4 KB at once).
  expect(o.report.worldWasm, `${ENGINE_NAMES[id]}: PhysicsWorld's WebAssembly kernels`).toBe(true);
}

describe('determinism across engines and display rates', () => {
  it('the catalogue covers every kind of scene, and every game at every display rate', () => {
    const ids = scenes.map((s) => s.id);
    for (const prefix of ['math/', 'random/', 'ball/', 'physics/', 'springs/', 'lab/', 'rapier/']) {
      expect(ids.find((id) => id.startsWith(prefix))).toBeDefined();
    }
    expect(ids.filter((id) => /^springs\/rope-[a-z0-9-]+$/.test(id))).toHaveLength(6);
    expect(ids.filter((id) => /^springs\/cloth-[a-z0-9-]+$/.test(id))).toHaveLength(6);
    for (const hz of TRACE_DISPLAY_RATES) expect(ids).toContain(`ball/loop-rig@${rateLabel(hz)}`);
    // Rapier: the tower (with its snapshot round trip and every display), the joints, a pile.
    for (const id of [
      'rapier/tower',
      'rapier/tower/reloaded',
      'rapier/joints',
      'rapier/circles-150',
    ])
      expect(ids).toContain(id);
    for (const hz of TRACE_DISPLAY_RATES) expect(ids).toContain(`rapier/tower@${rateLabel(hz)}`);
    // Every registered game (none yet is fine): bot match, replay, reload, and every display.
    for (const game of GAMES) {
      const id = game.info.id;
      for (const kind of ['bot', 'replay', 'reloaded', 'sampled'])
        expect(ids).toContain(`game/${id}/${kind}`);
      for (const hz of TRACE_DISPLAY_RATES) expect(ids).toContain(`game/${id}@${rateLabel(hz)}`);
    }
  });

  it('Node: every display-rate and replay scene equals its reference, tick for tick', () => {
    assertSame('node');
    // The cloth scenes ran SpringModel's WebAssembly kernel here (the browsers report theirs).
    expect(nodeRun?.wasm).toBe(true);
  });

  for (const id of BROWSERS) {
    it(`${ENGINE_NAMES[id]}: the same trace as Node at every tick of every scene`, (ctx) => {
      const reason = skipReason(id);
      if (reason !== undefined) {
        // An engine that is not installed is skipped, with its reason (also in the report).
        // eslint-disable-next-line vitest/no-disabled-tests
        ctx.skip(`${ENGINE_NAMES[id]} skipped: ${reason}`);
        return;
      }
      assertSame(id);
    });
  }

  it('a trace is a pure function of the scene: tracing twice gives the same hashes', () => {
    const scene = scenes.find((s) => s.id === 'ball/loop-rig@144hz')!;
    const first = nodeRun!.scenes.find((s) => s.id === scene.id)!.trace;
    expect(traceScene(scene)).toBe(first);
  });
});
