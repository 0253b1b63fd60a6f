/** Tiny DOM helpers: enough to build a page by hand, readably. */
import { dropText, holdText, writesHeld } from './write-phase.js';

type Attrs = Record<string, string | number | boolean | undefined>;
export type Child = Node | string | null | undefined | false;

/**
 * Creates an element. Attributes set to `false` or `undefined` are left out, `true` gives an
 * empty attribute; `class` and `data-*`/`aria-*` work as plain attributes.
 */
export function h<K extends keyof HTMLElementTagNameMap>(
  tag: K,
  attrs: Attrs = {},
  ...children: (Child | Child[])[]
): HTMLElementTagNameMap[K] {
  const el = document.createElement(tag);
  for (const [name, value] of Object.entries(attrs)) {
    if (value === undefined || value === false) continue;
    el.setAttribute(name, value === true ? '' : String(value));
  }
  for (const child of children.flat()) {
    if (child === null || child === undefined || child === false) continue;
    el.append(child);
  }
  return el;
}

/**
 * Sets text only when it changed (cheap to call every frame). Inside the shell's animation frame
 * it is held and written with the frame's other writes (write-phase.ts).
 */
export function setText(el: Element, text: string): void {
  if (writesHeld()) {
    holdText(el, '', text);
    return;
  }
  dropText(el, '');
  if (el.textContent !== text) el.textContent = text;
}

/** Sets an attribute only when it changed; held like {@link setText} inside the shell's frame. */
export function setAttr(el: Element, name: string, value: string): void {
  if (writesHeld()) {
    holdText(el, name, value);
    return;
  }
  dropText(el, name);
  if (el.getAttribute(name) !== value) el.setAttribute(name, value);
}

/** Code with the usual escaping done by the DOM. */
export function code(text: string): HTMLElement {
  return h('pre', { class: 'code' }, h('code', {}, text));
}

/**
 * Shows or hides `el`, writing only when that changes: setting `hidden` to what it already is still
 * makes the browser recalculate style (and, in a frame, forces it before the next canvas font).
 */
export function setHidden(el: HTMLElement, hidden: boolean): void {
  if (el.hidden !== hidden) el.hidden = hidden;
}
