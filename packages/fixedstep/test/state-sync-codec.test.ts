/**
 * The state-sync wire format and its delta coding, and what a client does with bytes it cannot
 * trust: a damaged or hostile snapshot or delta gives a clear error and a resync request, never a
 * crash or a silently wrong world.
 */
import { describe, expect, it } from 'vitest';
import fc from 'fast-check';
import {
  DEFAULT_STATE_SYNC_LIMITS,
  EventScheduler,
  ProtocolError,
  Random,
  SimulatedLink,
  StateSyncSession,
  applyDelta,
  decodeMessage,
  decodeStateSyncMessage,
  deltaBytes,
  encodeMessage,
  encodeStateSyncMessage,
  fnv1a64,
  hex64,
  peekStateSyncType,
  type ButtonInput,
  type StateSyncEvent,
  type StateSyncMessage,
  type Transport,
} from 'fixedstep';
import { ARENA_RENDER, Arena, World, arenaGame } from './state-sync-fixture.js';

/**
 * Runs `f`: `'ok'` when it returns (and its bytes equal `want`, if given), `'refused'` for a
 * ProtocolError, and what went wrong otherwise.
 */
function outcome(f: () => Uint8Array, want?: Uint8Array): string {
  try {
    const got = f();
    if (want === undefined) return 'ok';
    return got.length === want.length && got.every((b, i) => b === want[i])
      ? 'ok'
      : 'not canonical';
  } catch (e) {
    return e instanceof ProtocolError ? 'refused' : `threw ${String(e)}`;
  }
}

describe('state-sync messages', () => {
  // Their round trip and fuzz follow from the declaration (net-wire.test.ts); here, the rules of
  // state sync's own.
  it('and the relay’s protocol refuse each other’s messages, naming the other', () => {
    const ours = encodeStateSyncMessage({ type: 'ping', id: 1, time: 5 });
    expect(() => decodeMessage(ours)).toThrow(
      /BAD_VERSION: relay: a state sync message, not relay/,
    );
    const relays = encodeMessage({ type: 'ping', id: 1, time: 5 });
    expect(() => decodeStateSyncMessage(relays)).toThrow(
      /BAD_VERSION: state sync: a relay message, not state sync/,
    );
  });

  it('are refused before anything is allocated when a size is above the limits', () => {
    const snapshot: StateSyncMessage = {
      type: 'snapshot',
      tick: 303,
      base: 300,
      older: -1,
      sendDelayUs: 0,
      inputAck: 303,
      filled: 0,
      late: 0,
      slack: 0,
      codec: 'bytes',
      size: 1 << 20,
      hash: 1n,
      payload: Uint8Array.of(2, 1, 9),
    };
    const bytes = encodeStateSyncMessage(snapshot);
    expect(decodeStateSyncMessage(bytes).type).toBe('snapshot');
    expect(() =>
      decodeStateSyncMessage(bytes, { ...DEFAULT_STATE_SYNC_LIMITS, maxStateBytes: 4096 }),
    ).toThrow(/TOO_LARGE: state sync snapshot.size: 1048576, at most 4096 \(at byte \d+\)/);
    const inputs = encodeStateSyncMessage({
      type: 'input',
      player: 0,
      ack: 0,
      tick: 0,
      words: 1,
      inputs: new Uint32Array(64),
    });
    expect(() =>
      decodeStateSyncMessage(inputs, { ...DEFAULT_STATE_SYNC_LIMITS, maxInputTicks: 63 }),
    ).toThrow(/TOO_LARGE: state sync input.inputs: inputs rows is 64, at most 63/);
    expect(() =>
      encodeStateSyncMessage({
        type: 'input',
        player: 0,
        ack: 0,
        tick: 0,
        words: 1,
        inputs: new Uint32Array(65),
      }),
    ).toThrow(/cannot encode input\.inputs: 65 words is not 1 to 64 rows of 1/);
  });
});

describe('delta coding', () => {
  const state = fc.uint8Array({ minLength: 0, maxLength: 600 });
  const edits = fc.array(fc.tuple(fc.nat(), fc.integer({ min: 0, max: 255 })), { maxLength: 40 });

  it('rebuilds the next state from the base, for any pair', () => {
    fc.assert(
      fc.property(state, edits, fc.integer({ min: -20, max: 20 }), (base, changes, grow) => {
        const next = new Uint8Array(Math.max(0, base.length + grow));
        next.set(base.subarray(0, next.length));
        for (const [i, v] of changes) if (next.length > 0) next[i % next.length] = v;
        const d = deltaBytes(base, next);
        expect(applyDelta(base, d, next.length)).toEqual(next);
        // The same from arrays that do not start on a 4-byte boundary (the byte-wise path).
        const shifted = (a: Uint8Array, by: number) => {
          const buf = new Uint8Array(a.length + by);
          buf.set(a, by);
          return buf.subarray(by);
        };
        expect(deltaBytes(shifted(base, 1), shifted(next, 3))).toEqual(d);
      }),
      { numRuns: 2000, seed: 5 },
    );
  });

  it('costs nothing for equal states and a few bytes for a small change', () => {
    const base = Uint8Array.from({ length: 4000 }, (_, i) => (i * 31) & 0xff);
    expect(deltaBytes(base, base).length).toBe(0);
    const next = base.slice();
    next[1000] = next[1000]! ^ 1;
    next[1001] = next[1001]! ^ 4;
    next[3000] = next[3000]! ^ 0x80;
    // Two runs: (skip 1000, count 2, 2 bytes) and (skip 1998, count 1, 1 byte).
    expect(Array.from(deltaBytes(base, next))).toEqual([0xe8, 0x07, 2, 1, 4, 0xce, 0x0f, 1, 0x80]);
  });

  it('refuses runs that reach past the state, are empty or are cut short, with a ProtocolError', () => {
    const base = new Uint8Array(10);
    expect(() => applyDelta(base, Uint8Array.of(8, 3, 1, 1, 1), 10)).toThrow(
      /TOO_LARGE: state sync snapshot.payload \(delta\): a delta run ends at 11, past the 10-byte state/,
    );
    expect(() => applyDelta(base, Uint8Array.of(0, 0), 10)).toThrow(
      /BAD_VALUE: state sync snapshot.payload \(delta\): delta run length is 0, at least 1/,
    );
    expect(() => applyDelta(base, Uint8Array.of(0, 4, 1), 10)).toThrow(
      /TRUNCATED: state sync snapshot.payload \(delta\): delta run needs 4 bytes, 1 left/,
    );
    fc.assert(
      fc.property(fc.uint8Array({ maxLength: 40 }), fc.integer({ min: 0, max: 64 }), (d, size) => {
        const rebuilt = outcome(() => applyDelta(base, d, size));
        expect(['ok', 'refused']).toContain(rebuilt);
      }),
      { numRuns: 2000, seed: 8 },
    );
  });

  it('applied to the wrong base gives a state whose hash is not the server’s', () => {
    const a = new Arena(2, 1);
    const s0 = a.save();
    a.step([2, 0]);
    a.step([2, 0]);
    a.step([2, 0]);
    const s3 = a.save();
    a.step([8, 1]);
    a.step([8, 1]);
    a.step([8, 1]);
    const s6 = a.save();
    const d = deltaBytes(s3, s6);
    expect(fnv1a64(applyDelta(s3, d, s6.length))).toBe(fnv1a64(s6));
    const wrong = applyDelta(s0, d, s6.length);
    expect(wrong.length).toBe(s6.length);
    expect(hex64(fnv1a64(wrong))).not.toBe(hex64(fnv1a64(s6)));
  });
});

/** A hand-driven server on a simulated link: what it sends, the client gets; what the client sends is kept. */
class FakeServer {
  readonly scheduler = new EventScheduler(0);
  readonly link = new SimulatedLink({ scheduler: this.scheduler, latencyMs: 1 });
  readonly received: StateSyncMessage[] = [];
  readonly events: StateSyncEvent[] = [];
  readonly session: StateSyncSession<ButtonInput, Arena>;
  readonly sim = new Arena(2, 7);
  private readonly server: Transport = this.link.b;

  constructor() {
    this.server.onMessage((b) => this.received.push(decodeStateSyncMessage(b)));
    this.session = new StateSyncSession<ButtonInput, Arena>({
      transport: this.link.a,
      clock: this.scheduler.clock,
      room: 'r',
      game: arenaGame(),
      render: ARENA_RENDER,
      onEvent: (e) => this.events.push(e),
    });
    this.send({
      type: 'welcome',
      slot: 0,
      players: 2,
      seed: 7,
      tickRate: 60,
      snapshotEvery: 3,
      startAt: 0,
      inputFrom: 0,
      config: new Uint8Array(0),
      token: new Uint8Array(16),
      invite: new Uint8Array(16),
    });
    this.settle();
  }

  send(m: StateSyncMessage): void {
    this.server.send(encodeStateSyncMessage(m));
  }

  sendBytes(b: Uint8Array): void {
    this.server.send(b);
  }

  /** The state after three more steps, and its tick. */
  advance(): { tick: number; state: Uint8Array } {
    for (let i = 0; i < 3; i++) this.sim.step([2, 8]);
    return { tick: this.sim.tick, state: this.sim.save() };
  }

  snapshot(
    tick: number,
    state: Uint8Array,
    base?: { tick: number; state: Uint8Array },
  ): StateSyncMessage {
    return {
      type: 'snapshot',
      tick,
      base: base ? base.tick : -1,
      older: -1,
      sendDelayUs: 0,
      inputAck: tick,
      filled: 0,
      late: 0,
      slack: 0,
      codec: 'bytes',
      size: state.length,
      hash: fnv1a64(state),
      payload: base ? deltaBytes(base.state, state) : state,
    };
  }

  settle(): void {
    this.scheduler.runFor(5);
    this.session.frame(this.scheduler.now);
  }

  resyncs(): string[] {
    return this.received.flatMap((m) => (m.type === 'resync' ? [m.reason] : []));
  }
}

describe('a client and bytes it cannot trust', () => {
  it('a delta made against another base is detected by the hash, asks for a resync and changes nothing', () => {
    const f = new FakeServer();
    const s0 = { tick: 0, state: f.sim.save() };
    f.send(f.snapshot(0, s0.state));
    f.settle();
    const s3 = f.advance();
    f.send(f.snapshot(s3.tick, s3.state, s0));
    f.settle();
    expect(f.session.snapshotTick).toBe(3);
    const s6 = f.advance();
    // A delta 3 → 6, labelled as one against tick 0 (which the client also holds).
    const lie = f.snapshot(s6.tick, s6.state, s3);
    f.send({ ...lie, base: 0 } as StateSyncMessage);
    f.settle();
    expect(f.session.snapshotTick).toBe(3);
    expect(hex64(fnv1a64(f.session.snapshotState!))).toBe(hex64(fnv1a64(s3.state)));
    expect(f.resyncs()).toEqual(['hash-mismatch']);
    const bad = f.events.filter((e) => e.type === 'bad-snapshot');
    expect(bad).toEqual([
      {
        type: 'bad-snapshot',
        reason: 'hash-mismatch',
        tick: 6,
        message:
          "the state rebuilt for tick 6 does not have the server's hash (a damaged delta, or the wrong base)",
      },
    ]);
    // The right delta then applies.
    f.send(lie);
    f.settle();
    expect(f.session.snapshotTick).toBe(6);
    expect(f.session.stats.badSnapshots).toBe(1);
  });

  it('a delta against a base it never had, and a state the game refuses, ask for a resync too', () => {
    const f = new FakeServer();
    const s0 = { tick: 0, state: f.sim.save() };
    f.send(f.snapshot(0, s0.state));
    f.settle();
    const s3 = f.advance();
    f.send(f.snapshot(s3.tick, s3.state, { tick: 2, state: s0.state }));
    f.settle();
    // A full snapshot whose bytes hash right but that the game cannot load (a NaN position).
    const broken = s3.state.slice();
    broken.fill(0xff, broken.length - 8);
    f.send(f.snapshot(s3.tick, broken));
    f.settle();
    // One from another room's game: it loads, but at another tick than it says.
    const other = new Arena(2, 7);
    other.step([0, 0]);
    f.send(f.snapshot(9, other.save()));
    f.settle();
    expect(f.resyncs()).toEqual(['no-base', 'unloadable', 'unloadable']);
    const messages = f.events.flatMap((e) => (e.type === 'bad-snapshot' ? [e.message] : []));
    expect(messages).toEqual([
      'no snapshot of tick 2 here to apply a delta to',
      'the game refused the state: disc 1 is not finite',
      'the state is at tick 1, the snapshot says 9',
    ]);
    expect(f.session.snapshotTick).toBe(0);
  });

  it('survives a stream of damaged deltas: every state it holds is the server’s, and it recovers', () => {
    const w = new World(arenaGame(), { latencyMs: 40, jitterMs: 10, loss: 0.02 });
    const rng = new Random(2024);
    let damaged = 0;
    // Between the server and client 0, one snapshot in five is damaged: bytes flipped, cut short,
    // or stretched.
    const link = new SimulatedLink({
      scheduler: w.scheduler,
      seed: 77,
      latencyMs: 40,
      jitterMs: 10,
      loss: 0.02,
    });
    const inner = link.a;
    const tampered: Transport = {
      send: (b) => {
        inner.send(b);
      },
      onMessage: (handler) => {
        inner.onMessage((b) => {
          if (peekStateSyncType(b) !== 'snapshot' || rng.int(5) !== 0) {
            handler(b);
            return;
          }
          damaged++;
          const out = b.slice();
          const how = rng.int(3);
          for (let k = 0; how === 0 && k < 1 + rng.int(3); k++) {
            const at = rng.int(out.length);
            out[at] = out[at]! ^ (1 << rng.int(8));
          }
          if (how === 1) handler(out.subarray(0, rng.int(out.length)));
          else if (how === 2) handler(Uint8Array.from([...out, rng.int(256)]));
          else handler(out);
        });
      },
      onClose: (h) => {
        inner.onClose(h);
      },
      close: (r) => {
        inner.close(r);
      },
      get isOpen() {
        return inner.isOpen;
      },
    };
    w.room.accept(link.b);
    const s = new StateSyncSession<ButtonInput, Arena>({
      transport: tampered,
      clock: w.scheduler.clock,
      room: 'r',
      game: arenaGame(),
      render: ARENA_RENDER,
    });
    const history = w.room.simulation.history!;
    let checks = 0;
    w.scheduler.every(1000 / 60, () => {
      s.frame(w.scheduler.now);
      s.render(w.scheduler.now);
      const state = s.snapshotState;
      if (!state) return;
      expect(hex64(fnv1a64(state))).toBe(hex64(history.get(s.snapshotTick)!));
      checks++;
    });
    w.run(20_000);
    expect(damaged).toBeGreaterThan(50);
    expect(checks).toBeGreaterThan(1000);
    // Damage was caught — as bytes that do not decode, or a delta or hash that does not add up —
    // and every caught snapshot asked the server for a whole one.
    expect(s.stats.badMessages + s.stats.badSnapshots).toBeGreaterThan(30);
    expect(s.stats.badSnapshots).toBeGreaterThan(5);
    expect(w.room.stats.resyncs).toBeGreaterThan(5);
    expect(w.room.stats.fullSnapshots).toBeGreaterThan(5);
    // And it is still in step with the server.
    expect(s.phase).toBe('running');
    expect(s.snapshotTick).toBeGreaterThan(w.room.tick - 20);
  });
});
