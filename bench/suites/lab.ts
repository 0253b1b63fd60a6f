/**
 * The lab's main thread, chapter by chapter: the built lab opened in headless Chromium at a
 * laptop's 1440 × 900, each chapter scrolled to its first canvas for a fixed number of animation
 * frames, and measured twice — once with `Performance.getMetrics` (how busy the main thread was,
 * layouts and style recalculations per frame, script per frame) and once under a DevTools trace
 * (how much of the busy time was forced layout: style and layout run inside script because it
 * read a size after writing to the page).
 *
 * Builds: `apps/lab/dist` of this checkout (`npm run build`), or the folders named in
 * `FIXEDSTEP_LAB_BENCH_DIRS` as `name=folder,name=folder` (`before=/tmp/main-lab,after=apps/lab/dist`),
 * measured side by side: chapter by chapter, one build after the other. Needs Chromium
 * (`CHROMIUM_PATH`, default /usr/bin/chromium). CPU shares are noisy on a shared machine: compare
 * the builds of one run, not runs.
 */
import { existsSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium, type Browser, type CDPSession } from 'playwright-core';
import { CHAPTERS } from '../../apps/lab/src/chapters.js';
import { mainThreadWork } from '../lib/main-thread.js';
import { animationFrames, traceFrames } from '../lib/page-trace.js';
import { serveFolder, type StaticServer } from '../lib/static-files.js';
import { defineSuite } from '../lib/suite.js';

const ROOT = fileURLToPath(new URL('../../', import.meta.url));
const VIEWPORT = { width: 1440, height: 900 };
/** Animation frames a chapter is measured over (each way), and a quick run's. */
const FRAMES = 240;
const QUICK_FRAMES = 60;
/** Frames a chapter runs before it is measured (its first layout and chunks behind it). */
const SETTLE_FRAMES = 60;

interface Build {
  readonly name: string;
  readonly dir: string;
  server?: StaticServer;
}

/** One chapter of one build over its frames. */
interface Measured {
  /** Main-thread task time over wall time. */
  readonly busy: number;
  /** Forced style + layout time over main-thread task time (traced). */
  readonly forced: number;
  readonly layoutsPerFrame: number;
  readonly stylesPerFrame: number;
  readonly scriptMsPerFrame: number;
  readonly forcedLayoutsPerFrame: number;
}

function builds(): Build[] {
  const spec = process.env.FIXEDSTEP_LAB_BENCH_DIRS;
  if (!spec) return [{ name: 'this build', dir: path.join(ROOT, 'apps/lab/dist') }];
  return spec.split(',').map((pair) => {
    const [name, dir] = pair.split('=');
    if (!name || !dir) throw new Error(`FIXEDSTEP_LAB_BENCH_DIRS: "${pair}" is not name=folder`);
    return { name, dir: path.resolve(ROOT, dir) };
  });
}

async function metrics(cdp: CDPSession): Promise<Record<string, number>> {
  const { metrics: list } = await cdp.send('Performance.getMetrics');
  return Object.fromEntries(list.map((m) => [m.name, m.value]));
}

async function measure(
  browser: Browser,
  url: string,
  chapter: { id: string; title: string },
  n: number,
): Promise<Measured> {
  const page = await browser.newPage({ viewport: VIEWPORT });
  try {
    await page.goto(`${url}#/${chapter.id}`);
    await page.locator('main h1', { hasText: chapter.title }).waitFor();
    // To the chapter's first demo: a reader looks at it, and a demo off screen may stand still.
    await page.evaluate(
      `document.querySelector('main canvas')?.scrollIntoView({ block: 'center' })`,
    );
    await animationFrames(page, SETTLE_FRAMES);
    const cdp = await page.context().newCDPSession(page);
    await cdp.send('Performance.enable');
    const m0 = await metrics(cdp);
    const t0 = performance.now();
    await animationFrames(page, n);
    const wallS = (performance.now() - t0) / 1000;
    const m1 = await metrics(cdp);
    const d = (k: string) => (m1[k] ?? 0) - (m0[k] ?? 0);
    const work = mainThreadWork(await traceFrames(page, cdp, n));
    return {
      busy: d('TaskDuration') / wallS,
      forced: work.busyMs > 0 ? work.forcedMs / work.busyMs : 0,
      layoutsPerFrame: d('LayoutCount') / n,
      stylesPerFrame: d('RecalcStyleCount') / n,
      scriptMsPerFrame: (d('ScriptDuration') * 1000) / n,
      forcedLayoutsPerFrame: work.forcedLayouts / n,
    };
  } finally {
    await page.close();
  }
}

const pct = (x: number) => `${(100 * x).toFixed(1)} %`;

export default defineSuite({
  name: 'lab',
  description:
    'the built lab in headless Chromium, each chapter for a fixed number of frames: main-thread busy share and forced-layout share',
  async run(ctx) {
    const list = builds();
    for (const b of list) {
      if (!existsSync(path.join(b.dir, 'index.html'))) {
        ctx.note(`${b.name}: no built lab in ${b.dir} (npm run build) — skipped`);
        return;
      }
    }
    const n = ctx.quick ? QUICK_FRAMES : FRAMES;
    const browser = await chromium.launch({
      executablePath: process.env.CHROMIUM_PATH ?? '/usr/bin/chromium',
      args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run', '--disable-sync'],
    });
    const rows: string[][] = [];
    const sums = new Map<string, { busy: number; forced: number; layouts: number; k: number }>();
    try {
      for (const b of list) b.server = await serveFolder(b.dir);
      // A quick run (the test command's smoke) measures three chapters: that the suite runs.
      for (const chapter of ctx.quick ? CHAPTERS.slice(0, 3) : CHAPTERS) {
        for (const b of list) {
          const m = await measure(browser, b.server!.url, chapter, n);
          rows.push([
            `${chapter.number}. ${chapter.title}`,
            b.name,
            pct(m.busy),
            pct(m.forced),
            m.forcedLayoutsPerFrame.toFixed(2),
            m.layoutsPerFrame.toFixed(2),
            m.stylesPerFrame.toFixed(2),
            m.scriptMsPerFrame.toFixed(2),
          ]);
          const s = sums.get(b.name) ?? { busy: 0, forced: 0, layouts: 0, k: 0 };
          sums.set(b.name, {
            busy: s.busy + m.busy,
            forced: s.forced + m.forced,
            layouts: s.layouts + m.forcedLayoutsPerFrame,
            k: s.k + 1,
          });
        }
      }
    } finally {
      await browser.close();
      for (const b of list) await b.server?.close();
    }
    for (const [name, s] of sums) {
      rows.push([
        'mean of the chapters',
        name,
        pct(s.busy / s.k),
        pct(s.forced / s.k),
        (s.layouts / s.k).toFixed(2),
        '',
        '',
        '',
      ]);
    }
    ctx.table(
      `The lab's main thread, ${n} frames per chapter at ${VIEWPORT.width} × ${VIEWPORT.height} (headless Chromium)`,
      [
        'chapter',
        'build',
        'busy',
        'forced layout of busy',
        'forced layouts/frame',
        'layouts/frame',
        'style recalcs/frame',
        'script ms/frame',
      ],
      rows,
    );
  },
});
