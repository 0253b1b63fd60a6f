import { describe, expect, it } from 'vitest';
import { SimulatedMatch, type MatchResult } from 'fixedstep';
import { ctfGame } from '@fixedstep/games';
import { gameCatalog } from '../src/net/index.js';

/**
 * The 10-minute match: capture the flag, two players and a spectator, 36 000 ticks at 60 Hz,
 * every link 100 ms ± 30 ms one way (RTT ≈ 200 ms) with 5 % of messages lost, through the
 * server's relay (its catalog of registered games) and real sessions on simulated time. Bots
 * play, re-deciding every 100 ms.
 */
function tenMinutes(kind: 'lockstep' | 'rollback'): MatchResult {
  const match = new SimulatedMatch({
    game: ctfGame,
    seed: 2024,
    ticks: 36_000,
    catalog: gameCatalog(),
    link: { latencyMs: 100, jitterMs: 30, loss: 0.05 },
    clients: [{ kind }, { kind }, { kind: 'spectator' }],
  });
  return match.run(700_000);
}

function report(kind: string, r: MatchResult): void {
  const players = r.clients.filter((c) => c.kind !== 'spectator');
  const spectator = r.clients.find((c) => c.kind === 'spectator')!;
  const sum = (f: (c: (typeof r.clients)[number]) => number) =>
    players.reduce((a, c) => a + f(c), 0);
  console.log(
    [
      `${kind}: 36000 ticks (${(r.simulatedMs / 60000).toFixed(2)} min simulated) in ${(r.wallMs / 1000).toFixed(2)} s wall`,
      `  final hash ${players[0]!.finalHash} on all ${r.clients.length} clients: ${r.hashesAgree}`,
      `  rollbacks ${sum((c) => c.stats.rollbacks)} (${players.map((c) => c.stats.rollbacks).join(' + ')}), ` +
        `resimulated ticks ${sum((c) => c.stats.resimulatedTicks)}, max depth ${Math.max(...players.map((c) => c.stats.maxRollbackDepth))}`,
      `  stalls: players ${players.map((c) => `${c.stats.stalls} (${c.stats.stallFrames} frames)`).join(', ')}; spectator ${spectator.stats.stalls}`,
      `  input delay ${players.map((c) => c.stats.inputDelay).join('/')} ticks, lead ${players.map((c) => c.stats.lead).join('/')}, ` +
        `playout ${players.map((c) => c.stats.playoutDelay).join('/')}, rtt ${players.map((c) => c.stats.rtt.toFixed(0)).join('/')} ms`,
      `  link loss ${players.map((c) => `${c.link![0].lost}/${c.link![0].sent} up, ${c.link![1].lost}/${c.link![1].sent} down`).join('; ')}`,
      `  relay: ${r.relay.messagesIn} in / ${r.relay.messagesOut} out, ${(r.relay.bytesOut / 1024).toFixed(0)} KiB out, ` +
        `hash checks ${r.relay.hashChecks}, inputs filled after the deadline ${r.relay.filledInputs}`,
    ].join('\n'),
  );
}

describe('a 10-minute match at 100 ms ± 30 ms and 5 % loss', () => {
  it('lockstep: every client ends on the same hash', () => {
    const r = tenMinutes('lockstep');
    report('lockstep', r);
    expect(r.finished).toBe(true);
    expect(r.hashesAgree).toBe(true);
    expect(r.room!.closedTick).toBeGreaterThanOrEqual(36_000);
    expect(r.room!.hashChecks).toBeGreaterThan(1100);
    expect(r.room!.desyncs).toHaveLength(0);
    for (const c of r.clients) {
      expect(c.tick).toBe(36_000);
      expect(c.stats.rollbacks).toBe(0);
      // A stall is a run of frames waiting for inputs: a handful in ten minutes.
      expect(c.stats.stalls).toBeLessThan(60);
      expect(c.link![0].lost).toBeGreaterThan(0);
    }
    // RTT ≈ 200–260 ms: about 16 ticks of input delay.
    for (const c of r.clients.filter((x) => x.kind !== 'spectator')) {
      expect(c.stats.inputDelay).toBeGreaterThanOrEqual(13);
      expect(c.stats.inputDelay).toBeLessThanOrEqual(20);
    }
  });

  it('rollback: every client ends on the same hash', () => {
    const r = tenMinutes('rollback');
    report('rollback', r);
    expect(r.finished).toBe(true);
    expect(r.hashesAgree).toBe(true);
    expect(r.room!.desyncs).toHaveLength(0);
    for (const c of r.clients.filter((x) => x.kind === 'rollback')) {
      expect(c.tick).toBe(36_000);
      expect(c.stats.rollbacks).toBeGreaterThan(300);
      expect(c.stats.maxRollbackDepth).toBeLessThanOrEqual(30);
      expect(c.stats.stalls).toBeLessThan(10);
      // No input lag beyond the 1-tick local delay; ahead of the server by ~half an RTT.
      expect(c.stats.inputDelay).toBe(1);
      expect(c.stats.lead).toBeGreaterThanOrEqual(5);
      expect(c.stats.lead).toBeLessThanOrEqual(10);
    }
  });
});
