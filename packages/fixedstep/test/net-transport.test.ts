import { describe, expect, it } from 'vitest';
import {
  ClockSync,
  EventScheduler,
  SimulatedLink,
  memoryPair,
  nodeWebSocketTransport,
  webSocketTransport,
  type NodeWebSocketLike,
} from 'fixedstep';

describe('EventScheduler', () => {
  it('runs events in time order, ties in scheduling order, moving the clock to each', () => {
    const s = new EventScheduler(100);
    const seen: string[] = [];
    s.at(130, () => seen.push(`c@${s.now}`));
    s.at(110, () => seen.push(`a@${s.now}`));
    s.at(110, () => seen.push(`b@${s.now}`));
    const cancelled = s.at(120, () => seen.push('never'));
    cancelled.cancel();
    s.at(50, () => seen.push(`past@${s.now}`)); // runs at once, at now
    s.runUntil(125);
    expect(seen).toEqual(['past@100', 'a@110', 'b@110']);
    expect(s.now).toBe(125);
    s.runUntil(1000);
    expect(seen.at(-1)).toBe('c@130');
  });

  it('repeats with a period that may change (a display that is throttled when hidden)', () => {
    const s = new EventScheduler();
    const times: number[] = [];
    let period = 10;
    const ev = s.every(
      () => period,
      () => {
        times.push(s.now);
        if (s.now >= 30) period = 100;
      },
    );
    s.runUntil(250);
    expect(times).toEqual([10, 20, 30, 130, 230]);
    ev.cancel();
    s.runUntil(1000);
    expect(times).toHaveLength(5);
  });

  it('runs until a condition holds or the limit passes', () => {
    const s = new EventScheduler();
    let n = 0;
    s.every(5, () => n++);
    expect(s.runUntilDone(() => n >= 10, 1000)).toBe(true);
    expect(s.now).toBe(50);
    expect(s.runUntilDone(() => n >= 1e9, 100)).toBe(false);
    expect(s.now).toBe(150);
  });
});

describe('memoryPair', () => {
  it('delivers in order on a later microtask and closes both ends', async () => {
    const [a, b] = memoryPair();
    const got: number[] = [];
    let closed = '';
    b.onMessage((m) => got.push(m[0]!));
    b.onClose((r) => (closed = r));
    const buf = Uint8Array.of(1);
    a.send(buf);
    buf[0] = 9; // the sender may reuse its buffer
    a.send(Uint8Array.of(2));
    expect(got).toEqual([]); // never re-entrant
    await Promise.resolve();
    await Promise.resolve();
    expect(got).toEqual([1, 2]);
    a.close('bye');
    await Promise.resolve();
    expect(closed).toBe('bye');
    expect(b.isOpen).toBe(false);
    b.send(Uint8Array.of(3)); // ignored once closed
  });
});

describe('SimulatedLink', () => {
  function measure(options: ConstructorParameters<typeof SimulatedLink>[0]['seed']) {
    const scheduler = new EventScheduler();
    const link = new SimulatedLink({
      scheduler,
      latencyMs: 100,
      jitterMs: 30,
      loss: 0.05,
      seed: options,
    });
    const delays: number[] = [];
    const order: number[] = [];
    link.b.onMessage((m) => {
      const sentAt = new DataView(m.buffer, m.byteOffset).getFloat64(0);
      delays.push(scheduler.now - sentAt);
      order.push(new DataView(m.buffer, m.byteOffset).getUint32(8));
    });
    for (let i = 0; i < 20000; i++) {
      scheduler.at(i, () => {
        const m = new Uint8Array(12);
        new DataView(m.buffer).setFloat64(0, scheduler.now);
        new DataView(m.buffer).setUint32(8, i);
        link.a.send(m);
      });
    }
    scheduler.runUntil(30_000);
    return { delays, order, stats: link.stats[0] };
  }

  it('has the seeded latency, jitter and loss it was given, repeatably', () => {
    const r = measure(7);
    const mean = r.delays.reduce((a, b) => a + b, 0) / r.delays.length;
    expect(Math.min(...r.delays)).toBeGreaterThanOrEqual(70);
    expect(Math.max(...r.delays)).toBeLessThanOrEqual(130);
    expect(mean).toBeCloseTo(100, 0);
    expect(r.stats.lost / r.stats.sent).toBeGreaterThan(0.045);
    expect(r.stats.lost / r.stats.sent).toBeLessThan(0.055);
    expect(r.stats.delivered + r.stats.lost).toBe(r.stats.sent);
    // Datagrams overtake each other under jitter.
    expect(r.order.some((v, i) => i > 0 && v < r.order[i - 1]!)).toBe(true);
    // Same seed, same run.
    expect(measure(7).delays).toEqual(r.delays);
    expect(measure(8).delays).not.toEqual(r.delays);
  });

  it('keeps send order when ordered, and delivers a close after the latency', () => {
    const scheduler = new EventScheduler();
    const link = new SimulatedLink({ scheduler, latencyMs: 50, jitterMs: 40, ordered: true });
    const got: number[] = [];
    let closedAt = -1;
    link.b.onMessage((m) => got.push(m[0]!));
    link.b.onClose(() => (closedAt = scheduler.now));
    for (let i = 0; i < 100; i++) link.a.send(Uint8Array.of(i));
    link.a.close();
    scheduler.runUntil(1000);
    expect(got).toEqual(Array.from({ length: 100 }, (_, i) => i));
    expect(closedAt).toBeGreaterThanOrEqual(50);
    expect(link.b.isOpen).toBe(false);
  });

  it('retransmits a lost message of a stream a round trip later, and holds everything behind it', () => {
    const scheduler = new EventScheduler();
    const link = new SimulatedLink({
      scheduler,
      latencyMs: 50,
      loss: 0.2,
      ordered: true,
      retransmit: true,
    });
    const arrived: number[] = [];
    const order: number[] = [];
    link.b.onMessage((m) => {
      order.push(m[0]!);
      arrived[m[0]!] = scheduler.now;
    });
    // One message every 10 ms.
    for (let i = 0; i < 200; i++)
      scheduler.at(i * 10, () => {
        link.a.send(Uint8Array.of(i));
      });
    scheduler.runUntil(10_000);
    // Nothing is lost, nothing overtakes.
    expect(order).toEqual(Array.from({ length: 200 }, (_, i) => i));
    expect(link.stats[0].lost).toBeGreaterThan(20);
    const delays = arrived.map((t, i) => t - i * 10);
    // A lost one waits a round trip (100 ms) more, at least; ones behind it wait with it.
    expect(Math.max(...delays)).toBeGreaterThanOrEqual(150);
    expect(delays.filter((d) => d > 50).length).toBeGreaterThan(link.stats[0].lost);
    expect(() => new SimulatedLink({ scheduler, retransmit: true })).toThrow(
      /retransmit needs ordered/,
    );
  });

  it('changes conditions per direction', () => {
    const scheduler = new EventScheduler();
    const link = new SimulatedLink({ scheduler, latencyMs: 10 });
    link.setConditions({ loss: 1 }, 1);
    let ab = 0;
    let ba = 0;
    link.b.onMessage(() => ab++);
    link.a.onMessage(() => ba++);
    link.a.send(Uint8Array.of(1));
    link.b.send(Uint8Array.of(1));
    scheduler.runUntil(100);
    expect([ab, ba]).toEqual([1, 0]);
    expect(() => {
      link.setConditions({ loss: 2 });
    }).toThrow(RangeError);
  });
});

describe('ClockSync', () => {
  it('trusts the sample with the smallest round trip (NTP min-RTT filter)', () => {
    const c = new ClockSync(8);
    const offset = 5000; // server = client + 5000
    // Symmetric 40 ms round trip: exact.
    c.addSample(0, 20 + offset, 40);
    expect(c.offset).toBe(offset);
    // A pong that sat 300 ms in a throttled background tab before it was handled: its estimate
    // is off by 150 ms, but its round trip is long, so it is not trusted.
    c.addSample(100, 120 + offset, 440);
    expect(c.offset).toBe(offset);
    expect(c.rtt).toBe(40);
    expect(c.rttHigh).toBe(340);
    expect(c.serverTime(1000)).toBe(1000 + offset);
  });

  it('never runs the estimate backwards', () => {
    const c = new ClockSync(4);
    c.addSample(0, 1100, 100); // offset 1050
    expect(c.serverTime(200)).toBe(1250);
    c.addSample(200, 1200, 210); // better sample: offset 995
    expect(c.serverTime(201)).toBe(1250); // held still …
    expect(c.serverTime(300)).toBe(1295); // … until the clock catches up
    expect(c.addSample(10, 0, 5)).toBe(false); // received before sent: ignored
  });

  it('forgets old samples (a route that got slower is followed)', () => {
    const c = new ClockSync(4);
    c.addSample(0, 10, 20);
    for (let i = 1; i <= 4; i++) c.addSample(i * 1000, i * 1000 + 50, i * 1000 + 100);
    expect(c.rtt).toBe(100);
  });
});

describe('WebSocket adapters', () => {
  it('browser: binary frames, queued sends until open, text closes', () => {
    const listeners = new Map<string, ((e: unknown) => void)[]>();
    const sent: Uint8Array[] = [];
    const fake = {
      binaryType: 'blob',
      readyState: 0,
      bufferedAmount: 0,
      send: (b: Uint8Array) => sent.push(b),
      close: () => {
        fake.readyState = 3;
      },
      addEventListener: (type: string, l: (e: unknown) => void) => {
        listeners.set(type, [...(listeners.get(type) ?? []), l]);
      },
    };
    const fire = (type: string, e: unknown) =>
      listeners.get(type)?.forEach((l) => {
        l(e);
      });
    const t = webSocketTransport(fake as unknown as WebSocket);
    expect(fake.binaryType).toBe('arraybuffer');
    const got: number[] = [];
    t.onMessage((m) => got.push(...m));
    t.send(Uint8Array.of(1, 2));
    expect(sent).toHaveLength(0);
    fake.readyState = 1;
    fire('open', {});
    expect(sent.map((b) => [...b])).toEqual([[1, 2]]);
    fire('message', { data: Uint8Array.of(7, 8).buffer });
    expect(got).toEqual([7, 8]);
    let reason = '';
    t.onClose((r) => (reason = r));
    fire('message', { data: 'text' });
    expect(reason).toBe('text message on a binary protocol');
    expect(t.isOpen).toBe(false);
  });

  it('node ws: binary frames (Buffer, ArrayBuffer, fragments), backpressure closes', () => {
    const handlers = new Map<string, (...a: unknown[]) => void>();
    const sent: Uint8Array[] = [];
    const fake = {
      readyState: 1,
      bufferedAmount: 0,
      send: (b: Uint8Array) => sent.push(b),
      close: () => undefined,
      on: (event: string, l: (...a: unknown[]) => void) => {
        handlers.set(event, l);
        return fake;
      },
    };
    const t = nodeWebSocketTransport(fake as unknown as NodeWebSocketLike, {
      maxBufferedBytes: 10,
    });
    const got: number[][] = [];
    t.onMessage((m) => got.push([...m]));
    handlers.get('message')!(Uint8Array.of(1), true);
    handlers.get('message')!(Uint8Array.of(2, 3).buffer, true);
    handlers.get('message')!([Uint8Array.of(4), Uint8Array.of(5)], true);
    expect(got).toEqual([[1], [2, 3], [4, 5]]);
    t.send(Uint8Array.of(9));
    expect(sent).toHaveLength(1);
    fake.bufferedAmount = 11;
    let reason = '';
    t.onClose((r) => (reason = r));
    t.send(Uint8Array.of(9));
    expect(reason).toBe('send buffer overflow');
  });
});
