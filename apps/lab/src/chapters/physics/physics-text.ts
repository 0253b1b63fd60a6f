/**
 * What chapter 4 says: the integrators' colours, names and update rules, the lede, the intros, the
 * idea cards, the "Things to try" texts, how numbers are written, and "How this page works".
 */
import { INTEGRATOR_INFO, INTEGRATOR_METHODS, type IntegratorMethod } from 'fixedstep';
import { h } from '../../ui/dom.js';
import { textSection } from '../../ui/prose.js';
import { ideaCards, type IdeaCard } from '../../ui/cards.js';
import * as fmt from '../../ui/format.js';
import { EXPLODE_AT, ROPE_BEADS, X0, type Stability } from './physics-lab.js';

export const COLORS: Readonly<Record<IntegratorMethod, string>> = {
  'explicit-euler': '#f87171',
  'semi-implicit-euler': '#f5a524',
  'backward-euler': '#a78bfa',
  'position-verlet': '#34d399',
  'velocity-verlet': '#38bdf8',
  rk4: '#f472b6',
};

export const SHORT: Readonly<Record<IntegratorMethod, string>> = {
  'explicit-euler': 'Explicit Euler',
  'semi-implicit-euler': 'Semi-implicit',
  'backward-euler': 'Backward Euler',
  'position-verlet': 'Position Verlet',
  'velocity-verlet': 'Velocity Verlet',
  rk4: 'RK4',
};

export const UPDATE: Readonly<Record<IntegratorMethod, string>> = {
  'explicit-euler': 'x += v·dt; v += a(x₀)·dt',
  'semi-implicit-euler': 'v += a·dt; x += v·dt',
  'backward-euler': 'v₁ = v₀ + a(x₁)·dt; x₁ = x₀ + v₁·dt',
  'position-verlet': 'x₊ = 2x − x₋ + a·dt²',
  'velocity-verlet': 'v += ½a·dt; x += v·dt; v += ½a·dt',
  rk4: 'four stages, weights 1 2 2 1',
};

export const LEDE =
  'A simulation advances positions and velocities in steps: an integrator. The simplest one, Euler’s (move with the old velocity, then update it), is exact only for constant forces. On a spring — the force grows with the stretch — the small error of each step feeds itself: the spring gains energy every step until it blows up. Swap the two lines, as the talk’s own code does, and it holds; push the step or the stiffness too far and every explicit method blows up. A fixed step makes the behaviour at least the same everywhere; the integrator decides whether it is right.';

export const SPRING_INTRO = `A 1 kg mass on a spring, pulled ${X0} m and let go: x'' = −ω²x with ω = √(k/m). Each panel integrates the very same spring with the same fixed step; the dashed circle on the right is the exact motion in phase space (x against v/ω), the coloured trace is the method’s. Whether a method survives depends only on ω·dt.`;

export const ROPE_INTRO = `${ROPE_BEADS} beads of 100 g on springs, pinned at both ends, under gravity, with the step above. A rope has many modes at once; the fastest, ω ≈ 2√(k/m), decides stability. Poke it; then stiffen the links, or pick another integrator, and poke again.`;

export const TRY: Readonly<
  Record<
    'exploding' | 'past2' | 'smaller' | 'stiffrope',
    { title: string; text: string; action: string }
  >
> = {
  exploding: {
    title: 'The talk’s exploding spring',
    text: 'k = 20 N/m at the talk’s 30 ms: ω·dt ≈ 0.13, tiny. Explicit Euler still gains 1.8 % per step — ×380 in 10 s — while the talk’s own code (semi-implicit Euler) wobbles within 7 % and velocity Verlet within 0.5 %.',
    action: 'Run 10 s',
  },
  past2: {
    title: 'Just past 2',
    text: 'k = 5000 N/m at 30 ms: ω·dt ≈ 2.12. Semi-implicit Euler and both Verlets blow up within the first second; RK4 (limit 2√2) stays bounded but drains the motion away, backward Euler too. Smaller steps, not cleverer code, are what fixes a stiff spring.',
    action: 'k = 5000 N/m',
  },
  smaller: {
    title: 'A smaller step',
    text: 'The talk’s spring at 15 ms instead of 30 for 10 s. Explicit Euler’s growth per step falls four times and it takes twice the steps: ×20 instead of ×380 — better, still wrong. Everyone else gets closer to 1: the error of the first-order methods halves, the Verlets’ quarters.',
    action: 'Step 15 ms',
  },
  stiffrope: {
    title: 'Only backward Euler survives',
    text: 'Stiffen the rope’s links to 1000 N/m at 30 ms: its fastest mode has ω·dt ≈ 6. Every explicit method shreds it within a few steps; backward Euler stays calm — and you can see it drain the swing away.',
    action: 'Stiff rope',
  },
};

export function zoomText(z: number): string {
  if (z >= 1e4) return fmt.sci(z, 0);
  return z >= 10 ? z.toFixed(0) : z.toFixed(1);
}

/** E/E₀ for a readout: 4 significant digits near 1, then grouped, then powers of ten. */
export function energyText(r: number): string {
  if (!Number.isFinite(r)) return '—';
  if (r >= 1e5 || (r > 0 && r < 1e-3)) return `${fmt.sci(r)}×`;
  if (r >= 100) return `${fmt.count(r)}×`;
  return `${r.toFixed(4)}×`;
}

/** max |ΔE| / E₀: a percentage below 10×, a factor above (an explosion). */
export function errorText(e: number): string {
  if (!Number.isFinite(e)) return '∞';
  if (e >= 1e5) return `${fmt.sci(e)}×`;
  if (e >= 10) return `${fmt.count(e)}×`;
  return `${(e * 100).toFixed(2)} %`;
}

export function verdictText(st: Stability): string {
  switch (st) {
    case 'grows':
      return 'grows at any ω·dt';
    case 'damped':
      return 'stable, damps';
    case 'stable':
      return 'stable';
    case 'unstable':
      return 'explodes';
  }
}

export function methodsIntro(): HTMLElement {
  const cards: IdeaCard[] = [
    {
      title: 'Explicit Euler',
      color: COLORS['explicit-euler'],
      text: 'Both updates from the old state. On a spring every step multiplies the energy by 1 + (ω·dt)², at any step size: this is the spring that explodes.',
      snippet: 'position += velocity * dt\nvelocity += acceleration * dt',
    },
    {
      title: 'The talk’s code: semi-implicit Euler',
      color: COLORS['semi-implicit-euler'],
      text: 'Swap the two lines — velocity first, then move with the new velocity — and the energy stays bounded while ω·dt < 2. The slides’ own loop is this one: it wobbles but holds at the talk’s spring, and explodes only for stiff springs. The explosion the talk shows is what card 1 does.',
      snippet: 'velocity += acceleration * dt\nposition += velocity * dt',
    },
    {
      title: 'The alternatives',
      color: COLORS['velocity-verlet'],
      text: 'Backward (implicit) Euler solves for the end of the step: never unstable, but it drains energy. Verlet and velocity Verlet are second order and keep energy for ever below ω·dt = 2. RK4 is the most accurate per step, costs four force evaluations and slowly loses energy.',
      snippet: 'v += ½a·dt;  x += v·dt\na = force(x) / m\nv += ½a·dt   // velocity Verlet',
    },
  ];
  return ideaCards({
    id: 'methods-title',
    title: 'Integrators',
    cards,
    listClass: 'method-cards',
  });
}

export function energyLegend(): HTMLElement {
  return h(
    'ul',
    { class: 'chart-legend energy-legend' },
    INTEGRATOR_METHODS.map((m) =>
      h(
        'li',
        {},
        h('span', { class: 'line-swatch', style: `--swatch: ${COLORS[m]}`, 'aria-hidden': 'true' }),
        INTEGRATOR_INFO[m].label,
      ),
    ),
  );
}

export function howItWorks(): HTMLElement {
  return textSection(
    'how',
    'phys-how-title',
    'How this page works',
    `The six panels are one deterministic simulation: fixedstep’s integrators on one harmonic oscillator, stepped in lockstep by a fixed-step loop (FixedLoop) with the step you chose. Energy is ½v² + ½ω²x² per kilogram; a method whose energy passes ${fmt.sci(EXPLODE_AT, 0)} times the start is stopped and marked exploded. The rope is a SpringSystem (fixedstep’s springs) that starts hanging at rest.`,
    'The display is simulated, as in chapter 1, so every number repeats. The loop draws each mass and bead between its last two steps, at α = accumulator / step. Changing the step, a stiffness or the rope’s integrator rebuilds everything and replays it — pokes included — from zero to the current moment. “Real clock” drives the loop with this page’s own frame times.',
  );
}
