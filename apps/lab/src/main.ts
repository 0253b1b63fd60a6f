import { CHAPTERS, routeOf, type Chapter } from './chapters.js';
import { h } from './ui/dom.js';
import './styles.css';

const app = document.getElementById('app')!;

const nav = h(
  'nav',
  { class: 'site-nav', 'aria-label': 'Chapters' },
  h(
    'ol',
    {},
    CHAPTERS.map((c) =>
      h(
        'li',
        {},
        h(
          'a',
          { href: `#/${c.id}`, 'data-chapter': c.id, title: c.summary },
          h('span', { class: 'num' }, String(c.number)),
          ' ',
          c.title,
        ),
      ),
    ),
  ),
);

const skip = h('a', { class: 'skip-link', href: '#main' }, 'Skip to content');
const main = h('main', { id: 'main', tabindex: -1 });

app.append(
  skip,
  h(
    'header',
    { class: 'site-header' },
    h(
      'div',
      { class: 'site-header-inner' },
      h(
        'a',
        { class: 'brand', href: '#/' },
        h('span', { class: 'brand-mark', 'aria-hidden': 'true' }),
        h('span', { class: 'brand-name' }, 'fixedstep'),
        h('span', { class: 'brand-sub' }, 'lab'),
      ),
      nav,
    ),
  ),
  main,
  h(
    'footer',
    { class: 'site-footer' },
    h(
      'p',
      {},
      'Based on the talk “Fixed-Step Simulation”. Everything here is deterministic: the same settings give the same numbers, on any machine.',
    ),
    h(
      'p',
      {},
      'The library: ',
      h(
        'a',
        { href: 'https://github.com/fixedstep/fixedstep/blob/main/docs/guide/README.md' },
        'guide',
      ),
      ', ',
      h('a', { href: './docs/' }, 'API reference'),
      '.',
    ),
  ),
);

skip.addEventListener('click', (event) => {
  event.preventDefault();
  main.focus();
});

let unmount: (() => void) | undefined;
let generation = 0;

async function show(): Promise<void> {
  const id = routeOf(location.hash);
  const chapter: Chapter | undefined = id === '' ? CHAPTERS[0] : CHAPTERS.find((c) => c.id === id);
  const gen = ++generation;
  unmount?.();
  unmount = undefined;
  main.replaceChildren();
  for (const a of nav.querySelectorAll('a')) {
    if (a.dataset.chapter === chapter?.id) a.setAttribute('aria-current', 'page');
    else a.removeAttribute('aria-current');
  }
  if (!chapter) {
    document.title = 'fixedstep lab';
    main.append(
      h(
        'article',
        { class: 'chapter missing' },
        h('h1', {}, 'No such chapter'),
        h(
          'p',
          {},
          `There is no chapter “${id}”. `,
          h('a', { href: `#/${CHAPTERS[0]!.id}` }, `Start with chapter 1, ${CHAPTERS[0]!.title}.`),
        ),
      ),
    );
    return;
  }
  document.title = `${chapter.number}. ${chapter.title} — fixedstep lab`;
  const module = await chapter.load();
  if (gen !== generation) return;
  unmount = module.mount(main, chapter);
}

window.addEventListener('hashchange', () => {
  if (location.hash.startsWith('#/') || location.hash === '') void show();
});
void show();
