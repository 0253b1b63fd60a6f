/**
 * What chapter 3 says: the lede, the intros, the readout rows, the per-setting table's columns, the
 * idea cards, the legends and "How this page works". Numbers come from the model's constants.
 */
import { h } from '../../ui/dom.js';
import { legendDetails, textSection } from '../../ui/prose.js';
import { ideaCards, type IdeaCard } from '../../ui/cards.js';
import { CHART_COLORS } from './collisions-chart.js';
import { FIRE_EVERY_S, LANES, RADIUS, STEP_MS, type ResultDisplay } from './collisions-lab.js';

export const BODY = { flying: '#e2e8f0', bounced: '#34d399', through: '#e879f9' } as const;

export const LEDE =
  'A simulation does not watch bodies move: it teleports them one step at a time and then looks for overlaps. A body that jumps farther in one step than a wall is thick can land beyond it, and nothing ever saw them touch. Even a shorter jump can end past the middle of the wall, and the engine pushes an overlapping body out through the nearest face — here the far one. So every body bounces only while one step is at most half the wall plus the body’s radius. With a variable Δt the step is as long as the last frame — a hiccup of the display is a giant leap through the wall.';

export const RANGE_INTRO = `A body of radius ${RADIUS * 100} cm leaves the muzzle every ${FIRE_EVERY_S} s, in one of ${LANES} lanes, straight at a wall. Both panels fire the same shots; the left takes one step per display frame, the right takes steps of ${STEP_MS} ms. Each also runs a twin with continuous detection (CCD) — press CCD twins to draw those instead. Bodies that end up on the far side turn magenta. The bar above each range is one step; once it is longer than the green bar below it (half the wall plus the radius), some bodies are pushed through.`;

export const CHART_INTRO = `Which walls are safe at which speed, for a fixed step of ${STEP_MS} ms and a body of radius ${RADIUS} m. Below the amber line the wall is thinner than one step and a body can jump over it unseen. The talk’s rule puts the wall on that line — but a discrete engine pushes an overlapping body out through the nearer face, so a body that lands past the middle of the wall leaves on the far side. Only above the green line (v·dt ≤ w/2 + r) does every body bounce. Click the chart to try a setting; each one tried stays as a dot, magenta if some went through.`;

export type Field =
  'fired' | 'tunnelled' | 'ccd-tunnelled' | 'share' | 'dt' | 'max-dt' | 'steps' | 'sim';

/** The readout rows of a panel: test id suffix, label, what it means; `time` rows go right. */
export const ROWS: readonly { field: Field; label: string; title: string; time?: true }[] = [
  { field: 'fired', label: 'Fired', title: 'Bodies fired at the wall so far' },
  {
    field: 'tunnelled',
    label: 'Through, discrete',
    title: 'Bodies that ended on the far side with discrete detection only (of those resolved)',
  },
  {
    field: 'ccd-tunnelled',
    label: 'Through, CCD',
    title: 'The same shots with continuous collision detection',
  },
  {
    field: 'share',
    label: 'Share through',
    title: 'Through / resolved, discrete detection',
  },
  { field: 'dt', label: 'Last step', title: 'The Δt of the last update', time: true },
  { field: 'max-dt', label: 'Longest step', title: 'The longest update so far', time: true },
  {
    field: 'steps',
    label: 'Steps / frame',
    title: 'Updates the last display frame ran',
    time: true,
  },
  { field: 'sim', label: 'Sim time', title: 'Time as the loop has simulated it', time: true },
];

/** The per-setting table's columns; `short` labels a value when a narrow screen stacks a row. */
export const RESULT_COLUMNS: readonly {
  label: string;
  short: string;
  cls: string;
  title: string;
}[] = [
  { label: 'Speed', short: 'Speed', cls: 'col-speed', title: 'Speed of the bodies' },
  { label: 'Wall', short: 'Wall', cls: 'col-wall', title: 'Wall thickness' },
  {
    label: 'Display',
    short: 'Display',
    cls: 'col-display',
    title: 'The display the setting ran on: the variable-Δt loop takes one step per frame of it',
  },
  { label: 'Ran', short: 'Ran', cls: 'col-ran', title: 'Virtual time the setting ran for' },
  {
    label: 'Variable Δt',
    short: 'Variable Δt',
    cls: 'col-num',
    title: 'Through / resolved, variable Δt, discrete detection',
  },
  {
    label: 'Fixed step',
    short: 'Fixed step',
    cls: 'col-num',
    title: 'Through / resolved, fixed step, discrete detection',
  },
  {
    label: 'Theory, fixed',
    short: 'Theory, fixed',
    cls: 'col-num',
    title: 'The share through that geometry predicts for the fixed step',
  },
  {
    label: 'CCD',
    short: 'CCD, both',
    cls: 'col-num',
    title: 'Through / resolved, the CCD twins of both loops',
  },
];

export const RULE_ROWS: readonly { id: string; label: string; title: string }[] = [
  {
    id: 'min-wall',
    label: 'One step v·dt = minWallSize',
    title:
      'How far a body moves in one fixed step — the talk’s rule makes that the thinnest wall a body cannot jump over unseen',
  },
  {
    id: 'bounce-wall',
    label: 'All bounce if w ≥ 2(v·dt − r)',
    title: 'The thinnest wall from which every body bounces: v·dt ≤ w/2 + r',
  },
  {
    id: 'max-safe-speed',
    label: 'Max safe speed, (w/2 + r) / dt',
    title: 'The fastest body that always bounces off this wall',
  },
  {
    id: 'theory-share',
    label: 'Theory, share through',
    title: 'max(0, 1 − (w + 2r) / (2·v·dt)), fixed step, uniform phase',
  },
  {
    id: 'measured-share',
    label: 'Measured, fixed step',
    title: 'Through / resolved in the fixed-step panel, discrete detection',
  },
];

/** A share as a percentage: "44.4 %". */
export function percent(share: number): string {
  return Number.isFinite(share) ? `${(share * 100).toFixed(1)} %` : '—';
}

/** A value on a slider's grid, within its range. */

/** The display a result was measured on: "30 Hz ±30 %", "60 Hz, 1 hitch", "your display". */
export function displayText(d: ResultDisplay): string {
  if (d.hz === 'real') return 'your display';
  const jitter = d.jitter > 0 ? ` ±${Math.round(d.jitter * 100)} %` : '';
  const hitches = d.hitches > 0 ? `, ${d.hitches} hitch${d.hitches === 1 ? '' : 'es'}` : '';
  return `${d.hz} Hz${jitter}${hitches}`;
}

export function ideas(): HTMLElement {
  const cards: IdeaCard[] = [
    {
      title: 'Discrete detection',
      color: '#94a3b8',
      text: 'Move every body by v·dt, then look for overlaps and push overlapping bodies apart. Cheap, and what most engines do by default — but nothing happens between two steps.',
      snippet: 'x += v * dt\nif (overlaps(body, wall))\n  pushOut(body, wall)',
    },
    {
      title: 'The talk’s rule of thumb',
      color: CHART_COLORS.rule,
      text: 'A wall at least as thick as one step cannot be jumped over: some step always lands inside it. With a fixed step you know dt in advance, so you can size walls (or cap speeds) once.',
      snippet: 'minWallSize =\n  maxObjectSpeed * TIMESTEP',
    },
    {
      title: '…guarantees detection, not a bounce',
      color: CHART_COLORS.bounce,
      text: 'The push-out leaves through the nearer face. A body whose first overlap is past the middle of the wall is pushed out on the far side. Every body bounces only if one step is at most half the wall plus the radius.',
      snippet: 'v * dt <= w / 2 + r\nthrough = 1 - (w + 2r) / (2 v dt)',
    },
    {
      title: 'Continuous detection',
      color: CHART_COLORS.some,
      text: 'For bullets and very fast bodies: sweep the body along its path, find the time of impact, move it there and respond. It costs more, so engines use it only for bodies that need it.',
      snippet: 't = timeOfImpact(body, wall)\nx += v * dt * t\nbounce(); sweep the rest',
    },
  ];
  return ideaCards({
    id: 'ideas-title',
    title: 'Why bodies go through walls',
    cards,
    listClass: 'idea-cards',
  });
}

export function legend(): HTMLElement {
  const dot = (color: string, ring = false) =>
    h('span', {
      class: `body-dot${ring ? ' ring' : ''}`,
      style: `--dot: ${color}`,
      'aria-hidden': 'true',
    });
  return legendDetails('How to read a panel', [
    [
      [dot(BODY.flying), ' In flight'],
      'On its way to the wall. The faint streak is its jump in the last step.',
    ],
    [[dot(BODY.bounced), ' Bounced'], 'Came back off the near face; it fades out.'],
    [
      [dot(BODY.through, true), ' Through'],
      'Its centre is past the middle of the wall: it tunnelled.',
    ],
    [
      'One step',
      'The bar above the range is one step (the last one, for variable Δt), ending at the wall’s face. Past the amber mark it is longer than the wall is thick: the talk’s rule is broken and a body can jump the wall unseen. Past the end of the green bar below it, half the wall plus the radius (w/2 + r), a body can land beyond the wall’s middle and is pushed out the far side. While it is no longer than the green bar, every body bounces.',
    ],
    [
      'Through, discrete / CCD',
      'Both twins fire the same shots. The highlighted row is the one drawn; “CCD twins” draws the continuous ones instead.',
    ],
  ]);
}

export function chartLegend(): HTMLElement {
  const item = (swatch: HTMLElement, text: string) => h('li', {}, swatch, text);
  const line = (color: string, dashed = false) =>
    h('span', {
      class: `line-swatch${dashed ? ' dashed' : ''}`,
      style: `--swatch: ${color}`,
      'aria-hidden': 'true',
    });
  const area = (color: string) =>
    h('span', { class: 'area-swatch', style: `--swatch: ${color}`, 'aria-hidden': 'true' });
  const dot = (color: string) =>
    h('span', { class: 'body-dot', style: `--dot: ${color}`, 'aria-hidden': 'true' });
  return h(
    'ul',
    { class: 'chart-legend' },
    item(line(CHART_COLORS.rule), 'the talk’s rule, w = v·dt'),
    item(line(CHART_COLORS.bounce), 'every body bounces above: v·dt = w/2 + r'),
    item(line(CHART_COLORS.variable, true), 'the rule at the variable loop’s longest step'),
    item(area('rgba(248, 113, 113, 0.35)'), 'bodies can jump over the wall unseen'),
    item(area('rgba(251, 191, 36, 0.35)'), 'seen, but some are pushed out the far side'),
    item(dot(CHART_COLORS.current), 'this setting'),
    item(dot(CHART_COLORS.none), 'tried: none through (fixed step)'),
    item(dot(CHART_COLORS.some), 'tried: some through (bigger = more)'),
  );
}

export function howItWorks(): HTMLElement {
  return textSection(
    'how',
    'col-how-title',
    'How this page works',
    `Each panel runs two copies of one deterministic physics world (fixedstep’s PhysicsWorld): one with collision detection off between steps (ccd: 'off'), one with continuous detection ('auto'). Restitution is 1 and gravity is off, so a body that hits the wall comes straight back. Each shot starts up to one step of travel behind the muzzle (a seeded random phase), so the place where it first overlaps the wall is spread evenly over a step — that is what makes the theory’s share come out.`,
    'The display is simulated, as in chapter 1: its frame times are computed, so every run repeats exactly. Changing a setting rebuilds both panels and replays them from zero to the current moment. “Real clock” feeds the loops this page’s own frame times instead; then the variable loop’s steps are your display’s frames.',
  );
}
