import { describe, expect, it } from 'vitest';
import { SimulatedMatch, type MatchResult } from 'fixedstep';
import { ctfGame } from '@fixedstep/games';
import { registryCatalog } from '../src/relay/index.js';

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
    catalog: registryCatalog(),
    link: { latencyMs: 100, jitterMs: 30, loss: 0.05 },
    clients: [{ kind }, { kind }, { kind: 'spectator' }],
  });
  const r = match.run(700_000);
  print(kind, r);
  return r;
}

/** The numbers docs/network.md's "Measured" table shows, one line each. */
function print(kind: string, r: MatchResult): void {
  const players = r.clients.filter((c) => c.kind !== 'spectator');
  const spectator = r.clients.find((c) => c.kind === 'spectator');
  const each = (f: (c: MatchResult['clients'][number]) => number | string) =>
    players.map(f).join(' and ');
  const lines = [
    `wall time ${(r.wallMs / 1000).toFixed(1)} s; final hashes agree: ${r.hashesAgree}`,
    `input delay ${each((c) => c.stats.inputDelay)} ticks, lead ${each((c) => c.stats.lead)} ticks`,
    `rollbacks ${each((c) => c.stats.rollbacks)}, max depth ${each((c) => c.stats.maxRollbackDepth)}, ` +
      `${players.reduce((a, c) => a + c.stats.resimulatedTicks, 0)} ticks resimulated`,
    `stalls ${each((c) => c.stats.stalls)} players, ${spectator?.stats.stalls ?? '—'} spectator`,
    `hash checks ${r.relay.hashChecks}, desyncs ${r.relay.desyncs}`,
    `relay ${(r.relay.messagesIn / 1000).toFixed(1)} k messages in, ${(r.relay.messagesOut / 1000).toFixed(1)} k out, ` +
      `${(r.relay.bytesOut / 2 ** 20).toFixed(1)} MiB out`,
  ];
  console.log(`${kind}, 10-minute match:\n  ${lines.join('\n  ')}`);
}

describe('a 10-minute match at 100 ms ± 30 ms and 5 % loss', () => {
  it('lockstep: every client ends on the same hash', () => {
    const r = tenMinutes('lockstep');
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
    expect(r.finished).toBe(true);
    expect(r.hashesAgree).toBe(true);
    expect(r.room!.desyncs).toHaveLength(0);
    for (const c of r.clients.filter((x) => x.kind === 'rollback')) {
      expect(c.tick).toBe(36_000);
      // Confirmed ticks come in groups over a datagram link: one rollback may mend several ticks.
      expect(c.stats.rollbacks).toBeGreaterThan(200);
      expect(c.stats.maxRollbackDepth).toBeLessThanOrEqual(30);
      expect(c.stats.stalls).toBeLessThan(10);
      // No input lag beyond the 1-tick local delay; ahead of the server by ~half an RTT.
      expect(c.stats.inputDelay).toBe(1);
      expect(c.stats.lead).toBeGreaterThanOrEqual(5);
      expect(c.stats.lead).toBeLessThanOrEqual(10);
    }
  });
});
