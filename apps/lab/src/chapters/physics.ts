import { comingChapter } from '../ui/coming.js';

export const mount = comingChapter({
  number: 4,
  title: 'Physics',
  lede: 'A spring integrated with explicit Euler at the talk’s 0.03 s step gains energy every step until it explodes. Semi-implicit Euler, the Verlets and RK4 stay bounded below their stability limits; backward Euler never explodes but loses energy.',
  coming: [
    'The same spring under six integrators side by side, with a live energy plot.',
    'Step size and stiffness sliders with each method’s stability limit, and a rope of springs to poke.',
  ],
  today:
    'The numbers already exist: `fixedstep experiment integrators --svg energy.svg` prints each method’s energy ratio and phase error and plots the energy (see docs/integrators.md).',
});
