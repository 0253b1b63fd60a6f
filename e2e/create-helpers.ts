/**
 * A game made by `npm create fixedstep`, played the way its README says, whatever its template
 * draws with (plain canvas, Phaser, PixiJS, three.js — every template is the same game, the same
 * src/game.ts and src/play.ts): `npm run serve` (fixedstep serve: the page, the highscore table,
 * the relay), one round in headless Chromium with scripted keys, the round ended (the page
 * verifies its replay and submits the score), the downloaded replay verified by `npm run verify`,
 * and the canvas as drawn read back pixel by pixel against the state it was drawn from. Phaser,
 * PixiJS and three.js draw with WebGL here too: Chromium started with --disable-gpu (harness.ts)
 * gives pages a software WebGL (SwiftShader), whose performance notes ("GPU stall due to
 * ReadPixels") are console warnings, not errors.
 */
import { stat } from 'node:fs/promises';
import path from 'node:path';
import type { Browser, Page } from 'playwright-core';
import { expect } from 'vitest';
import { run } from './pack-helpers.js';
import { startProgram, waitFor, type Program } from './registry-helpers.js';

/** The field and the bodies on it, in metres, as templates/_shared/src/game.ts declares them. */
const WIDTH = 16;
const HEIGHT = 9;
const PLAYER_RADIUS = 0.4;
const COINS = 5;
/** The colours of templates/_shared/src/play.ts, as [r, g, b]. */
const BACKGROUND: Rgb = [0x10, 0x14, 0x1c];
const PLAYER: Rgb = [0x4c, 0xc2, 0xff];
const COIN: Rgb = [0xf5, 0xc5, 0x42];
/** The second player online. */
const OTHER: Rgb = [0xff, 0x7a, 0x59];
/** The seed of the round {@link playRound} plays. */
const SEED = 20_251_207;
/** How far (per channel, 0–255) a pixel may be from a colour and still count as it. */
const TOLERANCE = 24;

type Rgb = readonly [number, number, number];

/** A created game's `npm run serve`, listening and with its store open. */
export interface ServedGame {
  program: Program;
  url: string;
}

/** `npm run serve -- --port 0 --data <data>` in `dir`, once it answers /readyz. */
export async function serveGame(
  dir: string,
  data: string,
  env: NodeJS.ProcessEnv,
): Promise<ServedGame> {
  const program = startProgram(
    'npm',
    ['run', 'serve', '--', '--port', '0', '--data', data],
    dir,
    env,
  );
  try {
    const url = await waitFor(
      'the game served',
      () => Promise.resolve(/fixedstep lab: (http\S+)/.exec(program.output())?.[1]),
      program,
    );
    // The store opens while the server already listens: until then the highscore API answers
    // 503 (the page would ask again, but the browser logs the first answer as an error).
    await waitFor(
      'the store open (/readyz)',
      async () => ((await fetch(new URL('/readyz', url))).ok ? true : undefined),
      program,
    );
    return { program, url };
  } catch (error) {
    await program.stop('SIGKILL');
    throw error;
  }
}

/** The page's hook (`window.myGame` when playing alone), reduced to numbers. */
interface Alone {
  tick: number;
  seed: number;
  score: number;
  x: number;
  y: number;
  coins: [number, number][];
}

function alone(page: Page): Promise<Alone> {
  return page.evaluate(() => {
    interface Game {
      tick: number;
      score: Uint32Array;
      x: Float64Array;
      y: Float64Array;
      coinX: Float64Array;
      coinY: Float64Array;
    }
    const { game, seed } = (window as unknown as { myGame: { game: Game; seed: number } }).myGame;
    return {
      tick: game.tick,
      seed,
      score: game.score[0]!,
      x: game.x[0]!,
      y: game.y[0]!,
      coins: Array.from(game.coinX, (x, c): [number, number] => [x, game.coinY[c]!]),
    };
  });
}

/** What {@link playRound} saw, for the report. */
export interface Round {
  /** Ticks the round lasted, the score, and what `npm run verify` printed. */
  ticks: number;
  score: number;
  verified: string;
  /** Pixels per metre in the screenshot, and the player's disc: pixels of its colour. */
  scale: number;
  playerPixels: number;
}

/**
 * One round of the game served at `url` (made in `dir`): scripted keys move the player as they
 * say, the round is ended early, the page's own replay check passes, the server accepts the
 * score, the canvas shows the state, and `npm run verify` reproduces the downloaded replay.
 * The screenshot of the canvas is written to `shot` (look at it; it is not committed).
 */
export async function playRound(
  browser: Browser,
  url: string,
  dir: string,
  shot: string,
  env: NodeJS.ProcessEnv,
): Promise<Round> {
  const page = await browser.newPage();
  const problems: string[] = [];
  page.on('pageerror', (e) => problems.push(e.message));
  page.on('console', (m) => {
    // SwiftShader's notes on WebGL read-backs are the headless GPU's, not the page's.
    if (m.type() === 'error' && !m.text().includes('GL Driver')) problems.push(m.text());
  });
  // A seed of the test's own: the coins fall the same on every run (the keys' ticks do not).
  await page.goto(new URL(`/?seed=${SEED}`, url).href);
  const tick = async () => (await alone(page)).tick;
  await expect.poll(tick, { timeout: 30_000 }).toBeGreaterThan(0);
  // Nothing pressed: the player stays where one player starts, mid-field.
  expect(await alone(page)).toMatchObject({ seed: SEED, x: WIDTH / 2, y: HEIGHT / 2 });
  await page.locator('#field').click();

  // Right for a second: the player speeds right (40 m/s², drag 6/s) and stays on its row.
  await page.keyboard.down('ArrowRight');
  const t0 = await tick();
  await expect.poll(tick, { timeout: 20_000 }).toBeGreaterThan(t0 + 60);
  await page.keyboard.up('ArrowRight');
  const right = await alone(page);
  expect(right.x).toBeGreaterThan(WIDTH / 2 + 3);
  expect(right.y).toBe(HEIGHT / 2);
  // Then down, with a dash: the player leaves its row downwards.
  await page.keyboard.down('ArrowDown');
  await page.keyboard.press('Space');
  await expect.poll(tick, { timeout: 20_000 }).toBeGreaterThan(t0 + 150);
  await page.keyboard.up('ArrowDown');
  expect((await alone(page)).y).toBeGreaterThan(HEIGHT / 2 + 1.5);

  await page.locator('#end').click();
  await expect
    .poll(() => page.locator('#hud').textContent(), { timeout: 20_000 })
    .toContain('replay verified');
  await expect
    .poll(() => page.evaluate(() => document.body.dataset.highscore), { timeout: 30_000 })
    .toBe('accepted');
  // The round has ended: the state no longer changes, and the canvas keeps drawing it.
  const end = await alone(page);
  const png = await page.locator('#field').screenshot({ path: shot });
  const corner = [0.1, 0.1] as const; // no disc reaches it
  const drawn = await readPixels(browser, png, [corner, [end.x, end.y], ...end.coins], [PLAYER]);
  const [cornerRgb, playerRgb, ...coinRgb] = drawn.at;
  // The background in the corner, the player's colour where the state has it …
  expect(off(cornerRgb!, BACKGROUND), `corner ${String(cornerRgb)}`).toBeLessThanOrEqual(TOLERANCE);
  expect(off(playerRgb!, PLAYER), `player ${String(playerRgb)}`).toBeLessThanOrEqual(TOLERANCE);
  // … its disc centred there (within the last tick's motion: the frame blends the last two
  // ticks) and of its size, and every coin drawn where it lies (but one the last tick dropped
  // under the player: the player is drawn over it).
  const [centre] = drawn.centres;
  expect(Math.abs(centre![0] - end.x)).toBeLessThan(0.15);
  expect(Math.abs(centre![1] - end.y)).toBeLessThan(0.15);
  const disc = Math.PI * (PLAYER_RADIUS * drawn.scale) ** 2;
  expect(drawn.counts[0]).toBeGreaterThan(0.85 * disc);
  expect(drawn.counts[0]).toBeLessThan(1.15 * disc);
  expect(coinRgb).toHaveLength(COINS);
  coinRgb.forEach((rgb, c) => {
    const [cx, cy] = end.coins[c]!;
    if ((cx - end.x) ** 2 + (cy - end.y) ** 2 < (PLAYER_RADIUS + 0.15) ** 2) return;
    expect(off(rgb, COIN), `coin ${c}: ${rgb.join()}`).toBeLessThanOrEqual(TOLERANCE);
  });

  const [download] = await Promise.all([
    page.waitForEvent('download'),
    page.locator('#download').click(),
  ]);
  const file = path.join(path.dirname(shot), `${path.basename(dir)}.fsr`);
  await download.saveAs(file);
  expect((await stat(file)).size).toBeGreaterThan(50);
  expect(problems).toEqual([]);
  await page.close();

  const verified = await run('npm', ['run', '--silent', 'verify', '--', file], dir, env);
  expect({ code: verified.code, stderr: verified.stderr }).toEqual({ code: 0, stderr: '' });
  expect(verified.stdout).toContain(`ok: my-game v1, ${end.tick} ticks reproduced`);
  const scores = (await (await fetch(new URL('/api/highscores?game=my-game', url))).json()) as {
    entries: { score: number; ticks: number; seed: number; finalHash: string }[];
  };
  expect(scores.entries).toEqual([
    expect.objectContaining({ score: end.score, ticks: end.tick, seed: end.seed }),
  ]);
  expect(verified.stdout).toContain(`final hash ${scores.entries[0]!.finalHash}`);
  return {
    ticks: end.tick,
    score: end.score,
    verified: verified.stdout.trim(),
    scale: drawn.scale,
    playerPixels: drawn.counts[0]!,
  };
}

/** How far apart two colours are: the largest difference of a channel. */
function off(a: Rgb, b: Rgb): number {
  return Math.max(...a.map((v, k) => Math.abs(v - b[k]!)));
}

/** What {@link readPixels} read from a screenshot of the canvas. */
interface Pixels {
  /** Pixels per metre. */
  scale: number;
  /** The colour at each point asked for. */
  at: Rgb[];
  /** For each colour asked for: how many pixels have it, and their centre, in metres. */
  counts: number[];
  centres: [number, number][];
}

/**
 * Decodes `png`, a screenshot of the canvas, in a blank page (a page of the game may forbid
 * data: images), and reads it: the colour at each of `points` (in metres), and where each of
 * `colors` is. The canvas fills its screenshot, so the scale is its width over WIDTH.
 */
async function readPixels(
  browser: Browser,
  png: Buffer,
  points: readonly (readonly [number, number])[],
  colors: readonly Rgb[],
): Promise<Pixels> {
  const page = await browser.newPage();
  try {
    return await page.evaluate(
      async ({ b64, width, points, colors, tolerance }) => {
        const img = new Image();
        img.src = `data:image/png;base64,${b64}`;
        await img.decode();
        const canvas = document.createElement('canvas');
        canvas.width = img.width;
        canvas.height = img.height;
        const ctx = canvas.getContext('2d')!;
        ctx.drawImage(img, 0, 0);
        const { data } = ctx.getImageData(0, 0, img.width, img.height);
        const scale = img.width / width;
        const at = points.map(([x, y]): [number, number, number] => {
          const i = 4 * (Math.round(y * scale) * img.width + Math.round(x * scale));
          return [data[i]!, data[i + 1]!, data[i + 2]!];
        });
        const counts = colors.map(() => 0);
        const sums = colors.map(() => [0, 0]);
        for (let i = 0; i < data.length; i += 4) {
          colors.forEach((rgb, k) => {
            if (rgb.every((v, c) => Math.abs(v - data[i + c]!) <= tolerance)) {
              counts[k]! += 1;
              sums[k]![0]! += ((i / 4) % img.width) + 0.5;
              sums[k]![1]! += Math.floor(i / 4 / img.width) + 0.5;
            }
          });
        }
        const centres = sums.map(([x, y], k): [number, number] => [
          x! / counts[k]! / scale,
          y! / counts[k]! / scale,
        ]);
        return { scale, at, counts, centres };
      },
      { b64: png.toString('base64'), width: WIDTH, points, colors, tolerance: TOLERANCE },
    );
  } finally {
    await page.close();
  }
}

/**
 * Online play at `url`: two tabs in one room, both stepping the round through the relay, the
 * first tab's key moving its player away from the other, and each tab drawing both players
 * (slot 0 blue, slot 1 orange). Returns the tick both reached.
 */
export async function playOnline(browser: Browser, url: string, room: string): Promise<number> {
  const pages = await Promise.all([browser.newPage(), browser.newPage()]);
  for (const page of pages) await page.goto(new URL(`/?room=${room}`, url).href);
  interface Online {
    myGame: {
      session: { welcome?: { slot: number }; simulation?: { tick: number; x: Float64Array } };
    };
  }
  const online = (page: Page) =>
    page.evaluate(() => {
      const { session } = (window as unknown as Online).myGame;
      const game = session.simulation;
      return { slot: session.welcome?.slot ?? -1, tick: game?.tick ?? -1, x: [...(game?.x ?? [])] };
    });
  const least = async () => Math.min(...(await Promise.all(pages.map(online))).map((o) => o.tick));
  await expect.poll(least, { timeout: 30_000 }).toBeGreaterThan(60);
  const before = await online(pages[0]);
  // Two players start at a third and two thirds of the field: slot 0 goes left, slot 1 right.
  const away = before.slot === 0 ? -1 : 1;
  const key = away < 0 ? 'ArrowLeft' : 'ArrowRight';
  await pages[0].keyboard.down(key);
  await expect.poll(least, { timeout: 20_000 }).toBeGreaterThan(before.tick + 60);
  await pages[0].keyboard.up(key);
  const after = await online(pages[0]);
  expect(away * (after.x[after.slot]! - before.x[before.slot]!)).toBeGreaterThan(1);
  const disc = (scale: number) => Math.PI * (PLAYER_RADIUS * scale) ** 2;
  for (const page of pages) {
    expect(await page.locator('#hud').textContent()).toMatch(/^room \S+ · you \d+ · them \d+/);
    const png = await page.locator('#field').screenshot();
    const drawn = await readPixels(browser, png, [], [PLAYER, OTHER]);
    expect(drawn.counts[0]).toBeGreaterThan(0.85 * disc(drawn.scale));
    expect(drawn.counts[1]).toBeGreaterThan(0.85 * disc(drawn.scale));
  }
  const reached = await least();
  await Promise.all(pages.map((page) => page.close()));
  return reached;
}
