import { describe, expect, it } from 'vitest';
import { SimulatedMatch, SyncTestSession, type Simulation, type WelcomeMessage } from 'fixedstep';
import { ctfGame, type Game } from '@fixedstep/games';
import { registryCatalog } from '../src/relay/index.js';

/** The byte offset of capture the flag's f64 game clock in its snapshot (after magic, players, tick). */
const CLOCK_OFFSET = 4 + 1 + 4;

/** The next float64 above `x` (x > 0): a difference in the last bit, as engines' `Math.sin` may give. */
function nextUp(x: number): number {
  const v = new DataView(new ArrayBuffer(8));
  v.setFloat64(0, x);
  v.setBigUint64(0, v.getBigUint64(0) + 1n);
  return v.getFloat64(0);
}

/**
 * Capture the flag with a non-deterministic step: from tick `from` on, when `glitch()` says so,
 * the game clock comes out one ulp higher — the kind of last-bit difference a platform's math
 * library makes.
 */
class Glitchy implements Simulation {
  constructor(
    readonly inner: Game,
    private readonly from: number,
    private readonly glitch: () => boolean,
  ) {}
  get tick(): number {
    return this.inner.tick;
  }
  step(inputs: readonly number[]): void {
    const t = this.inner.tick;
    this.inner.step(inputs);
    if (t >= this.from && this.glitch()) {
      const b = this.inner.save();
      const v = new DataView(b.buffer, b.byteOffset, b.byteLength);
      v.setFloat64(CLOCK_OFFSET, nextUp(v.getFloat64(CLOCK_OFFSET, true)), true);
      this.inner.load(b);
    }
  }
  save(): Uint8Array {
    return this.inner.save();
  }
  load(bytes: Uint8Array): void {
    this.inner.load(bytes);
  }
  hash(): bigint {
    return this.inner.hash();
  }
}

const bot = (g: Simulation, slot: number) =>
  ctfGame.bot((g instanceof Glitchy ? g.inner : g) as Game, slot);

describe('a non-deterministic game is caught at the right tick', () => {
  it('by SyncTest, on one machine: a step that reads a per-call counter', () => {
    let calls = 0;
    const sim = new Glitchy(ctfGame.create({ seed: 3, players: 2 }), 1000, () => ++calls % 2 === 1);
    const st = new SyncTestSession(sim, { throwOnMismatch: false });
    while (st.step([bot(sim, 0), bot(sim, 1)]));
    expect(st.mismatch!.kind).toBe('step');
    // The step of tick 1000 diverged: the first differing state is tick 1001.
    expect(st.mismatch!.tick).toBe(1001);
    expect(st.mismatch!.diff.firstOffset).toBe(CLOCK_OFFSET);
    expect(st.checkedTicks).toBe(1000);
  });

  it('by the relay: three players, one differs from tick 1000; majority, exact tick and the bytes', () => {
    const players = 3;
    // Only the third client's clock drifts.
    const make =
      (glitch: boolean) =>
      (w: WelcomeMessage): Simulation =>
        new Glitchy(ctfGame.create(ctfGame.decodeConfig(w.config)), 1000, () => glitch);
    const match = new SimulatedMatch({
      game: ctfGame,
      seed: 11,
      ticks: 1400,
      link: { latencyMs: 40, jitterMs: 10, loss: 0.02 },
      relay: { hashEvery: 60 },
      catalog: registryCatalog(),
      clients: [
        {
          kind: 'lockstep',
          createSimulation: make(false),
          input: (_t, sim, slot) => bot(sim, slot),
        },
        {
          kind: 'rollback',
          createSimulation: make(false),
          input: (_t, sim, slot) => bot(sim, slot),
        },
        {
          kind: 'lockstep',
          createSimulation: make(true),
          input: (_t, sim, slot) => bot(sim, slot),
        },
        { kind: 'spectator', createSimulation: make(false) },
      ],
      players,
    });
    const r = match.run(120_000);
    expect(r.finished).toBe(true);
    const d = r.room!.desyncs[0]!;
    expect(d).toBeDefined();
    expect(d.complete).toBe(true);
    expect(d.reportTick).toBe(1020);
    expect(d.tick).toBe(1001);
    expect(d.exact).toBe(true);
    const bad = match.sessions[2]!.welcome!.slot;
    expect(d.majority).toBeGreaterThanOrEqual(0);
    // The spectator's hash is no evidence: the sides are the three players only.
    expect(d.groups[d.majority]!.peers).toHaveLength(2);
    expect(d.groups[d.majority]!.peers).not.toContain(bad);
    expect(d.groups[1 - d.majority]!.peers).toEqual([bad]);
    // Forensics: both sides' snapshots of tick 1001, differing only in the clock's last byte.
    expect(d.snapshots.every((s) => s.bytes.length > 1000)).toBe(true);
    expect(d.diffs).toHaveLength(1);
    expect(d.diffs[0]!.peer).toBe(bad);
    expect(d.diffs[0]!.diff.firstOffset).toBe(CLOCK_OFFSET);
    expect(d.diffs[0]!.diff.differingBytes).toBe(1);
    // Every client heard the exact tick.
    for (const s of match.sessions) expect(s!.desyncs[0]?.tick).toBe(1001);
  });

  it('by the relay with two players: both sides named, no majority', () => {
    const make =
      (glitch: boolean) =>
      (w: WelcomeMessage): Simulation =>
        new Glitchy(ctfGame.create(ctfGame.decodeConfig(w.config)), 500, () => glitch);
    const match = new SimulatedMatch({
      game: ctfGame,
      seed: 12,
      ticks: 700,
      link: { latencyMs: 30, jitterMs: 5 },
      clients: [
        {
          kind: 'rollback',
          createSimulation: make(false),
          input: (_t, sim, slot) => bot(sim, slot),
        },
        {
          kind: 'rollback',
          createSimulation: make(true),
          input: (_t, sim, slot) => bot(sim, slot),
        },
      ],
    });
    const r = match.run(60_000);
    const d = r.room!.desyncs[0]!;
    expect(d.tick).toBe(501);
    expect(d.exact).toBe(true);
    expect(d.majority).toBe(-1);
    expect(d.groups.map((g) => g.peers[0]!).sort((a, b) => a - b)).toEqual([0, 1]);
    expect(d.groups.every((g) => g.peers.length === 1)).toBe(true);
    expect(d.diffs[0]!.diff.firstOffset).toBe(CLOCK_OFFSET);
  });
});

/** Capture the flag whose `save()` lies at one tick: a fake report, the state itself is fine. */
class LiesOnce implements Simulation {
  constructor(
    readonly inner: Simulation,
    private readonly at: number,
  ) {}
  get tick(): number {
    return this.inner.tick;
  }
  step(inputs: readonly number[]): void {
    this.inner.step(inputs);
  }
  save(): Uint8Array {
    const b = this.inner.save();
    if (this.inner.tick === this.at) b[b.length - 1] = b[b.length - 1]! ^ 0xff;
    return b;
  }
  load(bytes: Uint8Array): void {
    this.inner.load(bytes);
  }
  hash(): bigint {
    return this.inner.hash();
  }
}

describe('every desync is diagnosed, not only the first', () => {
  it('a fake early report does not switch detection off: a real divergence later is pinned too', () => {
    const create = (w: WelcomeMessage) => ctfGame.create(ctfGame.decodeConfig(w.config));
    const inner = (g: Simulation): Simulation =>
      g instanceof Glitchy ? g.inner : g instanceof LiesOnce ? inner(g.inner) : g;
    const play = (_t: number, sim: Simulation, slot: number) => bot(inner(sim), slot);
    const match = new SimulatedMatch({
      game: ctfGame,
      seed: 21,
      ticks: 1400,
      // No loss: a desync message is not repeated, and every client should hear both.
      link: { latencyMs: 30, jitterMs: 5 },
      relay: { hashEvery: 60 },
      players: 3,
      clients: [
        { kind: 'lockstep', input: play },
        // Reports a wrong hash of tick 300 (and only that one).
        { kind: 'lockstep', input: play, createSimulation: (w) => new LiesOnce(create(w), 300) },
        // Really diverges from tick 1000 on.
        {
          kind: 'rollback',
          input: play,
          createSimulation: (w) => new Glitchy(create(w), 1000, () => true),
        },
        { kind: 'spectator' },
      ],
    });
    const r = match.run(120_000);
    expect(r.finished).toBe(true);
    const [fake, real] = r.room!.desyncs;
    const liar = match.sessions[1]!.welcome!.slot;
    const drifter = match.sessions[2]!.welcome!.slot;
    // The fake one: pinned to tick 300 exactly, the liar alone against the majority.
    expect(fake!.reportTick).toBe(300);
    expect(fake!.tick).toBe(300);
    expect(fake!.exact).toBe(true);
    expect(fake!.groups[fake!.majority]!.peers).not.toContain(liar);
    expect(fake!.groups.find((_g, i) => i !== fake!.majority)!.peers).toEqual([liar]);
    // At 360 all agreed again; the real divergence is diagnosed like the first.
    expect(real).toBeDefined();
    expect(real!.reportTick).toBe(1020);
    expect(real!.tick).toBe(1001);
    expect(real!.exact).toBe(true);
    expect(real!.groups.find((_g, i) => i !== real!.majority)!.peers).toEqual([drifter]);
    expect(real!.diffs[0]!.diff.firstOffset).toBe(CLOCK_OFFSET);
    // It persists from then on without being reported again: two desyncs in all.
    expect(r.room!.desyncs).toHaveLength(2);
    expect(r.relay.desyncs).toBe(2);
    for (const s of match.sessions) expect(s!.desyncs.map((d) => d.tick)).toEqual([300, 1001]);
  });
});
