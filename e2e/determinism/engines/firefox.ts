/**
 * Headless Firefox ESR (SpiderMonkey) through puppeteer-core over WebDriver BiDi: a stock Firefox,
 * nothing patched or downloaded.
 */
import puppeteer from 'puppeteer-core';
import { PAGE, parseRun, withTimeout, type EngineSession } from './session.js';

export async function openFirefox(executablePath: string, url: string): Promise<EngineSession> {
  const t0 = performance.now();
  const browser = await puppeteer.launch({
    browser: 'firefox',
    executablePath,
    headless: true,
    timeout: 60_000,
    protocolTimeout: 180_000,
    extraPrefsFirefox: {
      // No network beyond localhost, no updates, no telemetry.
      'app.update.enabled': false,
      'browser.shell.checkDefaultBrowser': false,
      'datareporting.policy.dataSubmissionEnabled': false,
      'toolkit.telemetry.enabled': false,
      // A long synchronous run() must not trigger the slow-script dialog.
      'dom.max_script_run_time': 0,
      'dom.max_chrome_script_run_time': 0,
    },
  });
  try {
    const page = await browser.newPage();
    const errors: string[] = [];
    page.on('pageerror', (e) => errors.push(e instanceof Error ? e.message : String(e)));
    await page.goto(url, { timeout: 30_000 });
    await page.waitForFunction(PAGE.ready, { timeout: 30_000 }).catch(() => {
      throw new Error(`the page did not get ready: ${errors.join('; ') || 'no error reported'}`);
    });
    const userAgent = String(await page.evaluate(PAGE.userAgent));
    const raw = await browser.version(); // e.g. "firefox/153.7.0esr"
    return {
      id: 'firefox',
      version: `Firefox ${raw.replace(/^firefox\//i, '')}`,
      jsVersion: '',
      userAgent,
      startMs: performance.now() - t0,
      run: async () =>
        parseRun(await withTimeout('firefox run()', 180_000, page.evaluate(PAGE.run)), 'firefox'),
      state: async (id, tick) =>
        String(await withTimeout('firefox state()', 60_000, page.evaluate(PAGE.state(id, tick)))),
      close: () => browser.close(),
    };
  } catch (e) {
    await browser.close();
    throw e;
  }
}
