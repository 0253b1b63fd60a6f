/**
 * The chapters' running text: a section of prose under a heading ("How this page works", "Why …"),
 * the "why" cards, and the collapsible legend that says how to read a panel. Styled by styles.css.
 */
import { code, h, type Child } from './dom.js';

/**
 * A `<section class="className">` labelled by its heading `title` (id `id`), then `content`: a
 * string is a paragraph, a node (a list, a code block, a paragraph of its own) goes in as it is.
 */
export function textSection(
  className: string,
  id: string,
  title: string,
  ...content: (Node | string | null)[]
): HTMLElement {
  return h(
    'section',
    { class: className, 'aria-labelledby': id },
    h('h2', { id }, title),
    content.map((c) => (typeof c === 'string' ? h('p', {}, c) : c)),
  );
}

/**
 * A chapter's bench or chart: a `<section class="className">` labelled by its heading `title`
 * (id `id`), the paragraph `intro` (`.section-intro`: what the section shows and what to try)
 * under it, then `children` (its controls, panels, charts).
 */
export function introSection(
  className: string,
  id: string,
  title: string,
  intro: Child | Child[],
  ...children: (Child | Child[])[]
): HTMLElement {
  return h(
    'section',
    { class: className, 'aria-labelledby': id },
    h('h2', { id }, title),
    h('p', { class: 'section-intro' }, intro),
    ...children,
  );
}

/** One "why" card: a title, a paragraph, and optionally a code snippet under it. */
export interface WhyCard {
  readonly title: string;
  readonly text: string;
  readonly snippet?: string;
}

/** The cards of a "why" section, side by side on a laptop. */
export function whyCards(cards: readonly WhyCard[]): HTMLElement {
  return h(
    'div',
    { class: 'why-grid' },
    cards.map((c) =>
      h(
        'div',
        { class: 'why-card' },
        h('h3', {}, c.title),
        h('p', {}, c.text),
        c.snippet === undefined ? null : code(c.snippet),
      ),
    ),
  );
}

/**
 * The collapsible legend under `summary` ("How to read a panel"): each entry a term (text, or a
 * chip then text) and what it means.
 */
export function legendDetails(
  summary: string,
  entries: readonly (readonly [term: Child | Child[], meaning: Child])[],
): HTMLElement {
  return h(
    'details',
    { class: 'legend' },
    h('summary', {}, summary),
    h(
      'dl',
      {},
      entries.flatMap(([term, meaning]) => [h('dt', {}, term), h('dd', {}, meaning)]),
    ),
  );
}
