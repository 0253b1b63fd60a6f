/**
 * One DOM-write phase per animation frame. The shell holds the page's writes while a chapter
 * draws: canvases are drawn first, on a page whose style and layout are still clean (setting a
 * canvas font makes Chrome bring the page's style up to date, so after a write it forces a style
 * recalculation), then the held writes go out at the end of the frame — the charts first (uPlot
 * draws at once, on the still clean page), then readouts and the text of `setText`/`setAttr`
 * (dom.ts). The browser then lays the page out once, after the frame.
 *
 * Readouts and charts change what the reader reads, which nobody reads 60 times a second: the
 * shell writes them every {@link TEXT_PERIOD_MS} (about 10 Hz), or at once after a control changed
 * something; a readout or chart set in between keeps its newest value, written with the next
 * due frame. Outside the shell's frame (a click, a message) nothing is held: they write at once.
 *
 * Nothing in a frame reads the page's layout: canvas and chart sizes come from ResizeObservers.
 */

/** How often held readouts and charts are written, ms (10 Hz). */
export const TEXT_PERIOD_MS = 100;

/** Something with a held write: {@link PendingWrite.flushWrite} writes its newest value. */
export interface PendingWrite {
  flushWrite(): void;
}

/** A chart (drawn by uPlot in a microtask) or text (written as it is flushed). */
export type WriteKind = 'chart' | 'text';

const pending: Record<WriteKind, Set<PendingWrite>> = { chart: new Set(), text: new Set() };
/** Text and attributes held by `setText`/`setAttr` (dom.ts): element → name (`''`: text) → value. */
const heldText = new Map<Element, Map<string, string>>();
let held = false;

/** True while the shell holds writes (inside its animation frame). */
export function writesHeld(): boolean {
  return held;
}

/** Hold writes (`true`) or let them through (`false`). */
export function holdWrites(on: boolean): void {
  held = on;
}

/** Remember `w` for the next {@link flushWrites}. */
export function deferWrite(w: PendingWrite, kind: WriteKind): void {
  pending[kind].add(w);
}

/** Forget `w`'s held write (it wrote at once, or it is gone). */
export function dropWrite(w: PendingWrite): void {
  pending.chart.delete(w);
  pending.text.delete(w);
}

/** Hold `el`'s text (`name` `''`) or attribute `name` at `value` for the next {@link flushWrites}. */
export function holdText(el: Element, name: string, value: string): void {
  let m = heldText.get(el);
  if (!m) {
    m = new Map<string, string>();
    heldText.set(el, m);
  }
  m.set(name, value);
}

/** Forget a held text or attribute of `el` (it was written at once: the newer value wins). */
export function dropText(el: Element, name: string): void {
  heldText.get(el)?.delete(name);
}

function flush(set: Set<PendingWrite>): void {
  const all = [...set];
  set.clear();
  for (const w of all) w.flushWrite();
}

/** Write every held value: the charts first, then the readouts and the held text. */
export function flushWrites(): void {
  flush(pending.chart);
  flush(pending.text);
  const all = [...heldText];
  heldText.clear();
  for (const [el, m] of all) {
    for (const [name, value] of m) {
      if (name === '') {
        if (el.textContent !== value) el.textContent = value;
      } else if (el.getAttribute(name) !== value) el.setAttribute(name, value);
    }
  }
}
