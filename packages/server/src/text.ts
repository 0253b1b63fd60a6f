/**
 * Text from files and from strangers, made safe to print and to store: control characters
 * (C0, DEL, C1 — the bytes that make terminal escape sequences) and bidirectional overrides are
 * removed.
 * @module
 */

// eslint-disable-next-line no-control-regex -- matching control characters is the point
const UNPRINTABLE = /[\u0000-\u001f\u007f-\u009f\u200e\u200f\u202a-\u202e\u2066-\u2069]/g;

/** `text` without control characters or bidirectional overrides. */
export function printable(text: string): string {
  return text.replace(UNPRINTABLE, '');
}

/** A player name for a table: printable, trimmed, at most 32 characters, `anonymous` if empty. */
export function cleanName(name: string): string {
  const clean = Array.from(printable(name).trim()).slice(0, 32).join('').trim();
  return clean === '' ? 'anonymous' : clean;
}
