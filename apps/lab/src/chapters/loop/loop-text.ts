/**
 * What chapter 1 says: the lede, the idea cards, the readout rows and what they mean, the legend
 * and "How this page works". Numbers come from the model's constants, never typed in.
 */
import { legendDetails, textSection } from '../../ui/prose.js';
import type { IdeaCard } from '../../ui/cards.js';
import {
  CHECKPOINT_TICK,
  HISTORY_MS,
  SLOW_UPDATE_COST_MS,
  STEP_MS,
  TRAIL_MS,
  type PanelReadouts,
} from './loop-lab.js';

/** Each loop's accent colour. */
export const COLORS: Readonly<Record<string, string>> = {
  'frame-locked': '#f5a524',
  variable: '#f87171',
  'fixed-naive': '#a78bfa',
  'fixed-final': '#34d399',
  fixed: '#38bdf8',
};

export const LEDE =
  'A game is a loop: read input, update the world, draw it. How that loop turns the clock on the wall into updates decides whether your game runs the same on every machine — or faster on a gaming monitor, differently after a hiccup, and never the same twice.';

export const BENCH_INTRO =
  'Each panel runs the same scene — a ball thrown in a 12 × 7 m box, with the same scripted throws at the same real moments — under a different loop. All five watch the same simulated display. Change the display and see which loops notice.';

export const EVOLUTION: readonly IdeaCard[] = [
  {
    title: 'Frame-locked',
    color: COLORS['frame-locked']!,
    text: 'Update once per drawn frame and assume every frame lasts 1/60 s. Nothing measures time, so time is the machine: on a 144 Hz screen the game runs 2.4 times too fast, on a slow one in slow motion.',
    snippet: 'velocity += acceleration\nposition += velocity',
  },
  {
    title: 'Variable Δt',
    color: COLORS.variable!,
    text: 'Measure how long the frame took and move by that much. The speed is right on average, but every machine now takes different steps: physics depends on the frame rate, and a 2 s hiccup becomes one 2 s step — straight through a wall.',
    snippet: 'dt = now - last\nupdate(dt)',
  },
  {
    title: 'Fixed step',
    color: COLORS['fixed-naive']!,
    text: `Put real time in an accumulator and pay it out in equal steps of ${STEP_MS} ms. Every display runs the very same steps, so the same inputs give the same game. As on the slides, nothing bounds the debt yet.`,
    snippet: 'acc += dt\nwhile (acc > STEP) {\n  update(STEP); acc -= STEP\n}',
  },
  {
    title: 'Final fixes',
    color: COLORS['fixed-final']!,
    text: 'Time never runs backwards (Δt ≥ 0), and the accumulator is capped at 1 s, so a long pause can no longer demand hundreds of steps in one frame.',
    snippet: 'dt = max(0, now - last)\nacc = clamp(acc + dt, 0, 1.0)',
  },
  {
    title: 'FixedLoop',
    color: COLORS.fixed!,
    text: 'What a real game adds: time as an integer tick count (no drifting float sums), a cap on steps per frame with an explicit overload policy, every dropped millisecond counted, hidden tabs paused — and α for the renderer to draw between the last two states.',
    snippet: 'n = loop.frame(now)\nfor (…n) world.step()\nrender(loop.alpha)',
  },
];

export type Field = keyof Omit<PanelReadouts, 'owed'>;

/** The readout rows of a panel: test id suffix, label, what it means. */
export const ROWS: readonly { field: Field; id: string; label: string; title: string }[] = [
  { field: 'simS', id: 'sim', label: 'Sim time', title: 'Time as the loop has simulated it' },
  { field: 'realS', id: 'real', label: 'Real time', title: 'Time of the last display frame' },
  {
    field: 'ratio',
    id: 'ratio',
    label: 'Sim / real',
    title: 'Simulated time over real time: 1 is right',
  },
  {
    field: 'steps',
    id: 'steps',
    label: 'Steps / frame',
    title: 'Updates the last display frame asked for',
  },
  {
    field: 'maxSteps',
    id: 'max-steps',
    label: 'Max steps',
    title: 'The most updates one display frame asked for',
  },
  {
    field: 'droppedMs',
    id: 'dropped',
    label: 'Dropped',
    title: 'Real time the loop chose not to simulate (n/a: the loop has no accumulator)',
  },
  {
    field: 'hash',
    id: 'hash',
    label: 'Hash now',
    title:
      'FNV-1a 64 of the ball’s state now. On a frame that lands exactly on a step boundary the slides’ loops (acc > STEP) are one update behind FixedLoop (acc ≥ step) until the next frame',
  },
  {
    field: 'checkpointHash',
    id: 'hash150',
    label: `Hash @${CHECKPOINT_TICK}`,
    title: `FNV-1a 64 of the ball’s state right after update ${CHECKPOINT_TICK}: equal ticks, equal hashes?`,
  },
];

/** One of the "Things to try" cards: what it sets up is the view's business. */
export interface TryText {
  readonly title: string;
  readonly text: string;
  readonly action: string;
}

export const TRY: Readonly<Record<'faster' | 'hitch' | 'hidden' | 'slow' | 'stutter', TryText>> = {
  faster: {
    title: 'A faster screen',
    text: `Switch the display to 144 Hz. The frame-locked ball now runs 2.4 times too fast (look at its sim / real). The variable-Δt ball keeps the right speed but follows a different path. The three fixed loops do not notice: same ticks, same Hash @${CHECKPOINT_TICK}.`,
    action: 'Show 144 Hz',
  },
  hitch: {
    title: 'A hitch',
    text: 'No frame for 2 s, then life goes on. Variable Δt takes one 2 s update. The slides’ accumulator runs every owed step in one frame (look at max steps), the final fixes clamp the debt at 1 s, and FixedLoop runs at most 8 steps and counts what it dropped.',
    action: 'Drop a 2 s hitch',
  },
  hidden: {
    title: 'A tab in the background',
    text: 'The page is hidden for 10 s (press Skip twice to get through it). On return the naive loop fast-forwards 10 s at once; FixedLoop pauses instead and counts the hidden time as dropped.',
    action: 'Hide the tab',
  },
  slow: {
    title: 'A slow machine',
    text: `Each update now costs ${SLOW_UPDATE_COST_MS} ms but simulates only ${STEP_MS} ms. The slides’ loop spirals: each frame owes more steps than the last, until the page stalls. The clamp bounds the debt; FixedLoop caps the steps per frame and stays responsive, in slow motion.`,
    action: 'Slow this machine down',
  },
  stutter: {
    title: 'Stutter',
    text: `At 144 Hz a ${STEP_MS} ms step lasts 4–5 frames. Turn interpolation off and the fixed balls stand still for several frames, then jump: their trails turn into clumps of dots. With interpolation they are drawn between the last two states, at α = accumulator / step.`,
    action: 'Show stutter',
  },
};

export const CHART_LABEL = (title: string): string =>
  `Steps per frame over the last ${HISTORY_MS / 1000} s, ${title}`;

export function legend(): HTMLElement {
  return legendDetails('How to read a panel', [
    ...ROWS.map((row) => [row.label, row.title] as const),
    [
      'Trail',
      `One dot per display frame over the last ${TRAIL_MS / 1000} s: even spacing is smooth motion, clumps are stutter.`,
    ],
    ['Colour chips', 'Derived from the hash: equal colours, equal states.'],
  ]);
}

export function howItWorks(): HTMLElement {
  return textSection(
    'how',
    'how-title',
    'How this page works',
    'The display here is simulated: frame times are computed, not measured, so every run is exactly repeatable. On each real animation frame the page moves a virtual clock forward by the real time that passed and runs, for every panel, the display frames due by then. “Skip +5 s” moves the virtual clock at once.',
    'Changing the display (its rate, jitter, a hitch, a hidden tab, a slow machine, a throw) rebuilds all five runs and replays them from zero to the current moment. The loops are deterministic, so the replay lands on exactly the state a live run would have reached.',
    '“Real clock” feeds the loops this page’s own requestAnimationFrame times instead. Switch to another tab for a few seconds and come back to see a real hidden tab.',
  );
}
