/**
 * What chapter 8 says: the lede, the two code cards, each bench's intro — its numbers computed from
 * the settings and from the same rigs the panels run (tested) — the readout rows and "How this page
 * works".
 */
import { code, h } from '../../ui/dom.js';
import { textSection } from '../../ui/prose.js';
import * as fmt from '../../ui/format.js';
import { STALL_WORK_MS, type FinalSettings, type SpiralOutlook } from './final-fixes-lab.js';
import { FINAL_STEP_MS } from '@fixedstep/games';

export const LEDE =
  'The accumulator on the slides has two holes. A frame that comes very late makes it owe more steps than a slow machine can pay, and paying them makes the next frame later still: the spiral of death. A clock that jumps back hands it a negative Δt. Two lines close both holes.';

export function codePair(): HTMLElement {
  return h(
    'div',
    { class: 'why-grid code-pair' },
    h(
      'div',
      { class: 'why-card' },
      h('h3', {}, 'On the slides'),
      code(
        'dt = now - last; last = now\naccumulator += dt\nwhile (accumulator > STEP) {\n  update(STEP); accumulator -= STEP\n}',
      ),
    ),
    h(
      'div',
      { class: 'why-card fixed-card' },
      h('h3', {}, 'With the final fixes'),
      code(
        '// time never runs backwards\ndt = max(0, now - last); last = now\n// never more than 1 s owed\naccumulator = clamp(accumulator + dt, 0, 1.0)\nwhile (accumulator > STEP) {\n  update(STEP); accumulator -= STEP\n}',
      ),
    ),
  );
}

/**
 * The spiral bench's intro: the machine, the hitch, and the steps the slides' loop (no clamp)
 * asks for after it — read from that loop's own rig ({@link spiralOutlook}).
 */
export function spiralIntro(o: SpiralOutlook): string {
  const step = FINAL_STEP_MS;
  const cost = o.costMs > step ? 'more than' : o.costMs === step ? 'exactly' : 'less than';
  const [first = 0, ...next] = o.steps;
  const grows = next.length > 0 && next[next.length - 1]! > first;
  const outcome = grows
    ? `each frame owes more than the last, until a frame would take longer than a browser lets a page hang. Here nothing hangs: the display is simulated, the steps beyond ${STALL_WORK_MS / 1000} s of work are counted, not run.`
    : `the debt shrinks, because an update costs less than the ${step} ms it simulates: this machine recovers even without the clamp.`;
  return `The ball of chapter 1 on a 60 Hz display, on a machine where one update costs ${o.costMs} ms — ${cost} the ${step} ms it simulates. At t = ${fmt.seconds(o.hitchAtMs / 1000)} the page stalls for ${fmt.seconds(o.hitchMs / 1000)}. Without the clamp the first frame after it owes ${fmt.plural(first, 'step')}; paying them takes ${fmt.seconds((first * o.costMs) / 1000)}, so the next frame owes ${next[0] ?? first}${next.length > 1 ? `, then ${next.slice(1).join(', ')}…` : ''} — ${outcome}`;
}

/** The clock bench's intro: when the clock is set back, by how much (the settings'). */
export function backwardsIntro(s: Pick<FinalSettings, 'backJumps' | 'backMs'>): string {
  const at = [...s.backJumps].sort((a, b) => a - b).map((t) => fmt.seconds(t / 1000));
  const when =
    at.length === 0
      ? 'Press “Set the clock back now” and the clock is set back'
      : `At t = ${at[0]!}${at.length > 1 ? ` (and again at ${at.slice(1).join(', ')})` : ''} the clock is set back`;
  return `A loop that reads the wall clock (Date.now) sees it jump when the system clock is corrected; some timer sources misbehave too. ${when} by ${fmt.seconds(s.backMs / 1000)}. A variable Δt takes one negative step and time runs backwards; the slides’ accumulator goes into debt and the game freezes until the clock has caught up those ${fmt.seconds(s.backMs / 1000)}; with max(0, Δt) nothing happens at all.`;
}

export type Row = readonly [id: string, label: string, title: string];

export const SPIRAL_ROWS: readonly Row[] = [
  ['steps', 'Steps / frame', 'Updates the last frame asked for'],
  ['max-steps', 'Max steps', 'The most updates one frame asked for'],
  [
    'longest-frame',
    'Longest frame',
    'The longest wait between two frames, the one in progress included',
  ],
  ['fps', 'Frames / s', 'Frames shown over the last 2 s: how responsive the page is'],
  ['ratio', 'Sim / real', 'Simulated time over real time, counting only updates that ran'],
  [
    'owed',
    'Owed',
    `Updates asked for in frames with more than ${STALL_WORK_MS / 1000} s of work, never run`,
  ],
];

export const BACKWARDS_ROWS: readonly Row[] = [
  ['sim', 'Sim time', 'Time as the loop has simulated it'],
  ['lag', 'Behind real', 'Display time minus simulated time'],
  ['reversed', 'Went back', 'Did simulated time ever run backwards?'],
  ['frozen', 'Longest freeze', 'The longest display time with no simulated progress'],
  [
    'backward-frames',
    'Back readings',
    'Frames whose clock reading was earlier than the last (FixedLoop counts them)',
  ],
];

export function how(): HTMLElement {
  return textSection(
    'how',
    'final-how-title',
    'How this page works',
    'The displays are simulated and a virtual clock runs them at real speed; “Skip +5 s” jumps it. On the slow machine the simulated display waits for the work each frame asked for, as a real page would — but the page never does more than 5 s of it in one frame, so a spiral costs nothing here. What a real page would have run in vain is shown as owed.',
    'Changing the machine, the policy or the jump size, and every hitch or clock jump you add, replays both benches from zero to the current moment. “Real clock” feeds them this page’s own animation frames instead: the slow machine still delays its own frames, the wall clock still jumps.',
    'FixedLoop goes beyond the talk’s two lines: it clamps at 0.25 s by default (15 steps at 60 Hz rather than 60), caps the steps of one frame (8) and says what happens to the rest — catch up later, drop them, or reset — counting every dropped millisecond. Pick a policy above and watch its frame rate and its sim / real ratio.',
  );
}
