/**
 * The loss harness's real-TCP link (e2e/netem/tun-link.py): in a network namespace of the test's
 * own, the kernel's TCP through a TUN device that delays, drops and reflects packets. A short
 * rollback match over a WebSocket on it loses packets on the wire (TCP retransmits them: the
 * session's own bytes are all delivered), and the namespace is gone afterwards. Skipped, saying
 * why, without root, /dev/net/tun, `ip` or python3.
 */
import { spawnSync } from 'node:child_process';
import { describe, expect, it } from 'vitest';
import { findTunSupport, runOverTun } from './netem/tun.js';

const tun = findTunSupport();

describe.runIf(tun.ok)('real TCP through the TUN link', () => {
  it('a rollback and a state-sync match play over it; the namespace goes with it', async () => {
    const before = spawnSync('ip', ['netns', 'list'], { encoding: 'utf8' }).stdout;
    const rows = await runOverTun({
      models: ['rollback', 'statesync'],
      seconds: 3,
      link: { latencyMs: 100, jitterMs: 30, loss: 0.05 },
      seed: 7,
    });
    expect(rows.map((r) => r.model)).toEqual(['rollback', 'statesync']);
    for (const r of rows) {
      // Player 2's input reached player 1's screen, a one-way trip and more after it was sampled.
      expect(r.otherLatencyMs).toBeGreaterThan(100);
      // The wire carries the messages and TCP's headers and acknowledgements on top.
      expect(r.wireUpBytesPerSecond).toBeGreaterThan(r.upBytesPerSecond);
      expect(r.wireDownBytesPerSecond).toBeGreaterThan(r.downBytesPerSecond);
    }
    expect(rows[1]!.renderDelayMs).toBeGreaterThan(0);
    expect(spawnSync('ip', ['netns', 'list'], { encoding: 'utf8' }).stdout).toBe(before);
  }, 60_000);
});

if (!tun.ok) {
  console.log(`TUN link skipped: ${tun.reason}`);
}
