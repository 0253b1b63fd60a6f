/**
 * Chapter 6's transport panel: the loss harness's recorded run (data/loss-harness.json) of the
 * same rollback match over WebRTC (an unreliable, UDP-like channel) and over WebSocket (TCP), side
 * by side — latency bars, stalls, the rollback depth distribution and bytes per second. Recorded
 * numbers, not live: nothing here runs a clock.
 */
import { Chart } from '../../ui/chart.js';
import { h } from '../../ui/dom.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import { LOSS_HARNESS_COMMAND, lossHarness, type TransportRow } from './loss-harness.js';

const COLORS: Readonly<Record<string, string>> = { WebRTC: '#4ade80', WebSocket: '#f5a524' };
const color = (t: string) => COLORS[t] ?? '#8da0bd';

/** RollbackSession's default `maxPrediction`, which the harness's pages use: ticks. */
const PREDICTION_WINDOW = 30;

/** A test-id-safe name for a transport: "WebRTC" → "webrtc". */
export const transportId = (t: string): string => t.toLowerCase().replace(/[^a-z0-9]+/g, '-');

/** The panel: build once, then {@link TransportsPanel.destroy} with the chapter. */
export class TransportsPanel {
  readonly el: HTMLElement;
  private readonly chart: Chart;

  constructor() {
    const r = lossHarness();
    const l = r.link;
    const link = `${l.latencyMs} ± ${l.jitterMs} ms one way, ${Math.round(l.loss * 100)} % loss each way`;
    const seconds = Math.round(r.ticks / r.tickRate);
    this.chart = depthChart(r.rows);
    const maxDepth = Math.max(...r.rows.map((x) => x.maxDepth));
    const xs = Array.from({ length: maxDepth }, (_, i) => i + 1);
    this.chart.set([xs, ...r.rows.map((x) => xs.map((d) => x.depths.get(d) ?? 0))]);
    this.el = h(
      'section',
      {
        class: 'net-transports',
        'aria-labelledby': 'net-transports-title',
        'data-testid': 'net-transports',
      },
      h('h3', { id: 'net-transports-title' }, 'Why rollback games use UDP-like transports'),
      h(
        'p',
        { class: 'section-intro' },
        'TCP delivers in order: when one segment is lost, everything sent after it waits at the ' +
          'receiver until the retransmission arrives, a retransmission timeout later — and a ' +
          'rollback game that runs out of the other player’s inputs stalls. Over an unreliable ' +
          'channel only that packet is gone; the next one carries the recent inputs again ' +
          '(the protocol’s redundancy), so nothing waits and a rollback repairs the guess.',
      ),
      h(
        'p',
        { class: 'net-transports-source', 'data-testid': 'net-transports-source' },
        `Recorded, not live: ${r.game}, ${r.players} players, ${fmt.count(r.ticks)} ticks ` +
          `(${seconds} s at ${r.tickRate} Hz) between ${r.where}, the same match over WebRTC ` +
          `(through a TURN relay behind a UDP proxy) and over WebSocket (behind a TCP model), ` +
          `${link}, on ${r.date.slice(0, 10)}. Made by `,
        h('code', {}, LOSS_HARNESS_COMMAND),
        '.',
      ),
      h(
        'div',
        {
          class: 'net-transport-bars',
          role: 'img',
          'aria-label': 'Latency and stalls by transport',
        },
        barGroup('Input → other screen, median', r.rows, (x) => x.latencyP50, fmt.millis),
        barGroup('Input → other screen, 99th percentile', r.rows, (x) => x.latencyP99, fmt.millis),
        barGroup('Display frames spent stalled', r.rows, (x) => x.stallFrames, fmt.count),
      ),
      h(
        'div',
        { class: 'duo net-transport-duo' },
        r.rows.map((x) => card(x)),
      ),
      h('h4', {}, 'How deep the rollbacks went'),
      this.chart.el,
      h(
        'p',
        { class: 'net-transports-note', 'data-testid': 'net-transports-depth-note' },
        r.rows
          .map((x) => {
            const full = x.depths.get(PREDICTION_WINDOW) ?? 0;
            return `${x.transport}: ${fmt.plural(full, 'rollback')} of ${fmt.count(x.rollbacks)}`;
          })
          .join('; ') +
          ` reached ${PREDICTION_WINDOW} ticks, the whole prediction window ` +
          `(${PREDICTION_WINDOW / r.tickRate} s at ${r.tickRate} Hz): ` +
          'a session that far ahead of the other player’s inputs stops and waits for them.',
      ),
    );
  }

  destroy(): void {
    this.chart.destroy();
  }
}

function barGroup(
  title: string,
  rows: readonly TransportRow[],
  value: (r: TransportRow) => number,
  text: (v: number) => string,
): HTMLElement {
  const max = Math.max(1e-9, ...rows.map(value));
  return h(
    'div',
    { class: 'net-bar-group' },
    h('p', { class: 'net-bar-title' }, title),
    rows.map((r) => {
      const v = value(r);
      return h(
        'div',
        { class: 'net-bar-row' },
        h('span', { class: 'net-bar-label' }, r.transport),
        h(
          'span',
          { class: 'net-bar-track' },
          h('span', {
            class: 'net-bar',
            style: `width: ${((v / max) * 100).toFixed(1)}%; --bar: ${color(r.transport)}`,
          }),
        ),
        h('span', { class: 'net-bar-value' }, text(v)),
      );
    }),
  );
}

function card(r: TransportRow): HTMLElement {
  const id = transportId(r.transport);
  const item = (label: string, key: string, text: string, value: number | boolean) => {
    const o = new Readout('dd', `transport-${id}-${key}`);
    o.set(text, value);
    return [h('dt', {}, label), o.el];
  };
  const bytes = r.bytesPerSecond.flatMap((b) =>
    item(
      `Player ${b.slot + 1} up / down, B/s`,
      `bytes-${b.slot + 1}`,
      `${fmt.count(b.up)} / ${fmt.count(b.down)}`,
      b.up,
    ),
  );
  const wire = r.wireBytesPerSecond;
  return h(
    'div',
    { class: `panel net-transport`, style: `--accent: ${color(r.transport)}` },
    h('div', { class: 'panel-head' }, h('h3', {}, r.transport)),
    h(
      'dl',
      { class: 'readouts' },
      ...item('Input → other screen, median', 'p50', fmt.millis(r.latencyP50), r.latencyP50),
      ...item('Input → other screen, p99', 'p99', fmt.millis(r.latencyP99), r.latencyP99),
      ...item('Stalls', 'stalls', fmt.count(r.stalls), r.stalls),
      ...item('Frames stalled', 'stall-frames', fmt.count(r.stallFrames), r.stallFrames),
      ...item('Rollbacks', 'rollbacks', fmt.count(r.rollbacks), r.rollbacks),
      ...item('Deepest rollback, ticks', 'max-depth', fmt.count(r.maxDepth), r.maxDepth),
      ...bytes,
      ...(wire
        ? item(
            'On the wire up / down, B/s',
            'wire',
            `${fmt.count(wire.up)} / ${fmt.count(wire.down)}`,
            wire.up,
          )
        : []),
      ...item('Loss seen', 'loss', `${(r.lossSeen * 100).toFixed(1)} %`, r.lossSeen),
      ...item('Hashes equal', 'hashes-equal', r.hashesEqual ? 'yes' : 'NO', r.hashesEqual),
    ),
  );
}

function depthChart(rows: readonly TransportRow[]): Chart {
  return new Chart({
    height: 200,
    label: 'How many rollbacks went how many ticks deep, per transport',
    x: { label: 'rollback depth, ticks', format: (v) => fmt.count(v) },
    y: { label: 'rollbacks', format: (v) => fmt.count(v), size: 36 },
    series: rows.map((r) => ({
      label: r.transport,
      color: color(r.transport),
      stepped: true,
      points: 2.5,
      gaps: false,
    })),
  });
}
