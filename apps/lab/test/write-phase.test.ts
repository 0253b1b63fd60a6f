import { afterEach, describe, expect, it } from 'vitest';
import { setAttr, setText } from '../src/ui/dom.js';
import { deferWrite, flushWrites, holdWrites, writesHeld } from '../src/ui/write-phase.js';

/** Enough of an element for setText / setAttr, recording every write. */
function fakeElement(log: string[], name: string): Element {
  const attrs = new Map<string, string>();
  let text = '';
  return {
    get textContent() {
      return text;
    },
    set textContent(v: string) {
      log.push(`${name} text ${v}`);
      text = v;
    },
    getAttribute: (k: string) => attrs.get(k) ?? null,
    setAttribute: (k: string, v: string) => {
      log.push(`${name} ${k}=${v}`);
      attrs.set(k, v);
    },
  } as unknown as Element;
}

afterEach(() => {
  holdWrites(false);
  flushWrites();
});

describe('one write phase per frame', () => {
  it('holds text and attributes in the frame and writes the newest once, charts first', () => {
    const log: string[] = [];
    const el = fakeElement(log, 'clock');
    holdWrites(true);
    expect(writesHeld()).toBe(true);
    setText(el, '0.1 s');
    setText(el, '0.2 s');
    setAttr(el, 'data-value', '200');
    deferWrite({ flushWrite: () => log.push('text readout') }, 'text');
    deferWrite({ flushWrite: () => log.push('chart') }, 'chart');
    expect(log).toEqual([]); // nothing written while the chapter draws
    holdWrites(false);
    flushWrites();
    expect(log).toEqual(['chart', 'text readout', 'clock text 0.2 s', 'clock data-value=200']);
    flushWrites();
    expect(log).toHaveLength(4); // written once
  });

  it('a write outside the frame wins over an older held one', () => {
    const log: string[] = [];
    const el = fakeElement(log, 'mode');
    holdWrites(true);
    setText(el, 'paused');
    holdWrites(false);
    setText(el, 'running'); // a click, between frames
    flushWrites();
    expect(el.textContent).toBe('running');
    expect(log).toEqual(['mode text running']);
  });
});
