/**
 * The three network models side by side — state sync, lockstep, rollback — measured exactly as
 * the lab's chapter 6 comparison table measures them (`NetworkLab.compare()`): two players of
 * capture the flag (bots re-deciding every 100 ms) over one simulated link each, on simulated time.
 * Bytes a second per client each way (payload, no frame headers), the mean time from player 1's
 * input being sampled to its own screen and the other player's showing it, and the corrections a
 * player could see (a prediction moved by 0.5–40 units).
 *
 * Nothing here is timed: every number is a function of the seed and the link settings, the same on
 * every machine (docs/network.md, "Which model to pick", quotes this table).
 */
import { NetworkLab } from '../../apps/lab/src/chapters/network/network-lab.js';
import type { NetSettings } from '../../apps/lab/src/chapters/network/network-model.js';
import { defineSuite } from '../lib/suite.js';

const LINKS: readonly (Pick<NetSettings, 'latencyMs' | 'jitterMs' | 'loss'> & { label: string })[] =
  [
    { label: 'the lab’s default link', latencyMs: 80, jitterMs: 20, loss: 0.02 },
    { label: 'a bad link', latencyMs: 100, jitterMs: 30, loss: 0.05 },
  ];

const ms = (x: number) => (Number.isFinite(x) ? `${x.toFixed(0)} ms` : '—');

export default defineSuite({
  name: 'network-models',
  description:
    'State sync vs lockstep vs rollback on one simulated link (the lab’s chapter 6 table): bytes/s, input to screen, corrections',
  run(ctx) {
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
  },
});
