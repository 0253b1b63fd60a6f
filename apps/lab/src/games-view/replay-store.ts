/**
 * The hand-over between chapter 9 (a game just played) and chapter 5 (its replay): the last
 * replay's bytes, kept in memory and, when the browser allows, in the tab's session storage so a
 * reload does not lose it; and whether the reader asked to watch it ("Watch replay"), so chapter
 * 5 opens it playing, in view.
 */

export interface StoredReplay {
  bytes: Uint8Array;
  /** Where it came from, for the page: “your last game of Runner”. */
  label: string;
}

const KEY = 'fixedstep.lastReplay';
/** Session storage holds a few MB; a replay is a few KB a minute. Larger ones stay in memory. */
const MAX_STORED = 1_500_000;

let last: StoredReplay | undefined;
let watch = false;

/** Ask the replays chapter to open the last replay playing, in view (once). */
export function requestWatch(): void {
  watch = true;
}

/** Whether a watch was asked for since the last call (the request is used up). */
export function takeWatchRequest(): boolean {
  const w = watch;
  watch = false;
  return w;
}

export function setLastReplay(replay: StoredReplay): void {
  last = { bytes: replay.bytes.slice(), label: replay.label };
  try {
    if (replay.bytes.length > MAX_STORED) sessionStorage.removeItem(KEY);
    else
      sessionStorage.setItem(
        KEY,
        JSON.stringify({ label: replay.label, b64: toBase64(replay.bytes) }),
      );
  } catch {
    // No storage (private mode, a test): memory is enough.
  }
}

export function getLastReplay(): StoredReplay | undefined {
  if (last) return last;
  try {
    const text = sessionStorage.getItem(KEY);
    if (!text) return undefined;
    const data = JSON.parse(text) as { label?: unknown; b64?: unknown };
    if (typeof data.label !== 'string' || typeof data.b64 !== 'string') return undefined;
    last = { label: data.label, bytes: fromBase64(data.b64) };
    return last;
  } catch {
    return undefined;
  }
}

function toBase64(bytes: Uint8Array): string {
  let s = '';
  for (let i = 0; i < bytes.length; i += 0x8000) {
    s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  }
  return btoa(s);
}

function fromBase64(b64: string): Uint8Array {
  const s = atob(b64);
  const out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
  return out;
}
