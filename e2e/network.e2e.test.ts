/**
 * Chapter 6 in a real browser: state sync, lockstep and rollback over a simulated link agree on
 * the state hash and are compared in one table; then two pages play one room through the server —
 * state sync through its worker rooms, lockstep through its relay — and agree on the world.
 */
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import type { Page } from 'playwright-core';
import { attachRelay } from '../packages/server/src/relay/endpoint.js';
import { attachStateSync } from '../packages/server/src/state-sync/index.js';
import {
  horizontalOverflow,
  num,
  phonePage,
  readouts,
  readoutsOnceHashed,
  realClockRuns,
  shots,
  skip,
  useLab,
  useLabWith,
  watch,
} from './harness.js';

const lab = useLab();

describe('chapter 6, network', () => {
  it('state sync, lockstep and rollback agree on the hashes over a lossy, late link', async () => {
    const page = await lab.browser.newPage({ viewport: { width: 1440, height: 900 } });
    const problems = watch(page);
    await page.goto(`${lab.server.url}#/network`);
    await expect.poll(() => page.title()).toBe('6. Network — fixedstep lab');
    await page.getByTestId('readout-lockstep-hashes-equal').waitFor();
    await page.getByTestId('control-pause').click();
    await page.getByTestId('control-restart').click();
    await expect.poll(() => page.getByTestId('readout-clock').getAttribute('data-value')).toBe('0');
    // 120 ms ± 30 ms, 5 % loss.
    await page.getByTestId('control-latency').fill('120');
    await page.getByTestId('control-jitter').fill('30');
    await page.getByTestId('control-loss').fill('5');
    await skip(page, 2);
    const r = await readouts(page);
    for (const mode of ['statesync', 'lockstep', 'rollback']) {
      expect(r[`readout-${mode}-hashes-equal`]).toBe('true');
      expect(r[`readout-${mode}-hash-1`]).toMatch(/^[0-9a-f]{16}$/);
      expect(r[`readout-${mode}-hash-1`]).toBe(r[`readout-${mode}-hash-2`]);
      expect(num(r, `${mode}-checkpoint`)).toBeGreaterThanOrEqual(480);
      expect(num(r, `${mode}-lost`)).toBeGreaterThan(0);
    }
    expect(num(r, 'lockstep-input-delay')).toBeGreaterThanOrEqual(10);
    expect(num(r, 'rollback-rollbacks')).toBeGreaterThan(0);
    expect(num(r, 'rollback-max-depth')).toBeGreaterThan(0);
    expect(num(r, 'statesync-render-delay')).toBeGreaterThan(120);
    expect(num(r, 'statesync-snapshots')).toBeGreaterThan(100);
    // The comparison: state sync shows your input at once, lockstep a round trip later; the
    // world costs more bytes than the inputs; lockstep never corrects.
    expect(num(r, 'compare-statesync-own')).toBeLessThan(17);
    expect(num(r, 'compare-lockstep-own')).toBeGreaterThan(150);
    expect(num(r, 'compare-statesync-down')).toBeGreaterThan(num(r, 'compare-lockstep-down'));
    expect(num(r, 'compare-lockstep-corrections')).toBe(0);
    expect(await page.getByTestId('when-to-use').textContent()).toContain('State sync when');
    // Under it, the bench's rows over real WebRTC and real TCP, labelled as the bench's.
    const measured = page.getByTestId('net-measured');
    expect(await measured.textContent()).toContain('Measured by the benchmark, not in this page');
    expect(await measured.locator('tbody tr').count()).toBe(6);
    expect(await measured.locator('tbody tr').first().textContent()).toContain('WebRTC');
    await page.screenshot({ path: path.join(shots, 'network.png'), fullPage: true });
    expect(problems).toEqual([]);
    await page.close();
  });

  it('runs on the real clock and fits a phone screen', async () => {
    const { context, page, problems } = await phonePage(lab.browser);
    await page.goto(`${lab.server.url}#/network?room=phone-room`);
    await page.getByTestId('readout-lockstep-hashes-equal').waitFor();
    await page.getByTestId('control-pause').click();
    await page.getByTestId('control-restart').click();
    // Both machines on this page's animation frames for 2.5 s: they reach checkpoints and agree.
    await realClockRuns(page, 2500);
    const r = await readouts(page);
    for (const mode of ['statesync', 'lockstep', 'rollback']) {
      expect(num(r, `${mode}-checkpoint`)).toBeGreaterThanOrEqual(60);
      expect(r[`readout-${mode}-hashes-equal`]).toBe('true');
    }
    // Offline, the online panel says what to do and links the room for a second tab.
    expect(await page.getByTestId('readout-online-state').getAttribute('data-value')).toBe(
      'offline',
    );
    expect(await page.getByTestId('link-room-tab').getAttribute('href')).toBe(
      '#/network?room=phone-room&join=1',
    );
    // …on its canvas, drawn when it was laid out (nothing redraws it per frame): text pixels.
    const lit = await page.getByTestId('canvas-online').evaluate((el) => {
      const c = el as HTMLCanvasElement;
      const d = c.getContext('2d')!.getImageData(0, 0, c.width, c.height).data;
      let n = 0;
      for (let i = 0; i < d.length; i += 4) if (d[i]! + d[i + 1]! + d[i + 2]! > 300) n++;
      return n;
    });
    expect(lit).toBeGreaterThan(500);
    await page.screenshot({ path: path.join(shots, 'network-phone.png'), fullPage: true });
    expect(await horizontalOverflow(page)).toBe(0);
    expect(problems).toEqual([]);
    await context.close();
  });

  it('charts the loss harness’s recorded WebRTC and WebSocket rows, on a desktop and a phone', async () => {
    const report = JSON.parse(
      readFileSync(
        new URL('../apps/lab/src/chapters/network/data/loss-harness.json', import.meta.url),
        'utf8',
      ),
    ) as { rows: Record<string, unknown>[] };
    const check = async (page: Page, name: string) => {
      await page.goto(`${lab.server.url}#/network`);
      const panel = page.getByTestId('net-transports');
      await panel.scrollIntoViewIfNeeded();
      const r = await readouts(page);
      for (const row of report.rows) {
        const id = String(row.transport).toLowerCase();
        for (const [key, field] of [
          ['p50', 'latencyP50'],
          ['p99', 'latencyP99'],
          ['stalls', 'stalls'],
          ['stall-frames', 'stallFrames'],
          ['rollbacks', 'rollbacks'],
          ['max-depth', 'maxDepth'],
        ] as const) {
          expect(num(r, `transport-${id}-${key}`), `${id} ${key}`).toBe(row[field]);
        }
        expect(r[`readout-transport-${id}-hashes-equal`]).toBe('true');
      }
      // TCP's retransmission timeouts: far more stalled frames and a far longer tail.
      expect(num(r, 'transport-websocket-stall-frames')).toBeGreaterThan(
        num(r, 'transport-webrtc-stall-frames'),
      );
      expect(num(r, 'transport-websocket-p99')).toBeGreaterThan(num(r, 'transport-webrtc-p99'));
      expect(await page.getByTestId('net-transports-source').textContent()).toContain(
        'npx vitest run --config e2e/vitest.config.ts e2e/netem.e2e.test.ts',
      );
      // Over WebSocket the rollbacks pile up at the prediction window's end (30 ticks).
      const ws = report.rows.find((x) => x.transport === 'WebSocket')!;
      const full = (ws.depths as Record<string, number>)['30'];
      expect(await page.getByTestId('net-transports-depth-note').textContent()).toContain(
        `WebSocket: ${full} rollbacks of ${String(ws.rollbacks)} reached 30 ticks`,
      );
      // The depth chart was drawn (uPlot's canvas has a size).
      const width = await panel
        .locator('canvas')
        .first()
        .evaluate((c) => c.clientWidth);
      expect(width).toBeGreaterThan(200);
      await panel.screenshot({ path: path.join(shots, name) });
    };
    const page = await lab.browser.newPage({ viewport: { width: 1440, height: 900 } });
    const problems = watch(page);
    await check(page, 'network-transports.png');
    expect(problems).toEqual([]);
    await page.close();
    const phone = await phonePage(lab.browser);
    await check(phone.page, 'network-transports-phone.png');
    expect(await horizontalOverflow(phone.page)).toBe(0);
    expect(phone.problems).toEqual([]);
    await phone.context.close();
  });

  it('shows lag compensation: the server confirms the shots that hit on screen when it judges them as seen', async () => {
    const page = await lab.browser.newPage({ viewport: { width: 1440, height: 900 } });
    const problems = watch(page);
    await page.goto(`${lab.server.url}#/network`);
    const panel = page.getByTestId('net-lag');
    await panel.scrollIntoViewIfNeeded();
    await page.getByTestId('lag-run').click();
    await expect
      .poll(async () => (await readouts(page))['readout-lag-confirmed-compensated'], {
        timeout: 30_000,
      })
      .not.toBe('');
    const r = await readouts(page);
    expect(num(r, 'lag-screen-hits')).toBeGreaterThan(50);
    expect(num(r, 'lag-confirmed-compensated')).toBeGreaterThanOrEqual(0.99);
    expect(num(r, 'lag-confirmed-plain')).toBeLessThan(0.2);
    await panel.screenshot({ path: path.join(shots, 'network-lag.png') });
    expect(problems).toEqual([]);
    await page.close();
  });
});

describe('chapter 6, play online', () => {
  const online = useLabWith(async (s) => {
    const relay = attachRelay(s.server);
    const stateSync = attachStateSync(s.server, { workers: 1 });
    await stateSync.ready;
    return [relay, stateSync];
  });

  it('two pages play state sync through the server’s worker rooms and get the same world', async () => {
    const pages = await Promise.all([0, 1].map(() => online.browser.newPage()));
    const problems = pages.map((p) => watch(p));
    // The first joins with the button; the second opens the first's "new tab" link, which joins.
    await pages[0]!.goto(`${online.server.url}#/network?state=e2e-state&at=300`);
    const link = await pages[0]!.getByTestId('link-state-room-tab').getAttribute('href');
    expect(link).toBe('#/network?state=e2e-state&at=300');
    await pages[1]!.goto(`${online.server.url}${link}`);
    const got = await readoutsOnceHashed(pages, 'readout-state-online-hash-at', 60_000);
    // Both received the server's world of tick 300, byte for byte.
    expect(got[0]!['readout-state-online-hash-at']).toBe(got[1]!['readout-state-online-hash-at']);
    expect(new Set(got.map((r) => r['readout-state-online-slot']))).toEqual(new Set(['1', '2']));
    for (const r of got) {
      expect(r['readout-state-online-state']).toBe('running');
      expect(num(r, 'state-online-snapshot')).toBeGreaterThanOrEqual(300);
      // Each predicts its own player ahead of the newest snapshot.
      expect(num(r, 'state-online-tick')).toBeGreaterThan(num(r, 'state-online-snapshot'));
    }
    await pages[0]!.screenshot({
      path: path.join(shots, 'network-state-online.png'),
      fullPage: true,
    });
    expect(problems).toEqual([[], []]);
    for (const p of pages) await p.close();
  });

  it('two pages play one room through the relay and agree on the final hash', async () => {
    const ticks = 360;
    const pages = await Promise.all([0, 1].map(() => online.browser.newPage()));
    const problems = pages.map((p) => watch(p));
    // The first joins with the button; the second opens the first's "new tab" link, which joins.
    await pages[0]!.goto(`${online.server.url}#/network?room=e2e-room&ticks=${ticks}`);
    await pages[0]!.getByTestId('control-join').click();
    const link = await pages[0]!.getByTestId('link-room-tab').getAttribute('href');
    expect(link).toBe(`#/network?room=e2e-room&ticks=${ticks}&join=1`);
    await pages[1]!.goto(`${online.server.url}${link}`);
    const finals = await readoutsOnceHashed(pages, 'readout-online-final-hash', 60_000);
    expect(finals[0]!['readout-online-final-hash']).toBe(finals[1]!['readout-online-final-hash']);
    expect(new Set(finals.map((r) => r['readout-online-slot']))).toEqual(new Set(['1', '2']));
    for (const r of finals) expect(num(r, 'online-desyncs')).toBe(0);
    await pages[1]!.screenshot({ path: path.join(shots, 'network-online.png'), fullPage: true });
    expect(problems).toEqual([[], []]);
    for (const p of pages) await p.close();
  });
});
