/**
 * WebRTC (unreliable data channels) against WebSocket (TCP) on the same impaired link: 100 ± 30 ms
 * one way, 5 % loss each way, 60 Hz, two capture-the-flag bots in rollback — the Node-peer version
 * of the loss harness (e2e/netem/node-match.ts): real sockets on 127.0.0.1, WebRTC through coturn
 * behind the impairing UDP proxy, WebSocket behind the TCP model. Input-to-screen latency p50/p99,
 * stalls, rollback depths, bytes per second per player.
 *
 * The Node WebRTC peer is werift 0.24 (pure TypeScript): its SCTP retransmits "unreliable"
 * messages (it never abandons a chunk with `maxRetransmits: 0`, so the harness asks for 1) and its
 * sender falls behind under loss, so Node-to-Node WebRTC stalls where Chromium's does not. The
 * browser version (`e2e/netem.e2e.test.ts`, two Chromium pages) is the comparison that answers
 * "why rollback games use UDP-like transports"; this suite tracks both Node transports over time.
 * Skipped, saying why, without coturn (`node scripts/coturn.mjs --install`).
 */
import { ctfGame } from '@fixedstep/games';
import { runNodeMatch } from '../../e2e/netem/node-match.js';
import type { Impairment } from '../../e2e/netem/impair.js';
import { comparisonTable, type TransportSummary } from '../../e2e/netem/probe.js';
import { writeNetemReport } from '../../e2e/netem/report.js';
import { findTurnServer, startTurnServer } from '../../e2e/netem/turn.js';
import { defineSuite } from '../lib/suite.js';

const LINK: Impairment = { latencyMs: 100, jitterMs: 30, loss: 0.05 };

export default defineSuite({
  name: 'transport',
  description:
    'WebRTC vs WebSocket on one impaired link (100 ± 30 ms, 5 % loss, 60 Hz, 2 players): latency p50/p99, stalls, bytes/s (Node peers)',
  async run(ctx) {
    const found = await findTurnServer();
    if (!found.ok) {
      ctx.note(`skipped: ${found.reason} (node scripts/coturn.mjs --install, as root)`);
      return;
    }
    const ticks = ctx.quick ? 300 : 3600;
    const turn = await startTurnServer(found.path);
    const rows: TransportSummary[] = [];
    try {
      for (const transport of ['webrtc', 'websocket'] as const) {
        const { summary } = await runNodeMatch({
          transport,
          ticks,
          link: LINK,
          turn,
          game: ctfGame,
        });
        rows.push({
          ...summary,
          transport: transport === 'webrtc' ? 'WebRTC (werift)' : 'WebSocket (ws)',
        });
      }
    } finally {
      await turn.stop();
    }
    ctx.table(
      `capture the flag, ${ticks} ticks, joiner's link ${LINK.latencyMs} ± ${LINK.jitterMs} ms, ${LINK.loss * 100} % loss`,
      ['', ...rows.map((r) => r.transport)],
      comparisonTable(rows)
        .split('\n')
        .slice(2)
        .map((line) =>
          line
            .slice(2, -2)
            .split(' | ')
            .map((c) => c.trim()),
        ),
    );
    for (const r of rows) {
      const worst = Math.max(...r.bytesPerSecond.flatMap((b) => [b.up, b.down]));
      ctx.note(
        `${r.transport}: the busiest player's protocol traffic is ${worst.toFixed(0)} B/s (goal ≤ 1024 B/s each way): ${worst <= 1024 ? 'met' : 'NOT met'}`,
      );
    }
    if (!ctx.quick) {
      writeNetemReport('node', {
        format: 'fixedstep-netem/1',
        date: new Date().toISOString(),
        where: 'Node peers (werift, ws)',
        game: 'capture the flag (bots)',
        ticks,
        tickRate: 60,
        players: 2,
        link: LINK,
        rows,
      });
    }
  },
});
