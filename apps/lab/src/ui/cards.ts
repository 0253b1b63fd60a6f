/**
 * A numbered row of idea cards — "how the loop evolved", "why bodies go through walls" — each with
 * a title, a sentence or two and a code snippet, in the card's accent colour. Styled by
 * styles.css (`.evolution`).
 */
import { code, h } from './dom.js';

export interface IdeaCard {
  readonly title: string;
  /** Accent colour (any CSS colour). */
  readonly color: string;
  readonly text: string;
  readonly snippet: string;
}

/** A section headed `title` (its heading gets `id`), the cards numbered from 1. */
export function ideaCards(options: {
  id: string;
  title: string;
  cards: readonly IdeaCard[];
  /** Extra class of the list, for a chapter's own layout (e.g. its column count). */
  listClass?: string;
}): HTMLElement {
  return h(
    'section',
    { class: 'evolution', 'aria-labelledby': options.id },
    h('h2', { id: options.id }, options.title),
    h(
      'ol',
      { class: `evolution-steps${options.listClass ? ` ${options.listClass}` : ''}` },
      options.cards.map((c, i) =>
        h(
          'li',
          { class: 'evolution-step', style: `--accent: ${c.color}` },
          h('h3', {}, h('span', { class: 'step-num' }, String(i + 1)), c.title),
          h('p', {}, c.text),
          code(c.snippet),
        ),
      ),
    ),
  );
}
