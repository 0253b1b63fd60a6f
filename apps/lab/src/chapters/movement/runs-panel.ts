/**
 * The panel of one loop that the movement and debugging chapters show side by side: the runs of
 * that loop on the four simulated displays (and on the page's own, once the real clock is on)
 * drawn over each other, a legend of their colours, a table with a row per display, a verdict.
 */
import type { MovementLoop } from '@fixedstep/games';
import type { ChapterShell } from '../../shell/chapter-shell.js';
import type { SceneCanvas } from '../../ui/canvas.js';
import { h, type Child } from '../../ui/dom.js';
import { dotRowHead, legendItem, panel } from '../../ui/panel.js';
import { rateColor, type Readout } from '../../ui/readout.js';
import { RATES, sourceLabel, type LoopInfo, type Source } from './movement-lab.js';

/** The colour of each loop: its panel's accent, its line in the charts. */
export const LOOP_COLORS: Readonly<Record<MovementLoop, string>> = {
  variable: '#f87171',
  fixed: '#38bdf8',
};

/** A display's chip in a legend: its colour and rate. */
export function rateChip(hz: number): HTMLElement {
  return legendItem(rateColor(hz), `${hz} Hz`);
}

/** A display's row of the table: the row, its label (renamed once the page's rate is known), its cells. */
export type SourceRow<C> = C & { readonly row: HTMLTableRowElement; readonly label: HTMLElement };

export interface RunsPanelOptions<C extends Record<string, Readout>> {
  /** The scene canvas's class and accessible label. */
  readonly sceneClass: string;
  readonly sceneLabel: string;
  /** A display's cells, in column order after its name. */
  cells(src: Source): C;
  /** The table's class, caption, `<thead>` and `<tfoot>`. */
  readonly tableClass: string;
  readonly caption: Child | Child[];
  readonly head: HTMLTableSectionElement;
  readonly foot: HTMLTableSectionElement;
  /** The panel heading's id (default `panel-<loop>`). */
  readonly headingId?: string;
}

export interface RunsPanel<C> {
  readonly element: HTMLElement;
  readonly scene: SceneCanvas;
  readonly rows: Map<Source, SourceRow<C>>;
  /** The legend's entry for the page's own display: shown only while the real clock runs. */
  readonly legendReal: HTMLElement;
  readonly verdict: HTMLElement;
}

/** Builds `info`'s panel in `shell` (which owns its canvas). */
export function runsPanel<C extends Record<string, Readout>>(
  shell: ChapterShell,
  info: LoopInfo,
  options: RunsPanelOptions<C>,
): RunsPanel<C> {
  const scene = shell.canvas({
    class: options.sceneClass,
    label: options.sceneLabel,
    testId: `canvas-${info.id}`,
  });
  const rows = new Map<Source, SourceRow<C>>();
  const sources: Source[] = [...RATES, 'real'];
  const body = h(
    'tbody',
    {},
    sources.map((src) => {
      const label = h('span', {}, sourceLabel(src));
      const cells = options.cells(src);
      const row = h(
        'tr',
        { hidden: src === 'real' },
        dotRowHead(rateColor(src), label),
        Object.values(cells).map((c) => c.el),
      );
      rows.set(src, { ...cells, row, label });
      return row;
    }),
  );
  const legendReal = legendItem(rateColor('real'), 'yours', true);
  const verdict = h('p', { class: 'verdict', 'data-testid': `verdict-${info.id}` });
  const element = panel(
    {
      ...info,
      accent: LOOP_COLORS[info.id],
      className: 'track-panel',
      headingId: options.headingId,
    },
    h('div', { class: 'scene-wrap' }, scene.canvas),
    h(
      'div',
      { class: 'chart-legend scene-legend', 'aria-hidden': 'true' },
      RATES.map(rateChip),
      legendReal,
    ),
    h(
      'table',
      { class: options.tableClass },
      h('caption', {}, options.caption),
      options.head,
      body,
      options.foot,
    ),
    verdict,
  );
  return { element, scene, rows, legendReal, verdict };
}
