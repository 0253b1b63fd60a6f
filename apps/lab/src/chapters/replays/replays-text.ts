/**
 * What chapter 5 says: the lede, where a replay can come from, what each fact of a file means,
 * and what is in the file open now — every size read from the file's own sections.
 */
import { h } from '../../ui/dom.js';
import { textSection } from '../../ui/prose.js';
import * as fmt from '../../ui/format.js';
import { describeContents } from '../../games-view/replays.js';
import type { ReplayFacts, Verification } from './replays-lab.js';

export const LEDE =
  'With a fixed step a replay does not need the world: the inputs of every tick and the seeds of the random number generators are enough to compute it again, bit for bit — at any display rate, forwards, backwards, from any tick.';

/** The sample that is open when the chapter opens: the runner's bot, recorded at load. */
export const SAMPLE = { game: 'runner', seed: 2024, seconds: 30 } as const;

export const SAMPLE_LABEL = `a sample: ${SAMPLE.seconds} s of the runner played by its bot (seed ${SAMPLE.seed}), recorded when this page opened`;

/** Seconds of play in a bot game recorded on this page. */
export const BOT_GAME_SECONDS = 60;

/** The rows of "The file": test id suffix, label, what it means. */
export const FACT_ROWS: readonly [id: string, label: string, title: string][] = [
  ['game', 'Game', 'The game and its version'],
  ['seed', 'Seed', 'The seed of every random number the game draws'],
  ['players', 'Player', 'Names in the file'],
  ['ticks', 'Ticks', 'Steps recorded'],
  ['length', 'Length', 'Ticks × step'],
  ['size', 'File size', 'The whole file: header, inputs, hashes, keyframes if any, checksum'],
  ['bpm', 'Per minute', 'File size per minute of play'],
  ['inputs', 'Inputs', 'The recorded inputs alone (run-length coded): what a replay needs'],
  ['hashes', 'Hashes', 'The state hashes stored while recording: what proves the replay'],
  ['keyframes', 'Keyframes', 'Snapshots of the state stored in the file, to seek from'],
];

/** "m:ss.cc" for a time in seconds. */
export function clock(seconds: number): string {
  if (!Number.isFinite(seconds)) return '—';
  const s = Math.floor(seconds);
  const cs = Math.floor((seconds - s) * 100);
  return `${Math.floor(s / 60)}:${String(s % 60).padStart(2, '0')}.${String(cs).padStart(2, '0')}`;
}

/** What the verdict line says after verification. */
export function verdictText(v: Verification, checkpoints: number, keyframes: number): string {
  const r = v.result;
  if (r.ok) {
    return `Verified: re-simulating all ${fmt.count(r.ticks)} ticks reproduced every stored hash (${fmt.plural(checkpoints, 'checkpoint')}, ${fmt.plural(keyframes, 'keyframe')}) in ${Math.max(1, Math.round(v.ms))} ms.`;
  }
  return `Does not reproduce: the ${r.kind ?? 'stored'} hash after tick ${r.firstMismatchTick} differs (last good tick ${r.lastGoodTick}). The inputs or the game changed since it was recorded.`;
}

/** "What is in the file": how a replay is laid out, and what this one holds. */
export function whatIsInTheFile(facts: ReplayFacts | undefined): HTMLElement {
  return textSection(
    'how',
    'how-title',
    'What is in the file',
    'A header (the game and its version, the step, the seed, the players), then the input of every tick, run-length coded: a held button costs a few bytes however long it is held. Then the state hashes taken while recording (one a second), any keyframes (snapshots of the state to seek from) and a checksum.',
    facts
      ? h(
          'p',
          { 'data-testid': 'replay-contents' },
          `The file open now — ${facts.title}, ${fmt.count(facts.ticks)} ticks — is ${describeContents(facts.contents, fmt.count)}.`,
        )
      : null,
    'Playing re-simulates: the game is built from the header and stepped with the recorded inputs, and every stored hash it passes is checked. Seeking starts from the last keyframe before the target (or from tick 0) and steps from there; a tick back is a seek. The display only decides how many ticks run per frame — never what a tick does — so a replay is the same at 30 Hz, 144 Hz, 16× or one tick at a time.',
    'A highscore server does the same: it re-simulates the submitted replay and ranks the score the replay reaches, not the one claimed. That proves these inputs reach that score with this seed on this version of the game; it cannot tell whether a person or a bot pressed them. Format: docs/replay-format.md.',
  );
}
