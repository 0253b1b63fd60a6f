/**
 * What the reader plays with: a keyboard (a mouse or trackpad is the main pointer), touch (a finger
 * is, as on a phone), or both (a touch-screen laptop, a tablet with a keyboard, or `?touch=1`). The
 * pages word their instructions by it: "press Space" is no help on a phone.
 */
export type InputKind = 'keyboard' | 'touch' | 'both';

/** The kind of input this device has; `forceTouch` adds touch (the page's `?touch=1`). */
export function inputKind(forceTouch = false): InputKind {
  const media = (q: string) => typeof matchMedia === 'function' && matchMedia(q).matches;
  const coarse = media('(pointer: coarse)');
  if (coarse) return media('(any-pointer: fine)') ? 'both' : 'touch';
  return forceTouch || media('(any-pointer: coarse)') ? 'both' : 'keyboard';
}

/** How the reader plays, in words: "the keyboard", "touch", "the keyboard or touch". */
export function inputWords(kind: InputKind): string {
  return kind === 'keyboard'
    ? 'the keyboard'
    : kind === 'touch'
      ? 'touch'
      : 'the keyboard or touch';
}
