/**
 * What chapter 2 says: the lede, the bench's intro, the legend, "Why the variable-Δt jumps differ"
 * and "How this page works". Numbers come from the model's constants.
 */
import { legendDetails, textSection, whyCards } from '../../ui/prose.js';
import { STEP_MS, SWEEP_RATES, type LoopReadouts } from './movement-lab.js';

export const LEDE =
  'A jump is a few lines of Euler integration: add gravity to the velocity, add the velocity to the position. Hand those lines a different Δt and they trace a different arc. With a variable Δt, every display rate — and every hiccup of the frame clock — gets its own jump. With a fixed step, everyone gets the designer’s jump.';

export const BENCH_INTRO =
  'A runner starts, jumps (holding the button for 0.18 s), lands and brakes; every 2.5 s it starts again. The same timestamped button presses reach four simulated displays — 30, 60, 144 and 240 Hz, each with its own frame jitter. Each loop traces its four runs over each other, widest line for 30 Hz, thinnest for 240 Hz: where they coincide you see one striped line.';

export const SWEEP_TITLE = `The same jump at ${SWEEP_RATES.length} display rates`;

export const SWEEP_INTRO = `The first jump of the script, run headless at every rate from ${SWEEP_RATES[0]} to ${SWEEP_RATES[SWEEP_RATES.length - 1]} Hz with the jitter above. Under a variable Δt the result depends on the display; under a fixed step it is one number.`;

/**
 * A panel's verdict: how many different jumps its displays computed (counted, not assumed), and by
 * how much they differ (`spread` formats metres).
 */
export function verdictText(r: LoopReadouts, spread: (metres: number) => string): string {
  if (r.jumpIndex < 0) return 'Waiting for the first landing…';
  const n = r.rows.length;
  const jumps = new Set(r.rows.map((row) => `${row.jump?.apex}|${row.jump?.distance}`)).size;
  if (jumps === 1) return `${n} displays, one jump — identical to the last bit.`;
  return `${n} displays, ${jumps} different jumps: the apex varies by ${spread(r.apexSpread)}, the landing by ${spread(r.landingSpread)}.`;
}

export function legend(): HTMLElement {
  return legendDetails('How to read the panels', [
    [
      'Lines',
      'Every position the simulation computed in this round, one line per display. Coinciding lines look like one striped line.',
    ],
    [
      'Runners',
      `Each as its own display last drew it. A 30 Hz display shows an older frame than a 240 Hz one, so moving runners can be a frame apart even when their paths are identical. The fixed-step runners are drawn between their last two ${STEP_MS} ms steps (interpolation).`,
    ],
    [
      'Ticks',
      'The short bar at the top of each arc is the apex; the marks under the floor are the landings, one row per display.',
    ],
    [
      'Apex, landing distance',
      'The highest point of the jump above the floor, and the distance from take-off to landing, as each simulation computed them. Spread is the largest minus the smallest.',
    ],
  ]);
}

export function why(): HTMLElement {
  return textSection(
    'why',
    'why-title',
    'Why the variable-Δt jumps differ',
    whyCards([
      {
        title: 'Euler depends on Δt',
        text: 'Each update moves the runner by its velocity times Δt, then gravity bends the velocity. Big steps overshoot the curve differently from small ones, so the apex and the airtime change with the frame rate — by centimetres here, by whole platforms in a real level.',
        snippet: 'vy -= gravity * dt\ny  += vy * dt   // the arc depends on dt',
      },
      {
        title: 'Inputs land on frames',
        text: 'With one update per frame, a button press takes effect on the next frame — up to 33 ms late at 30 Hz, 4 ms at 240 Hz — and so does letting go of the jump button, which decides how high the jump goes. A fixed step gives each press to the step whose time span contains it, whatever the display.',
        snippet:
          '// fixed step: same ticks, same inputs\nwhile (acc >= STEP) { update(STEP, input(tick)); acc -= STEP }',
      },
      {
        title: 'Jitter makes it worse',
        text: 'Real frames are never exactly 1/60 s. Under a variable Δt the same display gives a slightly different jump each time; drag the jitter slider to 0 and the variable runs still disagree, because the rates differ. Under a fixed step neither matters.',
      },
    ]),
  );
}

export function how(): HTMLElement {
  return textSection(
    'how',
    'movement-how-title',
    'How this page works',
    'The four displays are simulated: their frame times are computed from the rate and a seeded jitter, so the numbers repeat on every machine. The page moves a virtual clock forward at real speed and runs the frames due; “Skip +5 s” moves it at once. Changing the jitter or pressing Jump replays every run from zero to the current moment, which lands exactly where a live run would be.',
    '“Real clock” adds a fifth run to each loop, driven by this page’s own animation frames. Under the fixed step it still traces the very same jump, to the last bit.',
  );
}
