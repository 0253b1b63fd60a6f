import { comingChapter } from '../ui/coming.js';

export const mount = comingChapter({
  number: 6,
  title: 'Network',
  lede: 'When every machine steps the same world the same way, players only need to agree on the inputs and the clock — never send the state itself.',
  coming: [
    'Two players in one page through a simulated link with latency, jitter and loss.',
    'Lockstep and rollback side by side: input delay, rollback depth and hash agreement, live.',
    'Real play across two browser tabs through the server.',
  ],
});
