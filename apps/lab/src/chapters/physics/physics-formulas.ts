/**
 * Chapter 4's note on the slides' two formulas: `x(t) = a·t²/2 + v·t + C`, the closed form of
 * motion under a constant acceleration, and `x_{t+1} = x_t + F(t)·t²/2 + C`, which reads like a
 * step but is not an integrator as written. The numbers come from the two functions here (pure,
 * tested): a ball thrown up at 5 m/s, one second of 1/60 s steps.
 */
import { code, h } from '../../ui/dom.js';
import { textSection } from '../../ui/prose.js';

/** The ball: thrown up at `v0` m/s under `g` m/s², stepped at `dt` s for `seconds`. */
export const THROW = { v0: 5, g: -9.81, dt: 1 / 60, seconds: 1 } as const;

/** The slide's closed form at `t`: x(t) = a·t²/2 + v·t + C (with C = 0). */
export function closedForm(t: number): number {
  return (THROW.g * t * t) / 2 + THROW.v0 * t;
}

/**
 * The slide's step taken literally: x_{t+1} = x_t + F(t)·t²/2 + C with t the time since the start
 * (as the formula writes it), F the force on 1 kg, C = 0 — no velocity anywhere.
 */
export function slideStepAsWritten(): number {
  const n = Math.round(THROW.seconds / THROW.dt);
  let x = 0;
  for (let k = 0; k < n; k++) {
    const t = k * THROW.dt;
    x = x + (THROW.g * t * t) / 2;
  }
  return x;
}

/**
 * The step it stands for: with Δt in place of t and the velocity carried from step to step,
 * x += v·Δt + a·Δt²/2; v += a·Δt — exact for a constant force.
 */
export function taylorStep(): number {
  const n = Math.round(THROW.seconds / THROW.dt);
  const dt = THROW.dt;
  let x = 0;
  let v: number = THROW.v0;
  for (let k = 0; k < n; k++) {
    x = x + v * dt + (THROW.g * dt * dt) / 2;
    v = v + THROW.g * dt;
  }
  return x;
}

/** The section, beside the integrators. */
export function formulasSection(): HTMLElement {
  const exact = closedForm(THROW.seconds);
  const literal = slideStepAsWritten();
  const step = taylorStep();
  return textSection(
    'formulas',
    'formulas-title',
    'The slides’ two formulas',
    'The talk writes the motion under a constant acceleration in closed form:',
    code('x(t) = a·t²/2 + v·t + C'),
    'and then a step from one tick to the next:',
    code('x_{t+1} = x_t + F(t)·t²/2 + C'),
    h(
      'p',
      {
        'data-testid': 'formulas-text',
        'data-value': `${exact.toFixed(4)} ${literal.toFixed(2)} ${step.toFixed(4)}`,
      },
      `The first is exact. The second is not an integrator as written: t is the time since the start where the step Δt belongs, so each step adds more than the last; there is no velocity, so nothing carries the motion from step to step (a ball thrown up never rises); F is a force, an acceleration only on 1 kg; and a constant C added at every step drifts. Taken literally, a ball thrown up at ${THROW.v0} m/s is at ${literal.toFixed(2)} m after one second of 1/60 s steps; the closed form says ${exact.toFixed(4)} m. With Δt in place of t and the velocity carried — x += v·Δt + a·Δt²/2, then v += a·Δt — the steps land on ${step.toFixed(4)} m: exact for a constant force, and the integrators below are the ways to do the same when the force changes (a spring’s does).`,
    ),
  );
}
