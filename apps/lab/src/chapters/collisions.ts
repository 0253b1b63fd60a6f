import { comingChapter } from '../ui/coming.js';

export const mount = comingChapter({
  number: 3,
  title: 'Collisions',
  lede: 'Under a variable Δt a long frame lets a fast body step straight through a wall. The talk’s rule, minWallSize = maxObjectSpeed × TIMESTEP, only guarantees that a hit is detected; a correct bounce needs v·dt ≤ w/2 + r, and bullets need continuous collision detection.',
  coming: [
    'Bullets and fast bodies against walls of adjustable thickness, under a variable Δt and a fixed step, with CCD on and off, and a count of what tunnelled.',
    'A speed × thickness chart with the talk’s rule and the correct-bounce line.',
  ],
  today:
    'The numbers already exist: `fixedstep experiment tunnel` prints the share that tunnels for every speed, wall and step, with and without CCD (see docs/collisions.md).',
});
