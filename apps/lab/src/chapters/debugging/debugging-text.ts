/**
 * What chapter 7 says: the lede, the guarantee (its numbers read from the determinism catalogue
 * itself), the bench's intro, each panel's verdict (computed from the readouts, tested), "Why this
 * matters" and "How this page works".
 */
import { TRACE_DISPLAY_RATES, traceCatalogue } from '@fixedstep/games';
import { textSection, whyCards } from '../../ui/prose.js';
import * as fmt from '../../ui/format.js';
import { STEP_MS, type DebugReadouts, type LoopInfo } from './debugging-lab.js';

export const LEDE =
  'A bug you cannot reproduce is a bug you cannot fix. With a fixed step, the physics always behaves the same way: record the player’s inputs, replay them anywhere, and you get the very same game — down to the last bit of its state.';

export const BENCH_INTRO =
  'A little level with coins that reappear at seeded random places. The recording below — timestamped presses of ←, → and Jump — replays on four simulated displays under each loop. Every run hashes its whole state (runner, coins, score and the random generator) after every update. Press Record to play a session of your own; when you stop, it replays on all four displays.';

/** The determinism catalogue's size: scenes compared tick for tick, and their ticks. */
export function catalogueSize(): { scenes: number; ticks: number } {
  const scenes = traceCatalogue().filter((s) => s.informational !== true);
  return { scenes: scenes.length, ticks: scenes.reduce((n, s) => n + s.ticks, 0) };
}

/** The guarantee, with the catalogue's own numbers. */
export function guarantee(size: { scenes: number; ticks: number }): string {
  const rates = TRACE_DISPLAY_RATES.map((hz) => String(hz));
  return `the same start and the same recorded inputs give the same state bits, tick for tick — at every display rate, under any frame jitter, and in every JavaScript engine. The browser tests check it (e2e/determinism): Node, Chromium (V8), Firefox ESR (SpiderMonkey) and WebKitGTK (JavaScriptCore), when installed, compute the determinism catalogue of @fixedstep/games — ${fmt.count(size.scenes)} scenes and games, ${fmt.count(size.ticks)} ticks; the suite adds probes of the engines’ own arithmetic — and must agree on the state hash after every tick, and so must displays at ${rates.slice(0, -1).join(', ')} and ${rates[rates.length - 1]!} Hz. Only the inputs and the random seed need recording; the hash proves the replay is the game.`;
}

/** A panel's verdict: what its hashes (and the runs' paths so far) say. */
export function verdictText(
  loop: LoopInfo,
  r: DebugReadouts,
  centimetres: (m: number) => string,
): string {
  const n = r.rows.length;
  if (!r.equal) {
    const scores = r.rows.map((x) => x.score);
    return new Set(scores).size > 1
      ? `${n} displays, different states — even different scores: ${scores.join(' / ')} coins.`
      : `${n} displays, ${new Set(r.rows.map((x) => x.hash)).size} different states from the same inputs.`;
  }
  if (loop.fixed) return `${n} displays, one hash at every tick: the replay is the game.`;
  if (!r.moved) return `${n} displays agree — for now: nothing has moved yet.`;
  if (r.maxDivergence > 0) {
    return `${n} displays agree right now — the runners came to rest in the same place — but their paths did not: up to ${centimetres(r.maxDivergence)} apart (at ${(r.maxDivergenceAtMs / 1000).toFixed(1)} s).`;
  }
  return `${n} displays agree: the same state, and no two runners apart at any sample so far.`;
}

export function why(): HTMLElement {
  return textSection(
    'why',
    'debug-why-title',
    'Why this matters when something goes wrong',
    whyCards([
      {
        title: 'A bug report is a recording',
        text: 'A player hits a bug on a 144 Hz laptop; you debug on a 60 Hz desktop. Under a fixed step their recorded inputs replay into the very same states on your machine, tick by tick, so the bug happens again — under your debugger, as often as you like.',
      },
      {
        title: 'Hashes find the first wrong tick',
        text: 'Hash the state every tick and two runs can be compared cheaply: the first tick whose hashes differ is where the behaviour changed. Replays, network peers and tests all use the same check.',
        snippet: `for each tick:\n  step(inputs[tick])\n  if (hash() !== recorded[tick]) stop()`,
      },
      {
        title: 'What breaks it',
        text: `A variable Δt (shown above), reading a clock or Math.random inside a step, engine-dependent maths (Math.sin may differ in the last bit between browsers), iterating over things in an order that can change. fixedstep’s lint rules and its determinism guard catch these in simulation code.`,
      },
    ]),
  );
}

export function how(): HTMLElement {
  return textSection(
    'how',
    'debug-how-title',
    'How this page works',
    `The four displays are simulated (rate plus seeded jitter), and a virtual clock runs them at real speed; “Skip +5 s” jumps it. The fixed-step runs use FixedLoop with a ${STEP_MS} ms step; each press goes to the tick whose time span contains it, whatever the display. Their hashes are compared at the latest tick all four have reached. The variable-Δt runs have no ticks, so their states are compared as they are now.`,
    'While you record, your presses reach every run at the same virtual time. When you stop, the recording replays from zero. “Real clock” adds a fifth run per loop, driven by this page’s own animation frames.',
  );
}
