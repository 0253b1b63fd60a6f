/**
 * A readout: a cell showing a formatted number, carrying a stable test id
 * (`data-testid="readout-…"`) and the full-precision value in `data-value`, which is what the
 * browser tests read. A hash readout also shows a colour chip derived from the hash, so equal
 * hashes are visibly equal.
 */
import { h, setAttr, setText } from './dom.js';
import * as fmt from './format.js';
import { deferWrite, dropWrite, writesHeld, type PendingWrite } from './write-phase.js';

export class Readout implements PendingWrite {
  readonly el: HTMLElement;
  private readonly text: HTMLElement;
  private readonly chip: HTMLElement | undefined;
  private nextText = '—';
  private nextValue: number | string | boolean | undefined;

  constructor(
    tag: 'dd' | 'td' | 'span' | 'strong',
    id: string,
    options: { hash?: boolean; className?: string; title?: string } = {},
  ) {
    this.text = h('span', { class: 'readout-text' }, '—');
    this.chip = options.hash ? h('span', { class: 'swatch', 'aria-hidden': 'true' }) : undefined;
    const cls = [options.className, options.hash ? 'hash' : undefined].filter(Boolean).join(' ');
    this.el = h(
      tag,
      {
        'data-testid': `readout-${id}`,
        'data-value': '',
        class: cls || undefined,
        title: options.title,
      },
      this.chip ?? null,
      this.text,
    );
  }

  /**
   * Show `text`; `value` (full precision) goes to `data-value`; undefined shows as empty. Inside
   * an animation frame the shell holds, it is written with the next due frame (write-phase.ts).
   */
  set(text: string, value: number | string | boolean | undefined): void {
    this.nextText = text;
    this.nextValue = value;
    if (writesHeld()) deferWrite(this, 'text');
    else this.flushWrite();
  }

  /** Write the newest value to the page. */
  flushWrite(): void {
    dropWrite(this);
    const value = this.nextValue;
    setText(this.text, this.nextText);
    setAttr(this.el, 'data-value', fmt.exact(value));
    if (this.chip) {
      const hex = typeof value === 'string' && /^[0-9a-f]{6,}$/.test(value) ? value : '';
      setAttr(this.chip, 'style', hex ? `--swatch: hsl(${fmt.hashHue(hex)} 80% 60%)` : '');
    }
  }

  /** Mark the value as notable (amber) or not. */
  warn(on: boolean): void {
    this.el.classList.toggle('warn', on);
  }

  /** Mark the value as good (green) or not. */
  good(on: boolean): void {
    this.el.classList.toggle('good', on);
  }
}

/** A hue for a display rate, for the chips and lines that tell the rates apart. */
export const RATE_COLORS: Readonly<Record<number, string>> = {
  30: '#f5a524',
  60: '#f472b6',
  144: '#a78bfa',
  240: '#38bdf8',
};

/** The colour of a display rate (or of "your display"). */
export function rateColor(hz: number | 'real'): string {
  return hz === 'real' ? '#e6edf7' : (RATE_COLORS[hz] ?? '#94a3b8');
}
