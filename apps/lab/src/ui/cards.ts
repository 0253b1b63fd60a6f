/**
 * The cards chapters are made of: a numbered row of idea cards — "how the loop evolved", "why
 * bodies go through walls" — each with a title, a sentence or two and a code snippet in the card's
 * accent colour (`.evolution`); and the "Things to try" cards, each with a button that sets up
 * what its text says (`.experiments`). Styled by styles.css.
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

/** One "Things to try" card: what to try, what it shows, and the button that sets it up. */
export interface TryCard {
  readonly title: string;
  readonly text: string;
  /** The button's label. */
  readonly action: string;
  /** The button's test id, if a test clicks it by id. */
  readonly testId?: string;
  /** Set up everything the text assumes. */
  readonly run: () => void;
}

/** The "Things to try" section (heading id `id`), its cards in one row on a laptop. */
export function tryCards(id: string, cards: readonly TryCard[]): HTMLElement {
  return h(
    'section',
    { class: 'experiments', 'aria-labelledby': id },
    h('h2', { id }, 'Things to try'),
    h(
      'ol',
      { class: 'experiment-list' },
      cards.map((c) => {
        const btn = h(
          'button',
          { type: 'button', class: 'btn btn-small', 'data-testid': c.testId },
          c.action,
        );
        btn.addEventListener('click', c.run);
        return h('li', {}, h('h3', {}, c.title), h('p', {}, c.text), btn);
      }),
    ),
  );
}
