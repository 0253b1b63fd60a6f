/**
 * Shared set-up of the browser tests: the built lab served by `fixedstep serve`'s server on a free
 * port, headless Chromium, and helpers to read a chapter's readouts and catch console problems.
 * Every chapter's test file calls {@link useLab} once at its top level.
 */
import { existsSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { afterAll, beforeAll, expect } from 'vitest';
import { chromium, type Browser, type BrowserContext, type Page } from 'playwright-core';
import { startServer, type RunningServer } from '@fixedstep/server';
import { openStore } from '../packages/server/src/store/store.js';

const repo = fileURLToPath(new URL('..', import.meta.url));
export const dist = path.join(repo, 'apps/lab/dist');
/** Where screenshots go (look at them). */
export const shots = path.join(repo, 'artifacts/screenshots');

/** The flags every headless Chromium here starts with (no network beyond localhost). */
export const CHROMIUM_ARGS = [
  '--headless',
  '--no-sandbox',
  '--disable-gpu',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--no-first-run',
];

/** Starts the headless Chromium the tests drive: `CHROMIUM_PATH` (or /usr/bin/chromium) with {@link CHROMIUM_ARGS}. */
export function launchChromium(): Promise<Browser> {
  return chromium.launch({
    executablePath: process.env.CHROMIUM_PATH ?? '/usr/bin/chromium',
    args: CHROMIUM_ARGS,
  });
}

export interface Lab {
  server: RunningServer;
  browser: Browser;
}

/** Starts the server and the browser before the file's tests and stops them after. */
export function useLab(): Lab {
  const lab = {} as Lab;
  beforeAll(async () => {
    if (!existsSync(path.join(dist, 'index.html'))) {
      throw new Error(
        `The lab is not built: ${path.join(dist, 'index.html')} is missing. Run \`npm run build\` first.`,
      );
    }
    mkdirSync(shots, { recursive: true });
    lab.server = await startServer({ port: 0, host: '127.0.0.1', root: dist });
    lab.browser = await launchChromium();
  });
  afterAll(async () => {
    await lab.browser.close();
    await lab.server.close();
  });
  return lab;
}

/** An endpoint a test's server runs beside the lab (the relay, signalling, state sync). */
export interface Closable {
  close(): Promise<unknown>;
}

/**
 * The lab served with the endpoints `attach` adds to its HTTP server, and a browser: started
 * before the file's (or the describe block's) tests; after them the browser, the endpoints
 * (the last attached first) and the server are closed.
 */
export function useLabWith(
  attach: (server: RunningServer) => Promise<Closable[]> | Closable[],
): Lab {
  const lab = {} as Lab;
  let endpoints: Closable[] = [];
  beforeAll(async () => {
    lab.server = await startServer({ port: 0, host: '127.0.0.1', root: dist });
    endpoints = await attach(lab.server);
    lab.browser = await launchChromium();
  });
  afterAll(async () => {
    await lab.browser.close();
    for (const e of [...endpoints].reverse()) await e.close();
    await lab.server.close();
  });
  return lab;
}

/** The lab and a second server of it with the highscore API (see {@link useHighscoreServer}). */
export interface HighscoreLab {
  /** The lab (its browser; its plain server, without the highscore API). */
  readonly lab: Lab;
  /** The second server's address, once the tests run. */
  readonly url: string;
}

/**
 * The lab ({@link useLab}) and a second server of the built lab, with the highscore API on a
 * store in a temporary folder (named after `name`), started before the file's tests and stopped
 * (its folder removed) after: the game and replay chapters read their tables from it.
 */
export function useHighscoreServer(name: string): HighscoreLab {
  const lab = useLab();
  let server: RunningServer | undefined;
  let dataDir = '';
  beforeAll(async () => {
    dataDir = mkdtempSync(path.join(tmpdir(), `fixedstep-${name}-e2e-`));
    server = await startServer({ root: dist, port: 0, store: openStore({ dataDir }) });
    // The chapters ask for their table on load: the store must be open (until then it answers 503).
    await server.storeReady;
  });
  afterAll(async () => {
    await server?.close();
    rmSync(dataDir, { recursive: true, force: true });
  });
  return {
    lab,
    get url(): string {
      if (server === undefined) throw new Error('the highscore server is not started yet');
      return server.url;
    },
  };
}

/** Chapter 9, the games, as a test file opens it (see {@link useGames}). */
export interface GamesChapter extends HighscoreLab {
  /**
   * Goes to the chapter at {@link url} with `query` (`game=ctf&seed=7`, …) on `page` and waits for
   * the game's canvas and its first tick.
   */
  open(page: Page, query: string): Promise<void>;
}

/** A {@link useHighscoreServer} named `name`, for tests of the games chapter. */
export function useGames(name: string): GamesChapter {
  const api = useHighscoreServer(name);
  return {
    lab: api.lab,
    get url(): string {
      return api.url;
    },
    async open(page: Page, query: string): Promise<void> {
      await page.goto(`${api.url}#/games?${query}`);
      await expect.poll(() => page.title()).toBe('9. Games — fixedstep lab');
      await page.getByTestId('canvas-game').waitFor();
      await page.getByTestId('readout-tick').waitFor();
    },
  };
}

/** A page's viewport in CSS px. */
export interface Viewport {
  width: number;
  height: number;
}

/** One chapter of the lab as its test file opens it (see {@link useChapter}). */
export interface Chapter {
  /** The lab the chapter is served from. */
  readonly lab: Lab;
  /** Go to the chapter on `page` and wait until it is mounted (its title, then its readout). */
  goto(page: Page): Promise<void>;
  /**
   * A watched page of `device` (a laptop's 1440 × 900 unless told; `'phone'`: {@link phonePage}),
   * still blank. Close it with `page.context().close()`.
   */
  newPage(device?: Device): Promise<{ page: Page; problems: string[] }>;
  /** {@link Chapter.newPage}, then {@link Chapter.goto}: the page on the mounted chapter. */
  open(device?: Device): Promise<{ page: Page; problems: string[] }>;
  /** {@link Chapter.open}, then {@link freshRun}: paused, restarted, the clock at 0. */
  openFresh(device?: Device): Promise<{ page: Page; problems: string[] }>;
}

/** A page's viewport in CSS px, or `'phone'` for {@link phonePage}'s. */
export type Device = Viewport | 'phone';

/**
 * {@link useLab} for a file that tests one chapter: the chapter at `#/route`, whose document title
 * is `title`, is mounted once the element with test id `ready` is there.
 */
export function useChapter(route: string, title: string, ready: string): Chapter {
  const lab = useLab();
  const goto = async (page: Page): Promise<void> => {
    await page.goto(`${lab.server.url}#/${route}`);
    await expect.poll(() => page.title()).toBe(title);
    await page.getByTestId(ready).waitFor();
  };
  const newPage = async (device: Device = { width: 1440, height: 900 }) => {
    if (device === 'phone') return phonePage(lab.browser);
    const page = await lab.browser.newPage({ viewport: device });
    return { page, problems: watch(page) };
  };
  const open = async (device?: Device) => {
    const opened = await newPage(device);
    await goto(opened.page);
    return opened;
  };
  return {
    lab,
    goto,
    newPage,
    open,
    async openFresh(device) {
      const opened = await open(device);
      await freshRun(opened.page);
      return opened;
    },
  };
}

/** A full-page screenshot of `page` to `name`.png in {@link shots}. */
export async function shoot(page: Page, name: string): Promise<void> {
  await page.screenshot({ path: path.join(shots, `${name}.png`), fullPage: true });
}

/** A full-page screenshot to `name`.png, and the page fits its window: no sideways scrolling. */
export async function expectFits(page: Page, name: string): Promise<void> {
  await shoot(page, name);
  expect(await horizontalOverflow(page)).toBe(0);
}

/** Every readout on the page: test id → data-value. */
export async function readouts(page: Page): Promise<Record<string, string>> {
  return page.evaluate(() => {
    const out: Record<string, string> = {};
    for (const el of document.querySelectorAll<HTMLElement>('[data-testid^="readout-"]')) {
      out[el.dataset.testid!] = el.dataset.value ?? '';
    }
    return out;
  });
}

/**
 * Waits until readout `testId` on every page holds a state hash (16 hex digits: the match, the
 * replay or the snapshot got there), up to `timeoutMs`, and returns each page's readouts then.
 */
export async function readoutsOnceHashed(
  pages: readonly Page[],
  testId: string,
  timeoutMs: number,
): Promise<Record<string, string>[]> {
  return Promise.all(
    pages.map(async (p) => {
      await expect
        .poll(() => p.getByTestId(testId).getAttribute('data-value'), { timeout: timeoutMs })
        .toMatch(/^[0-9a-f]{16}$/);
      return readouts(p);
    }),
  );
}

/** A readout's value as a number; throws naming the readout when it is missing. */
export function num(r: Record<string, string>, id: string): number {
  const v = r[`readout-${id}`];
  if (v === undefined || v === '') throw new Error(`no readout-${id}`);
  return Number(v);
}

/** Console errors and warnings, page errors and failed requests of `page`, as they happen. */
export function watch(page: Page): string[] {
  const problems: string[] = [];
  page.on('console', (msg) => {
    if (msg.type() === 'error' || msg.type() === 'warning')
      problems.push(`console.${msg.type()}: ${msg.text()}`);
  });
  page.on('pageerror', (error) => problems.push(`page error: ${error.message}`));
  page.on('requestfailed', (req) => problems.push(`request failed: ${req.url()}`));
  return problems;
}

/** The `data-value` of the element with test id `testId` ('' when it has none). */
export async function value(page: Page, testId: string): Promise<string> {
  return (await page.getByTestId(testId).getAttribute('data-value')) ?? '';
}

/** The lab's virtual clock in ms (every chapter shows it as `readout-clock`). */
async function clock(page: Page): Promise<number> {
  return Number(await value(page, 'readout-clock'));
}

/** Pause the chapter unless it is paused already. */
export async function pause(page: Page): Promise<void> {
  if ((await page.getByTestId('control-pause').getAttribute('aria-pressed')) !== 'true') {
    await page.getByTestId('control-pause').click();
  }
}

/** Pause the chapter, optionally choose a display rate, and restart: the clock stops at exactly 0. */
export async function freshRun(page: Page, hz?: number): Promise<void> {
  await pause(page);
  if (hz !== undefined) await page.getByTestId(`control-hz-${String(hz)}`).click();
  await page.getByTestId('control-restart').click();
  await expect.poll(() => clock(page)).toBe(0);
}

/** Press "Skip +5 s" `times` times and wait until the clock shows it. */
export async function skip(page: Page, times = 1): Promise<void> {
  const before = await clock(page);
  for (let i = 0; i < times; i++) await page.getByTestId('control-skip').click();
  await expect.poll(() => clock(page)).toBe(before + 5000 * times);
}

/** A phone-sized page (390 × 844 CSS px, touch, 2× pixels) in a context of its own, watched. */
export async function phonePage(
  browser: Browser,
): Promise<{ context: BrowserContext; page: Page; problems: string[] }> {
  const context = await browser.newContext({
    viewport: { width: 390, height: 844 },
    deviceScaleFactor: 2,
    isMobile: true,
    hasTouch: true,
  });
  const page = await context.newPage();
  return { context, page, problems: watch(page) };
}

/** How many CSS px the page is wider than its window: 0 means no sideways scrolling. */
export function horizontalOverflow(page: Page): Promise<number> {
  return page.evaluate(
    () => document.documentElement.scrollWidth - document.documentElement.clientWidth,
  );
}

/**
 * Switch the (paused) chapter to the real clock, play, wait until its clock has passed `ms`, and
 * switch back to the simulated display.
 */
export async function realClockRuns(page: Page, ms = 100): Promise<void> {
  await page.getByTestId('control-real-clock').click();
  await page.getByTestId('control-pause').click();
  await expect.poll(() => clock(page), { timeout: ms + 60_000 }).toBeGreaterThan(ms);
  await page.getByTestId('control-real-clock').click();
}
