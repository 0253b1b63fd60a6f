/**
 * The loss harness's own instruments (e2e/netem): the TCP model's in-order delivery with
 * retransmission timeouts, the UDP proxy's seeded drops and delays, and both proxies on real
 * sockets on 127.0.0.1. No browser, no coturn.
 */
import dgram from 'node:dgram';
import net from 'node:net';
import { afterEach, describe, expect, it } from 'vitest';
import { CLEAN, Dice, checkImpairment, type Impairment } from './netem/impair.js';
import { SegmentTimeline, startTcpProxy } from './netem/tcp-proxy.js';
import { startUdpProxy } from './netem/udp-proxy.js';

/** Dice whose losses follow a script (then none) and whose delay is the latency. */
class Scripted extends Dice {
  constructor(private readonly losses: boolean[]) {
    super(1);
  }
  override lost(): boolean {
    return this.losses.shift() ?? false;
  }
  override delay(c: Impairment): number {
    return c.latencyMs;
  }
}

const closers: (() => Promise<void> | void)[] = [];
afterEach(async () => {
  for (const f of closers.splice(0).reverse()) await f();
});

describe('TCP model', () => {
  const link: Impairment = { latencyMs: 100, jitterMs: 0, loss: 0.05 };

  it('a lost segment waits a retransmission timeout, and everything behind it waits too', () => {
    // Segment 2 is lost once, segment 4 twice (the timeout doubles: 300 + 600).
    const t = new SegmentTimeline(
      new Scripted(
        // Each segment asks until it is not lost: 1 | 2 (lost once) | 3 | 4 | 5 (twice) | 6.
        [false, true, false, false, false, true, true, false, false],
      ),
    );
    const sent = [0, 10, 20, 30, 1000, 1010];
    const at = sent.map((now) => t.deliveryTime(now, link, 300));
    expect(at).toEqual([100, 410, 410, 410, 1000 + 100 + 900, 1000 + 100 + 900]);
    expect(t.retransmissions).toBe(3);
  });

  it('delivers in order even when jitter would swap two segments', () => {
    const t = new SegmentTimeline(new Dice(5));
    const jittery: Impairment = { latencyMs: 100, jitterMs: 30, loss: 0 };
    let last = -Infinity;
    for (let k = 0; k < 1000; k++) {
      const at = t.deliveryTime(k, jittery, 300);
      expect(at).toBeGreaterThanOrEqual(last);
      expect(at).toBeLessThanOrEqual(k + 130);
      last = at;
    }
  });

  it('refuses impossible conditions, naming them', () => {
    expect(() => checkImpairment({ latencyMs: 10, jitterMs: 20, loss: 0 })).toThrow(
      /jitterMs must be from 0 to latencyMs, got 20/,
    );
    expect(() => checkImpairment({ latencyMs: 10, jitterMs: 0, loss: 1 })).toThrow(
      /loss must be in \[0, 1\), got 1/,
    );
    expect(() => checkImpairment({ ...CLEAN, latencyMs: Number.NaN })).toThrow(/latencyMs/);
  });

  it('the proxy passes a stream through in order on real sockets', async () => {
    const echo = net.createServer((s) => s.pipe(s));
    await new Promise<void>((resolve) => echo.listen(0, '127.0.0.1', resolve));
    closers.push(
      () =>
        new Promise<void>((resolve) => {
          echo.close(() => {
            resolve();
          });
        }),
    );
    const proxy = await startTcpProxy({
      targetPort: (echo.address() as net.AddressInfo).port,
      conditions: { latencyMs: 5, jitterMs: 5, loss: 0.2 },
      rtoMs: 10,
      seed: 3,
    });
    closers.push(() => proxy.close());
    const socket = net.connect(proxy.port, '127.0.0.1');
    closers.push(() => {
      socket.destroy();
    });
    const want = Buffer.from(Array.from({ length: 5000 }, (_v, i) => (i * 31) & 255));
    const chunks: Buffer[] = [];
    let got = 0;
    const done = new Promise<void>((resolve) => {
      socket.on('data', (d: Buffer) => {
        chunks.push(d);
        got += d.length;
        if (got >= want.length) resolve();
      });
    });
    // One write at a time, each after the last came back: each is its own segment.
    for (let at = 0; at < want.length; at += 100) {
      socket.write(want.subarray(at, at + 100));
      while (got < at + 100) await new Promise<void>((resolve) => setImmediate(resolve));
    }
    await done;
    expect(Buffer.concat(chunks).equals(want)).toBe(true);
    // Some segments were "lost" (held and delivered late), none was actually lost or reordered.
    const c = proxy.connections[0]!;
    expect(c.up.lost + c.down.lost).toBeGreaterThan(0);
  });
});

describe('UDP proxy', () => {
  it('drops the seeded share of datagrams and delays the rest within latency ± jitter', async () => {
    const target = dgram.createSocket('udp4');
    await new Promise<void>((resolve) => target.bind(0, '127.0.0.1', resolve));
    target.on('message', (msg, r) => {
      target.send(msg, r.port, r.address);
    });
    closers.push(
      () =>
        new Promise<void>((resolve) => {
          target.close(() => {
            resolve();
          });
        }),
    );
    const delays: number[] = [];
    const up: Impairment = { latencyMs: 100, jitterMs: 30, loss: 0.2 };
    const proxy = await startUdpProxy({
      targetPort: target.address().port,
      up,
      seed: 9,
      // Deliver at once, recording the delay asked for: the test does not wait on real time.
      schedule: (fn, ms) => {
        delays.push(ms);
        queueMicrotask(fn);
      },
    });
    closers.push(() => proxy.close());
    const client = dgram.createSocket('udp4');
    await new Promise<void>((resolve) => client.bind(0, '127.0.0.1', resolve));
    closers.push(() => {
      client.close();
    });
    const n = 1000;
    let echoed = 0;
    client.on('message', () => echoed++);
    // Ten at a time, each batch after the last came back (a burst would overflow the sockets'
    // receive buffers: a loss that is not the proxy's).
    const settled = (sent: number) => {
      const st = proxy.stats()[0];
      return st?.up.packets === sent && echoed === sent - st.up.lost;
    };
    for (let k = 0; k < n; k++) {
      client.send(Buffer.from([k & 255, k >> 8]), proxy.port, '127.0.0.1');
      if (k % 10 === 9) {
        for (let w = 0; w < 5000 && !settled(k + 1); w++) {
          await new Promise<void>((resolve) => setTimeout(resolve, 1));
        }
      }
    }
    const [s] = proxy.stats();
    expect(s!.up.packets).toBe(n);
    // About a fifth dropped (seeded: the same count every run), the rest echoed back.
    expect(s!.up.lost).toBeGreaterThan(150);
    expect(s!.up.lost).toBeLessThan(250);
    expect(echoed).toBe(n - s!.up.lost);
    expect(s!.down.lost).toBe(0);
    const upDelays = delays.filter((d) => d > 0);
    expect(upDelays).toHaveLength(n - s!.up.lost);
    expect(Math.min(...upDelays)).toBeGreaterThanOrEqual(70);
    expect(Math.max(...upDelays)).toBeLessThanOrEqual(130);
  });
});
