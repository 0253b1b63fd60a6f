import type { MountChapter } from '../chapters.js';
import { h } from './dom.js';

export interface ComingChapter {
  number: number;
  title: string;
  /** What the talk says, in one paragraph. */
  lede: string;
  /** What the chapter will let you do, once its part of the library lands. */
  coming: string[];
  /** What already exists and where to look. */
  today?: string;
}

/** A chapter whose demo is not built yet: it says plainly what is coming and what exists today. */
export function comingChapter(c: ComingChapter): MountChapter {
  return (root) => {
    root.append(
      h(
        'article',
        { class: 'chapter coming-chapter', 'data-testid': 'chapter-coming' },
        h(
          'header',
          { class: 'chapter-head' },
          h('p', { class: 'eyebrow' }, `Chapter ${c.number}`),
          h('h1', {}, c.title),
          h('p', { class: 'lede' }, c.lede),
        ),
        h(
          'section',
          { class: 'coming' },
          h('h2', {}, 'Coming to the lab'),
          h(
            'ul',
            {},
            c.coming.map((line) => h('li', {}, line)),
          ),
          c.today ? h('p', { class: 'section-intro' }, c.today) : null,
        ),
      ),
    );
    return () => undefined;
  };
}
