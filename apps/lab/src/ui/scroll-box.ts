/**
 * A box for content wider than a phone (a table of many columns): it scrolls sideways and says so.
 * While its content is wider than it, a line under it says "scroll sideways" and a shadow darkens
 * each edge that has more to show, so a cut-off column reads as "more this way", not as the end.
 *
 * Its sizes are read only when the browser reports a change (a ResizeObserver, a scroll event),
 * never while the page is being written, so it forces no layout.
 */
import { h } from './dom.js';

export class ScrollBox {
  /** The box: the scrolling view, then the hint. `data-overflows` says whether it scrolls. */
  readonly el: HTMLElement;
  /** The part that scrolls (a focusable region, so a keyboard can scroll it too). */
  readonly view: HTMLElement;
  private readonly observer: ResizeObserver;

  /** Wraps `content`; `label` names the region for screen readers, `testId` tests the box. */
  constructor(content: HTMLElement, label: string, testId?: string) {
    this.view = h(
      'div',
      { class: 'scroll-box-view', tabindex: 0, role: 'region', 'aria-label': label },
      content,
    );
    this.el = h(
      'div',
      { class: 'scroll-box', 'data-overflows': 'false', 'data-testid': testId },
      this.view,
      h(
        'p',
        { class: 'scroll-hint', 'aria-hidden': 'true', 'data-testid': testId && `${testId}-hint` },
        'Scroll sideways for the other columns →',
      ),
    );
    this.observer = new ResizeObserver(this.update);
    this.observer.observe(this.view);
    this.observer.observe(content);
    this.view.addEventListener('scroll', this.update, { passive: true });
  }

  destroy(): void {
    this.observer.disconnect();
    this.view.removeEventListener('scroll', this.update);
  }

  private readonly update = (): void => {
    const v = this.view;
    const hidden = v.scrollWidth - v.clientWidth;
    const overflows = hidden > 1;
    this.el.dataset.overflows = String(overflows);
    this.el.classList.toggle('more-left', overflows && v.scrollLeft > 1);
    this.el.classList.toggle('more-right', overflows && v.scrollLeft < hidden - 1);
  };
}
