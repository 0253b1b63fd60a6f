/**
 * What the determinism work found outside its own files, as regression tests (Node only, fast).
 *
 * Each finding was first written as an `it.fails` test (passing while the bug was there); once
 * fixed it became a plain `it` named "fixed: …" that guards the fix. The comment above each says
 * where the bug was and how it showed; docs/determinism.md lists them too.
 */
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { Linter } from 'eslint';
import { describe, expect, it } from 'vitest';
import {
  BallScene,
  LoopRig,
  ballTraceScript,
  diffStates,
  physicsWorldFields,
  traceDisplay,
} from '@fixedstep/games';
import { PhysicsWorld, bulletsScene, buildWorld, fnv1a64Hex, type PhysicsScene } from 'fixedstep';

const repo = fileURLToPath(new URL('../..', import.meta.url));

/** Per-tick hashes of the ball scene through LoopRig with a given hysteresis, on a display. */
function ballTrace(hz: number | undefined, hysteresis: number, ticks: number): string[] {
  const rig = new LoopRig({
    loop: { kind: 'fixed', fixed: { maxAccumulatorMs: 1000, hysteresis } },
    display: hz === undefined ? { hz: 60 } : { ...traceDisplay(hz), events: [] },
    script: ballTraceScript(Math.ceil(ticks / 60) + 2),
    trace: true,
  });
  while (rig.trace.length < ticks * 6) rig.frame();
  const out: string[] = [];
  for (let t = 0; t < ticks; t++) {
    const state = Float64Array.from(rig.trace.slice(t * 6, t * 6 + 6));
    out.push(fnv1a64Hex(new Uint8Array(state.buffer)));
  }
  return out;
}

/** A bullets world built with a chosen buffer capacity (what `buildWorld` does, but for that). */
function bulletsWorld(scene: PhysicsScene, capacity: number): PhysicsWorld {
  const world = new PhysicsWorld(scene.def, { capacity });
  for (const w of scene.walls) world.addStaticBox(w.x, w.y, w.halfWidth, w.halfHeight);
  for (const s of scene.segments) world.addSegment(s.ax, s.ay, s.bx, s.by);
  for (const { radius, halfWidth, halfHeight, ...b } of scene.bodies) {
    if (radius !== undefined) world.createCircle({ ...b, radius });
    else world.createBox({ ...b, halfWidth: halfWidth ?? 0, halfHeight: halfHeight ?? 0 });
  }
  return world;
}

/** The first tick at which two worlds' saved states differ (with the differing field), or ''. */
function firstWorldDifference(a: PhysicsWorld, b: PhysicsWorld, ticks: number): string {
  for (let t = 1; t <= ticks; t++) {
    a.step();
    b.step();
    const sa = a.save();
    const d = diffStates(sa, b.save(), physicsWorldFields(sa));
    if (!d.equal) return `tick ${String(t)}: ${d.summary}`;
  }
  return '';
}

describe('findings of the determinism suite', () => {
  it('FixedLoop without hysteresis: the ball’s inputs land in the same ticks at every display rate', () => {
    const steady = ballTrace(undefined, 0, 1200);
    for (const hz of [30, 144, 240])
      expect(ballTrace(hz, 0, 1200), `${String(hz)} Hz`).toEqual(steady);
  });

  // packages/fixedstep/src/time/fixed-loop.ts, FixedLoop.isBeforeUpdateEnd with `hysteresis` > 0:
  // a step may run up to h·step before its nominal end, and a press in that last stretch of the
  // step lands in it on one display (the step ran late) and in the next step on another (it ran
  // early). Measured: h = 0.25 changes the ball's trace at every rate (first at tick 215–595 of
  // 3600); h = 0.1 at 144 and 240 Hz. Ending each step's input window at (j + 1 − h)·step — the
  // earliest the step can run — makes all rates agree again (checked with h = 0.1, 0.25, 0.5).
  it('fixed: FixedLoop with hysteresis 0.25: the ball’s trace is the same at 30, 144 and 240 Hz', () => {
    const steady = ballTrace(undefined, 0.25, 1200);
    for (const hz of [30, 144, 240])
      expect(ballTrace(hz, 0.25, 1200), `${String(hz)} Hz`).toEqual(steady);
  });

  it('PhysicsWorld: a snapshot loaded into a world built the same way steps the same', () => {
    const scene = bulletsScene(3);
    const a = buildWorld(scene);
    for (let t = 0; t < 50; t++) a.step();
    const b = buildWorld(scene);
    b.load(a.save());
    expect(firstWorldDifference(a, b, 200)).toBe('');
  });

  // packages/fixedstep/src/physics/world/world.ts: grow() sets `maxCells = 4 * cap + 64` from the
  // buffer capacity (WorldOptions.capacity, or the doubling history), and the broad-phase grid
  // doubles its cell size while `cols * rows > maxCells`. Capacity is not state, so two worlds with
  // byte-identical states find their contacts in a different order and then move differently:
  // bulletsScene(3) built with capacity 60 vs 1024 differs at tick 19 (contact[0].a 8 vs 2) and its
  // bodies at tick 37 (body[25].x); loading a tick-50 snapshot into `new PhysicsWorld()` (capacity
  // 256) instead of a world built like the original (capacity 60) differs on the very next step.
  // Suggested fix: size the grid from the state (e.g. from the body count `n`), not from `cap`.
  it('fixed: PhysicsWorld steps the same whatever its buffer capacity', () => {
    const scene = bulletsScene(3);
    expect(firstWorldDifference(bulletsWorld(scene, 60), bulletsWorld(scene, 1024), 400)).toBe('');
  });

  it('fixed: PhysicsWorld: a snapshot loaded into a bare new PhysicsWorld() steps the same', () => {
    const a = buildWorld(bulletsScene(3));
    for (let t = 0; t < 50; t++) a.step();
    const b = new PhysicsWorld();
    b.load(a.save());
    expect(firstWorldDifference(a, b, 200)).toBe('');
  });

  // eslint.config.js, the simulation-path rule list `nonDeterministic`: it bans Math.sin … cbrt
  // and Math.pow, but not Math.asinh, Math.acosh, Math.atanh, nor the `**` operator (and `**=`),
  // which is Math.pow. The suite's informational probes show them differing between engines
  // (asinh, acosh, x ** y vs Node 20; see artifacts/determinism/report.md). The replay codec's one
  // use, `2 ** shift` with an integer shift, is exact everywhere (scene engine/integer-powers).
  const simRules = async (): Promise<Linter.RulesRecord> => {
    const mod = (await import(pathToFileURL(path.join(repo, 'eslint.config.js')).href)) as {
      default: Linter.Config[];
    };
    const rules: Linter.RulesRecord = {};
    for (const c of mod.default) {
      if (c.files?.some((f) => typeof f === 'string' && f.startsWith('packages/games/src'))) {
        for (const name of ['no-restricted-properties', 'no-restricted-syntax']) {
          const rule = c.rules?.[name];
          if (rule !== undefined) rules[name] = rule;
        }
      }
    }
    return rules;
  };
  const lint = (rules: Linter.RulesRecord, code: string) =>
    new Linter({ configType: 'flat' }).verify(code, [
      { languageOptions: { ecmaVersion: 2022, sourceType: 'module' }, rules },
    ]);

  it('lint: simulation code may not call Math.sin, Math.random or Date.now', async () => {
    const rules = await simRules();
    const messages = lint(rules, 'export const v = [Math.sin(1), Math.random(), Date.now()];');
    expect(messages.map((m) => m.ruleId)).toEqual([
      'no-restricted-properties',
      'no-restricted-properties',
      'no-restricted-properties',
    ]);
  });

  it('fixed: lint: simulation code may not call Math.asinh/acosh/atanh or use **', async () => {
    const rules = await simRules();
    const code =
      'let w = 3; w **= 0.5;\nexport const v = [Math.asinh(1), Math.acosh(2), Math.atanh(0.5), 2 ** 0.5, w];';
    expect(lint(rules, code)).toHaveLength(5);
  });

  // packages/games/src/scenes/ball.ts, BallScene.update: the "at rest on the floor" test
  // `if (vy < 0.05) vy = 0` runs after the bounce, where a ball lying on the floor has gained
  // g·dt·e = 9.81 / 60 × 0.8 ≈ 0.13 m/s in one step at 60 Hz (0.26 at 30 Hz) — always above 0.05.
  // So a ball never rests: it counts a bounce every other tick (300 in 10 s at 60 Hz) and the
  // rolling friction (`y <= r && vy === 0`) never applies. Deterministic, but not the physics
  // intended.
  it('fixed: BallScene: a ball lying on the floor stays at rest (no bounces in 10 s at 60 Hz)', () => {
    const ball = new BallScene();
    for (let t = 0; t < 600; t++) ball.update(1 / 60, 0);
    expect(ball.bounces).toBe(0);
  });
});
