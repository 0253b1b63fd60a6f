/**
 * The three network models side by side — state sync, lockstep, rollback — measured exactly as
 * the lab's chapter 6 comparison table measures them (`NetworkLab.compare()`): two players of
 * capture the flag (bots re-deciding every 100 ms) over one simulated link each, on simulated time.
 * Bytes a second per client each way (payload, no frame headers), the mean time from player 1's
 * input being sampled to its own screen and the other player's showing it, and the corrections a
 * player could see (a prediction moved by 0.5–40 units).
 *
 * The simulated tables are not timed: every number is a function of the seed and the link settings,
 * the same on every machine (docs/network.md, "Which model to pick", quotes them). The measured
 * tables after them are real time over real sockets (see `measured`), so they vary between runs.
 */
import { writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { NetworkLab } from '../../apps/lab/src/chapters/network/network-lab.js';
import type { NetSettings } from '../../apps/lab/src/chapters/network/network-model.js';
import type { Impairment } from '../../e2e/netem/impair.js';
import { webrtcLink } from '../../e2e/netem/links.js';
import { MODELS, runModelMatch, type Model, type ModelRow } from '../../e2e/netem/model-match.js';
import { findTunSupport, runOverTun } from '../../e2e/netem/tun.js';
import { findTurnServer, startTurnServer } from '../../e2e/netem/turn.js';
import { defineSuite, type SuiteContext } from '../lib/suite.js';

/** The bad link, on real transports (the loss harness's conditions). */
const REAL_LINK: Impairment = { latencyMs: 100, jitterMs: 30, loss: 0.05 };

/** Where a full run writes the measured rows for the lab's table. */
const MEASURED_JSON = fileURLToPath(
  new URL('../../apps/lab/src/chapters/network/data/measured-models.json', import.meta.url),
);

/** The measured rows of one transport: what the lab imports. */
export interface MeasuredModels {
  transport: string;
  link: Impairment;
  rows: ModelRow[];
}

const LINKS: readonly (Pick<NetSettings, 'latencyMs' | 'jitterMs' | 'loss'> & { label: string })[] =
  [
    { label: 'the lab’s default link', latencyMs: 80, jitterMs: 20, loss: 0.02 },
    { label: 'a bad link', latencyMs: 100, jitterMs: 30, loss: 0.05 },
  ];

/** How long the late-input run over real TCP plays: long enough for several retransmission stalls. */
const LATE_SECONDS = 180;

const ms = (x: number) => (Number.isFinite(x) ? `${x.toFixed(0)} ms` : '—');

export default defineSuite({
  name: 'network-models',
  description:
    'State sync vs lockstep vs rollback on one simulated link (the lab’s chapter 6 table), and over real WebRTC and real TCP through the loss harness: bytes/s, input to screen, render delay, corrections',
  async run(ctx) {
    const seconds = ctx.quick ? 5 : 20;
    ctx.note(
      `capture the flag, 2 players (bots re-deciding every 100 ms), seed 7, ${seconds} s of simulated ` +
        'time from the first connection; what the lab’s comparison table shows at that moment.',
    );
    for (const link of LINKS) {
      const lab = new NetworkLab({
        game: 'ctf',
        seed: 7,
        latencyMs: link.latencyMs,
        jitterMs: link.jitterMs,
        loss: link.loss,
      });
      lab.advanceTo(seconds * 1000);
      const r = lab.readouts();
      for (const mode of ['statesync', 'lockstep', 'rollback'] as const) {
        if (!r[mode].equal) throw new Error(`${mode}: the machines do not agree at the checkpoint`);
      }
      ctx.table(
        `${link.label}: ${link.latencyMs} ± ${link.jitterMs} ms each way, ${100 * link.loss} % loss`,
        [
          'model',
          'up B/s',
          'down B/s',
          'input → own screen',
          'input → other screen',
          'corrections (largest, units)',
        ],
        lab
          .compare()
          .map((n) => [
            n.mode === 'statesync' ? 'state sync' : n.mode,
            n.upBytesPerSecond.toFixed(0),
            n.downBytesPerSecond.toFixed(0),
            ms(n.ownLatencyMs),
            ms(n.otherLatencyMs),
            `${n.corrections} (${n.largestCorrection.toFixed(1)}, ${n.smoothed ? 'glide' : n.corrections === 0 ? '—' : 'jump'})`,
          ]),
      );
      ctx.note(
        `state sync: render delay ${r.statesync.renderDelayMs.toFixed(0)} ms, lead ${r.statesync.lead} ticks; ` +
          `lockstep: input delay ${r.lockstep.inputDelay} ticks; rollback: ${r.rollback.rollbacks} rollbacks, ` +
          `deepest ${r.rollback.maxDepth} ticks; all three agree with the server / each other at tick ${Math.min(r.statesync.checkpoint, r.lockstep.checkpoint, r.rollback.checkpoint)}.`,
      );
    }
    await measured(ctx);
  },
});

/**
 * The same three models measured over real transports through the loss harness (e2e/netem): player
 * 2 on a WebRTC data channel (werift peers through coturn behind the impairing UDP proxy) or on a
 * WebSocket over the kernel's TCP through the TUN link, player 1 on the machine running the room.
 * Real time, so the numbers vary from run to run; `--quick` plays 2 s of rollback on each.
 */
async function measured(ctx: SuiteContext): Promise<void> {
  const models: readonly Model[] = ctx.quick ? ['rollback'] : MODELS;
  const seconds = ctx.quick ? 2 : 20;
  const seed = 7;
  const results: MeasuredModels[] = [];
  const turnFound = await findTurnServer();
  if (turnFound.ok) {
    const turn = await startTurnServer(turnFound.path);
    try {
      const rows: ModelRow[] = [];
      for (const model of models) {
        rows.push(
          await runModelMatch({
            model,
            seconds,
            seed,
            connect: (accept) => webrtcLink(turn, REAL_LINK, seed, accept),
          }),
        );
      }
      results.push({ transport: 'WebRTC (werift, through TURN)', link: REAL_LINK, rows });
    } finally {
      await turn.stop();
    }
  } else {
    ctx.note(
      `WebRTC rows skipped: ${turnFound.reason} (node scripts/coturn.mjs --install, as root)`,
    );
  }
  const tun = findTunSupport();
  if (tun.ok) {
    const rows = await runOverTun({ models, seconds, link: REAL_LINK, seed });
    results.push({ transport: 'WebSocket (kernel TCP, TUN link)', link: REAL_LINK, rows });
    if (!ctx.quick) await lateOverTcp(ctx);
  } else {
    ctx.note(`TCP rows skipped: ${tun.reason}`);
  }
  for (const r of results) {
    ctx.table(
      `measured over ${r.transport}: player 2's link ${REAL_LINK.latencyMs} ± ${REAL_LINK.jitterMs} ms each way, ` +
        `${100 * REAL_LINK.loss} % loss; player 1 on the room's machine; ${seconds} s each`,
      [
        'model',
        'up B/s',
        'down B/s',
        'wire up / down B/s',
        'input → own screen',
        'input → other screen',
        'render delay',
        'corrections (largest, units)',
      ],
      r.rows.map((m) => [
        m.model === 'statesync' ? 'state sync' : m.model,
        m.upBytesPerSecond.toFixed(0),
        m.downBytesPerSecond.toFixed(0),
        `${m.wireUpBytesPerSecond.toFixed(0)} / ${m.wireDownBytesPerSecond.toFixed(0)}`,
        ms(m.ownLatencyMs),
        ms(m.otherLatencyMs),
        m.model === 'statesync' ? ms(m.renderDelayMs) : '—',
        `${m.corrections} (${m.largestCorrection.toFixed(1)})`,
      ]),
    );
  }
  if (!ctx.quick && results.length > 0) {
    writeFileSync(
      MEASURED_JSON,
      `${JSON.stringify({ format: 'fixedstep-measured-models/1', date: new Date().toISOString(), seconds, results }, null, 2)}\n`,
    );
    ctx.note(
      `wrote ${MEASURED_JSON} (the lab's chapter 6 table shows it as measured by this bench)`,
    );
  }
}

/**
 * Issue 24's late inputs over the kernel's TCP: state sync alone, player 2 on the TUN link for
 * `LATE_SECONDS` (the lead learns the link's stalls in the first ~30 s, which are counted).
 */
async function lateOverTcp(ctx: SuiteContext): Promise<void> {
  const [row] = await runOverTun({
    models: ['statesync'],
    seconds: LATE_SECONDS,
    link: REAL_LINK,
    seed: 11,
  });
  ctx.table(
    `late inputs over real TCP (WebSocket, TUN link ${REAL_LINK.latencyMs} ± ${REAL_LINK.jitterMs} ms, ` +
      `${100 * REAL_LINK.loss} % loss each way), state sync, player 2, ${LATE_SECONDS} s`,
    ['inputs late (after their tick)', 'lead at the end', 'render delay', 'input → own screen'],
    [
      [
        `${(100 * (row?.lateShare ?? NaN)).toFixed(2)} %`,
        `${row?.lead ?? '—'} ticks`,
        ms(row?.renderDelayMs ?? NaN),
        ms(row?.ownLatencyMs ?? NaN),
      ],
    ],
  );
}
