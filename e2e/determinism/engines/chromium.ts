/** Headless Chromium (V8) through playwright-core. */
import { chromium } from 'playwright-core';
import { CHROMIUM_ARGS } from '../../harness.js';
import { PAGE, parseRun, withTimeout, type EngineSession } from './session.js';

export async function openChromium(executablePath: string, url: string): Promise<EngineSession> {
  const t0 = performance.now();
  const browser = await chromium.launch({ executablePath, args: CHROMIUM_ARGS, timeout: 30_000 });
  try {
    const page = await browser.newPage();
    const errors: string[] = [];
    page.on('pageerror', (e) => errors.push(e.message));
    await page.goto(url, { timeout: 30_000 });
    await page.waitForFunction(PAGE.ready, undefined, { timeout: 30_000 }).catch(() => {
      throw new Error(`the page did not get ready: ${errors.join('; ') || 'no error reported'}`);
    });
    let jsVersion = '';
    try {
      const cdp = await browser.newBrowserCDPSession();
      const v = await cdp.send('Browser.getVersion');
      jsVersion = v.jsVersion ? `V8 ${v.jsVersion}` : '';
    } catch {
      // Not essential: the report then names only the browser version.
    }
    const userAgent = String(await page.evaluate(PAGE.userAgent));
    return {
      id: 'chromium',
      version: `Chromium ${browser.version()}`,
      jsVersion,
      userAgent,
      startMs: performance.now() - t0,
      run: async () =>
        parseRun(await withTimeout('chromium run()', 180_000, page.evaluate(PAGE.run)), 'chromium'),
      state: async (id, tick) =>
        String(await withTimeout('chromium state()', 60_000, page.evaluate(PAGE.state(id, tick)))),
      close: () => browser.close(),
    };
  } catch (e) {
    await browser.close();
    throw e;
  }
}
