/**
 * Chapter 6's lag-compensation panel: the shooting gallery played by two bots over a simulated
 * link, each shot aimed where the shooter's screen draws the target; the server judges it at the
 * time the shooter saw (a LagHistory rewind) or at its present, and the panel shows how many
 * on-screen hits the server confirmed each way. Live: the matches run on simulated time when you
 * press Run (about a second of work on a phone).
 */
import { runGalleryMatch, type GalleryMatchResult } from '@fixedstep/games';
import { button, segmented } from '../../ui/controls.js';
import { h } from '../../ui/dom.js';
import { Readout } from '../../ui/readout.js';

/** Round trips the panel offers, ms. */
export const LAG_RTTS = [50, 150, 250] as const;
export type LagRtt = (typeof LAG_RTTS)[number];
/** Simulated seconds per match. */
const SECONDS = 20;

/** The numbers the panel shows for one round trip. */
export interface LagRow {
  rttMs: number;
  compensated: GalleryMatchResult;
  plain: GalleryMatchResult;
}

/** Both matches at `rttMs`. */
export function lagRow(rttMs: number, seconds = SECONDS): LagRow {
  return {
    rttMs,
    compensated: runGalleryMatch({ compensate: true, rttMs, seconds }),
    plain: runGalleryMatch({ compensate: false, rttMs, seconds }),
  };
}

const share = (r: GalleryMatchResult): number =>
  r.screenHits === 0 ? 0 : r.confirmed / r.screenHits;
const percent = (x: number): string => `${(100 * x).toFixed(1)} %`;

/** The panel: build once; {@link run} (the Run button) plays both matches. */
export class LagPanel {
  readonly el: HTMLElement;
  private rtt: LagRtt = 150;
  private readonly readouts = {
    hits: new Readout('dd', 'lag-screen-hits'),
    on: new Readout('dd', 'lag-confirmed-compensated'),
    off: new Readout('dd', 'lag-confirmed-plain'),
    rewind: new Readout('dd', 'lag-rewind'),
  };

  constructor() {
    const choice = segmented<LagRtt>({
      name: 'lag-rtt',
      label: 'Round trip',
      testPrefix: 'lag-rtt',
      values: LAG_RTTS,
      selected: this.rtt,
      text: (v) => `${v} ms`,
      onChange: (v) => {
        this.rtt = v;
      },
    });
    const run = button(`Run ${SECONDS} s`, 'lag-run', () => {
      this.run();
    });
    const r = this.readouts;
    this.el = h(
      'section',
      { class: 'net-lag', 'aria-labelledby': 'net-lag-title', 'data-testid': 'net-lag' },
      h('h3', { id: 'net-lag-title' }, 'Lag compensation: judged when the shooter saw'),
      h(
        'p',
        { class: 'section-intro' },
        'A state-sync client draws the others where they were a snapshot interval and half a ' +
          'round trip ago. Aim at what you see and fire: by the time the shot reaches the server, ' +
          'the target has moved on. In the shooting gallery each shot carries how far back its ' +
          'shooter’s screen was (the issued tick minus the render tick); the server keeps where ' +
          'every target was for the last 30 ticks (LagHistory) and judges the shot then — or, ' +
          'without compensation, at its present. Two bots aim at the targets their screens draw.',
      ),
      h('div', { class: 'controls' }, choice.el, run),
      h(
        'dl',
        { class: 'readouts' },
        h('dt', {}, 'Shots that hit on the shooter’s screen'),
        r.hits.el,
        h('dt', {}, 'Confirmed by the server, judged when the shooter saw'),
        r.on.el,
        h('dt', {}, 'Confirmed by the server, judged at its present'),
        r.off.el,
        h('dt', {}, 'Rewind a shot asked for (mean)'),
        r.rewind.el,
      ),
    );
  }

  /** Play both matches at the chosen round trip and show the result. */
  run(): LagRow {
    const row = lagRow(this.rtt);
    const r = this.readouts;
    r.hits.set(
      `${row.compensated.screenHits} of ${row.compensated.shots}`,
      row.compensated.screenHits,
    );
    r.on.set(percent(share(row.compensated)), share(row.compensated));
    r.off.set(percent(share(row.plain)), share(row.plain));
    r.rewind.set(`${row.compensated.meanRewind.toFixed(1)} ticks`, row.compensated.meanRewind);
    r.on.good(share(row.compensated) >= 0.99);
    r.off.warn(share(row.plain) < 0.5);
    return row;
  }

  destroy(): void {
    // Nothing runs between presses.
  }
}
