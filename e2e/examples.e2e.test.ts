/**
 * The examples as a user runs them: `examples/coin-dash` and the Phaser 4, PixiJS 8 and three.js
 * recipes. Each is copied outside the repository (the recipes with the game they share,
 * examples/shared, beside them), given the packed `fixedstep` tarball and its own
 * dependencies (the engine, TypeScript, Vite) with `npm install`, type-checked by its own
 * tsconfig, built by its own Vite, served, and played in headless Chromium on a simulated display:
 * Playwright's clock fakes `performance.now()` and timers, and an init script turns
 * `requestAnimationFrame` into a display of a chosen rate. On two rates, each example must
 * - run its game at the game's tick rate (within 1 %),
 * - give every key press to exactly one tick: the one whose time span holds the press,
 * - draw with render interpolation: the drawn position is the blend of the last two ticks by the
 *   loop's alpha, and alpha varies;
 * and coin-dash must play a whole round and show "replay verified". Results (tick rates, presses,
 * timings) land in artifacts/examples/results.json. Needs the build (`npm run build`) for the
 * tarball; npm's cache serves the engines when it holds them, the registry otherwise.
 */
import { cp, mkdir, mkdtemp, readFile, rm, stat, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import type { Browser, Page } from 'playwright-core';
import { startServer } from '@fixedstep/server';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { launchChromium } from './harness.js';
import { packWorkspaces, repo, run, type Ran } from './pack-helpers.js';

/** How the test reaches into one example's page. */
interface Example {
  /** Folder under examples/. */
  name: string;
  /** Path and query to open. */
  url: string;
  /** The window property that holds `{ game, loop }` (what the example exposes for tests). */
  hook: string;
  /**
   * Where the steered body was drawn, in metres: `'arc'`, the last disc drawn on the 2D canvas
   * (coin-dash: 960 × 540 px for 16 × 9 m, the player drawn last), or `'hook'`, the hook's
   * `drawn()` (the recipes read their engine's sprite).
   */
  drawn: 'arc' | 'hook';
  /** Button index in the example's schema for each key the test presses. */
  keys: Readonly<Record<string, number>>;
  /** Play a whole round and expect "replay verified". */
  playsRound?: boolean;
}

// coin-dash: buttons left, right, up, down, dash; recipes: left, right, up, down, kick.
const KEYS = { ArrowLeft: 0, ArrowRight: 1, ArrowUp: 2, ArrowDown: 3, Space: 4 };

const EXAMPLES: readonly Example[] = [
  {
    name: 'coin-dash',
    url: '/?seed=42',
    hook: 'coinDash',
    drawn: 'arc',
    keys: KEYS,
    playsRound: true,
  },
  { name: 'phaser', url: '/', hook: 'recipe', drawn: 'hook', keys: KEYS },
  { name: 'pixi', url: '/', hook: 'recipe', drawn: 'hook', keys: KEYS },
  { name: 'three', url: '/', hook: 'recipe', drawn: 'hook', keys: KEYS },
];

/**
 * Display rates: 50 Hz runs one or two ticks a frame, 144 Hz zero or one; neither divides 60, so
 * alpha takes many values on both.
 */
const RATES = [50, 144] as const;
const TICK_RATE = 60;
const STEP_MS = 1000 / TICK_RATE;

/** Where each example was prepared, and how long each stage took (ms). */
interface Prepared {
  dir: string;
  timings: Record<string, number>;
}

/** What one example measured on one display, for the report. */
interface Measured {
  hz: number;
  ticksPerSecond: number;
  presses: number;
  pressesOnTheirTick: number;
  alphaValues: number;
  framesBetweenTicks: number;
  framesSampled: number;
  seconds: number;
}

let scratch: string;
let tarball: string;
let browser: Browser;
const prepared = new Map<string, Promise<Prepared>>();
const results: Record<string, { prepare?: Record<string, number>; displays: Measured[] }> = {};

/** Fails with the program's output when it did not exit 0. */
function ok(ran: Ran, what: string): void {
  if (ran.code !== 0) {
    throw new Error(`${what} failed (exit ${ran.code}):\n${ran.stdout}\n${ran.stderr}`);
  }
}

/**
 * Copies an example outside the repository, installs the tarball and its dependencies, type-checks
 * and builds it — with its own TypeScript and Vite, as `npm run typecheck` / `npm run build` would.
 */
async function prepare(name: string): Promise<Prepared> {
  const dir = path.join(scratch, name);
  const timings: Record<string, number> = {};
  const time = async <T>(stage: string, work: () => Promise<T>): Promise<T> => {
    const t0 = performance.now();
    const out = await work();
    timings[stage] = Math.round(performance.now() - t0);
    return out;
  };
  await cp(path.join(repo, 'examples', name), dir, {
    recursive: true,
    filter: (src) => !/[\\/](node_modules|dist|dist-game)$/.test(src),
  });
  // The package comes from its tarball (what `npm install fixedstep` would give), not the registry.
  const pkgFile = path.join(dir, 'package.json');
  const pkg = JSON.parse(await readFile(pkgFile, 'utf8')) as {
    dependencies: Record<string, string>;
    scripts: Record<string, string>;
  };
  expect(pkg.dependencies.fixedstep).toBe('^0.1.0');
  pkg.dependencies.fixedstep = `file:${tarball}`;
  await writeFile(pkgFile, JSON.stringify(pkg, null, 2));
  await time('install', async () => {
    ok(
      await run('npm', ['install', '--no-audit', '--no-fund', '--prefer-offline'], dir),
      `npm install in ${name}`,
    );
  });
  expect((await stat(path.join(dir, 'node_modules/fixedstep'))).isSymbolicLink()).toBe(false);
  await time('typecheck', async () => {
    ok(
      await run(process.execPath, ['node_modules/typescript/bin/tsc', '-p', 'tsconfig.json'], dir),
      `tsc in ${name}`,
    );
  });
  // Coin Dash compiles its simulation alone for Node (`lib: ["ES2022"], types: []`): the
  // declarations it reads must name no global of the DOM or of Node.
  if (pkg.scripts['build:game'] !== undefined) {
    await time('build:game', async () => {
      ok(await run('npm', ['run', 'build:game'], dir), `npm run build:game in ${name}`);
    });
  }
  await time('build', async () => {
    ok(
      await run(
        process.execPath,
        ['node_modules/vite/bin/vite.js', 'build', '--logLevel', 'error'],
        dir,
      ),
      `vite build in ${name}`,
    );
  });
  return { dir, timings };
}

beforeAll(async () => {
  scratch = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-examples-'));
  const tarballs = path.join(scratch, 'tarballs');
  await mkdir(tarballs);
  tarball = (await packWorkspaces(['packages/fixedstep'], tarballs)).get('fixedstep')!.tarball;
  // The recipes' shared game, beside them as in examples/: their `prepare` script (which
  // `npm install` runs) copies it into their src/.
  await cp(path.join(repo, 'examples/shared'), path.join(scratch, 'shared'), { recursive: true });
  // Installs wait on the network and the disk, builds on the CPU: start them all at once.
  for (const e of EXAMPLES) {
    const p = prepare(e.name);
    p.catch(() => undefined); // reported by the example's own test
    prepared.set(e.name, p);
  }
  browser = await launchChromium();
}, 180_000);

afterAll(async () => {
  await Promise.allSettled(prepared.values());
  await browser.close();
  await rm(scratch, { recursive: true, force: true });
  await mkdir(path.join(repo, 'artifacts/examples'), { recursive: true });
  await writeFile(
    path.join(repo, 'artifacts/examples/results.json'),
    `${JSON.stringify(results, null, 2)}\n`,
  );
}, 120_000);

/**
 * The simulated display, run in the page before its own scripts (after Playwright's clock): a
 * vsync every 1000 / hz ms of the fake clock, every callback requested before it run at it with
 * its timestamp, as a browser does. Playwright fakes `performance.now()` but not
 * `event.timeStamp`; a browser keeps both on one time line, so the display does too. Key events
 * are logged with their time; the last arc drawn on a 2D canvas is kept (coin-dash's player).
 */
function display(hz: number): void {
  const period = 1000 / hz;
  let queue: [number, FrameRequestCallback][] = [];
  let timer = 0;
  let frame = -1;
  let nextId = 1;
  const fire = () => {
    timer = 0;
    const callbacks = queue;
    queue = [];
    const t = frame * period;
    for (const [, cb] of callbacks) cb(t);
  };
  window.requestAnimationFrame = (cb) => {
    if (timer === 0) {
      const now = performance.now();
      frame = Math.max(frame + 1, Math.floor(now / period) + 1);
      timer = window.setTimeout(fire, frame * period - now);
    }
    queue.push([nextId, cb]);
    return nextId++;
  };
  window.cancelAnimationFrame = (id) => {
    queue = queue.filter(([i]) => i !== id);
  };
  Object.defineProperty(Event.prototype, 'timeStamp', {
    configurable: true,
    get: () => performance.now(),
  });
  const w = window as unknown as { __keys: [number, string, string][]; __lastArc: number[] };
  w.__keys = [];
  const log = (e: KeyboardEvent) => w.__keys.push([performance.now(), e.code, e.type]);
  window.addEventListener('keydown', log, true);
  window.addEventListener('keyup', log, true);
  // eslint-disable-next-line @typescript-eslint/unbound-method -- called below with the context as this
  const arc = CanvasRenderingContext2D.prototype.arc;
  CanvasRenderingContext2D.prototype.arc = function (x, y, r, a0, a1, ccw) {
    w.__lastArc = [x, y, r];
    arc.call(this, x, y, r, a0, a1, ccw);
  };
}

/** One tick as the test's wrapper of `game.step` saw it: tick before the step, pressed mask, x, y after. */
type TickRecord = [tick: number, pressed: number, x: number, y: number];

/** Wraps the page's `game.step` to record every tick (see {@link TickRecord}). */
function recordTicks(page: Page, hook: string): Promise<void> {
  return page.evaluate((hook) => {
    const w = window as unknown as Record<string, { game: Record<string, unknown> }> & {
      __ticks: TickRecord[];
    };
    const game = w[hook]!.game as {
      tick: number;
      x: number | Float64Array;
      y: number | Float64Array;
      step(inputs: readonly unknown[]): void;
    };
    const step = game.step.bind(game);
    const first = (v: number | Float64Array) => (typeof v === 'number' ? v : v[0]!);
    w.__ticks = [];
    game.step = (inputs) => {
      const i = inputs[0] as number | { buttons: number };
      const buttons = typeof i === 'number' ? i : i.buttons;
      const tick = game.tick;
      step(inputs);
      w.__ticks.push([tick, buttons >>> 16, first(game.x), first(game.y)]);
    };
  }, hook);
}

/** The loop's state between frames: its tick, time line, accumulator and alpha. */
interface LoopState {
  now: number;
  tick: number;
  loopNow: number;
  acc: number;
  alpha: number;
  drawn: [number, number];
}

function loopState(page: Page, e: Example): Promise<LoopState> {
  return page.evaluate(
    ({ hook, drawn }) => {
      const w = window as unknown as Record<
        string,
        {
          loop: { tick: number; nowMs: number; accumulatorMs: number; alpha: number };
          drawn(): [number, number];
        }
      > & { __lastArc: [number, number, number] };
      const h = w[hook]!;
      const loop = h.loop;
      const where: [number, number] =
        drawn === 'arc' ? [w.__lastArc[0] / 60, w.__lastArc[1] / 60] : h.drawn();
      return {
        now: performance.now(),
        tick: loop.tick,
        loopNow: loop.nowMs,
        acc: loop.accumulatorMs,
        alpha: loop.alpha,
        drawn: where,
      };
    },
    { hook: e.hook, drawn: e.drawn },
  );
}

/** Plays `e` on a display of `hz` and checks tick rate, key presses and interpolation. */
async function playOn(url: string, e: Example, hz: number): Promise<Measured> {
  const t0 = performance.now();
  const context = await browser.newContext({ viewport: { width: 1000, height: 800 } });
  const problems: string[] = [];
  try {
    await context.route('**/favicon.ico', (r) => r.fulfill({ status: 204 }));
    const page = await context.newPage();
    page.on('console', (msg) => {
      // SwiftShader's notes on WebGL read-backs are the headless GPU's, not the page's.
      if (
        (msg.type() === 'error' || msg.type() === 'warning') &&
        !msg.text().includes('GL Driver')
      ) {
        problems.push(`console.${msg.type()}: ${msg.text()}`);
      }
    });
    page.on('pageerror', (error) => problems.push(`page error: ${error.message}`));
    page.on('requestfailed', (req) => problems.push(`request failed: ${req.url()}`));
    await page.clock.install({ time: 0 });
    await page.clock.pauseAt(1000);
    await page.addInitScript(display, hz);
    await page.goto(url + e.url);
    // The engine boots (some of it on real time: module loads, a WebGL context): wait on the
    // hook, moving the page's clock along, for up to a minute of real time on a busy machine.
    const deadline = performance.now() + 60_000;
    while (!(await page.evaluate((h) => h in window, e.hook))) {
      if (performance.now() > deadline) {
        throw new Error(`${e.name}: the page never set ${e.hook}; ${problems.join('; ')}`);
      }
      await page.clock.runFor(100);
    }
    await recordTicks(page, e.hook);
    await page.clock.runFor(1000); // the engine boots, the loop takes its first frames

    // 1. Ticks per second, over 5 s of the display.
    const a = await loopState(page, e);
    await page.clock.runFor(5000);
    const b = await loopState(page, e);
    const ticksPerSecond = (b.tick - a.tick) / ((b.now - a.now) / 1000);
    expect(Math.abs(ticksPerSecond - TICK_RATE) / TICK_RATE).toBeLessThan(0.01);

    // 2. Key presses: taps of 5 ms (shorter than a tick) at times that fall anywhere in a frame.
    // The tick that must see a press at t is the one whose span [origin + g·step, origin +
    // (g+1)·step) holds t, where origin is the loop's time line less its ticks and accumulator.
    const s = await loopState(page, e);
    const origin = s.loopNow - s.acc - s.tick * STEP_MS;
    const keyNames = Object.keys(e.keys);
    const expected: [number, number][] = [];
    const pressStart = await page.evaluate(
      () => (window as unknown as { __keys: [] }).__keys.length,
    );
    for (let k = 0; k < 12; k++) {
      await page.clock.runFor(61 + 13 * k);
      const now = await page.evaluate(() => performance.now());
      const phase = (now - origin) / STEP_MS;
      if (Math.abs(phase - Math.round(phase)) < 1e-3) await page.clock.runFor(1); // not on a tick's edge
      const key = keyNames[k % keyNames.length]!;
      await page.keyboard.down(key);
      await page.clock.runFor(5);
      await page.keyboard.up(key);
    }
    await page.clock.runFor(200);
    const keys = await page.evaluate(
      (from) => (window as unknown as { __keys: [number, string, string][] }).__keys.slice(from),
      pressStart,
    );
    for (const [t, code, type] of keys) {
      if (type === 'keydown') expected.push([Math.floor((t - origin) / STEP_MS), e.keys[code]!]);
    }
    expect(expected).toHaveLength(12);
    const ticks = await page.evaluate(
      () => (window as unknown as { __ticks: TickRecord[] }).__ticks,
    );
    const seen: [number, number][] = [];
    for (const [tick, pressed] of ticks) {
      for (let bit = 0; bit < 16; bit++) if (pressed & (1 << bit)) seen.push([tick, bit]);
    }
    // Each press on exactly one tick, its own, and no press anywhere else.
    expect(seen).toEqual(expected);

    // 3. Interpolation: steer left and look at 60 single frames.
    await page.keyboard.down('ArrowLeft');
    const period = 1000 / hz;
    const byTick = new Map<number, [number, number]>();
    const frames: LoopState[] = [];
    for (let f = 0; f < 60; f++) {
      await page.clock.runFor(period);
      frames.push(await loopState(page, e));
    }
    await page.keyboard.up('ArrowLeft');
    for (const [tick, , x, y] of await page.evaluate(
      () => (window as unknown as { __ticks: TickRecord[] }).__ticks,
    )) {
      byTick.set(tick + 1, [x, y]);
    }
    const alphas = new Set<number>();
    let between = 0;
    for (const f of frames) {
      const prev = byTick.get(f.tick - 1);
      const curr = byTick.get(f.tick);
      if (!prev || !curr) throw new Error(`no record of ticks ${f.tick - 1}…${f.tick}`);
      alphas.add(f.alpha);
      for (const c of [0, 1]) {
        const want = prev[c]! + (curr[c]! - prev[c]!) * f.alpha;
        expect(f.drawn[c]).toBeCloseTo(want, 6);
      }
      const lo = Math.min(prev[0], curr[0]);
      const hi = Math.max(prev[0], curr[0]);
      if (f.drawn[0] > lo + 1e-9 && f.drawn[0] < hi - 1e-9) between++;
    }
    expect(alphas.size).toBeGreaterThan(3);
    expect(between).toBeGreaterThan(20);

    // 4. coin-dash: the round to its end, and the replay verified by re-simulation.
    if (e.playsRound === true && hz === RATES[0]) {
      const over = () =>
        page.evaluate(
          (hook) =>
            (window as unknown as Record<string, { game: { over: boolean } }>)[hook]!.game.over,
          e.hook,
        );
      for (let i = 0; i < 80 && !(await over()); i++) await page.clock.runFor(1000);
      expect(await over()).toBe(true);
      await expect.poll(() => page.locator('#hud').textContent()).toContain('replay verified');
    }
    expect(problems).toEqual([]);
    return {
      hz,
      ticksPerSecond,
      presses: expected.length,
      pressesOnTheirTick: seen.length,
      alphaValues: alphas.size,
      framesBetweenTicks: between,
      framesSampled: frames.length,
      seconds: Math.round(performance.now() - t0) / 1000,
    };
  } catch (error) {
    if (problems.length > 0)
      console.error(`${e.name} at ${hz} Hz, page problems:\n${problems.join('\n')}`);
    throw error;
  } finally {
    await context.close();
  }
}

describe('the examples, installed from the packed tarball and played on a simulated display', () => {
  it.each(EXAMPLES)(
    '$name: installs, type-checks, builds; 60 ticks/s, one tick per key press, interpolated drawing at 50 and 144 Hz',
    async (e) => {
      const { dir, timings } = await prepared.get(e.name)!;
      const server = await startServer({
        port: 0,
        host: '127.0.0.1',
        root: path.join(dir, 'dist'),
      });
      results[e.name] = { prepare: timings, displays: [] };
      try {
        for (const hz of RATES)
          results[e.name]!.displays.push(await playOn(server.url.replace(/\/$/, ''), e, hz));
      } finally {
        await server.close();
      }
      expect(results[e.name]!.displays.map((d) => d.hz)).toEqual([...RATES]);
    },
    900_000,
  );
});
