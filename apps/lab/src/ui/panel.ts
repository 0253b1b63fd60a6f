/**
 * The pieces the chapters' side-by-side panels are built of: the panel itself (an accent colour,
 * a header with a title and a tagline, then its scene and numbers), a table's head row, a legend
 * chip and a table row headed by a coloured dot. Styled by styles.css.
 */
import { h, type Child } from './dom.js';

/** What a panel says about itself. */
export interface PanelOptions {
  /** Its `data-panel` (what the tests and the styles find it by). */
  id: string;
  title: string;
  tagline: string;
  /** Accent colour (any CSS colour). */
  accent: string;
  /** Extra classes after `panel`. */
  className?: string;
  /** The heading's id, which labels the section. Default `panel-<id>`. */
  headingId?: string;
}

/** A `<section class="panel">` labelled by its header's title, `children` after the header. */
export function panel(options: PanelOptions, ...children: (Child | Child[])[]): HTMLElement {
  const headingId = options.headingId ?? `panel-${options.id}`;
  return h(
    'section',
    {
      class: options.className ? `panel ${options.className}` : 'panel',
      style: `--accent: ${options.accent}`,
      'data-panel': options.id,
      'aria-labelledby': headingId,
    },
    h(
      'header',
      { class: 'panel-head' },
      h('h3', { id: headingId }, options.title),
      h('p', {}, options.tagline),
    ),
    ...children,
  );
}

/** A table's `<thead>`: one row of column headings. */
export function headRow(...labels: string[]): HTMLTableSectionElement {
  return h(
    'thead',
    {},
    h(
      'tr',
      {},
      labels.map((label) => h('th', { scope: 'col' }, label)),
    ),
  );
}

/** A chart or scene legend's entry: a chip in `color`, then `label`. */
export function legendItem(color: string, label: string, hidden = false): HTMLElement {
  return h(
    'span',
    { class: 'legend-item', style: `--chip: ${color}`, hidden },
    h('span', { class: 'legend-chip', 'aria-hidden': 'true' }),
    label,
  );
}

/** A row's heading cell: a dot in `color` (the display's, the run's), then `label`. */
export function dotRowHead(color: string, label: Child): HTMLTableCellElement {
  return h(
    'th',
    { scope: 'row' },
    h(
      'span',
      { class: 'row-label' },
      h('span', { class: 'rate-dot', style: `--chip: ${color}` }),
      label,
    ),
  );
}
