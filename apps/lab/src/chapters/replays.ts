import { comingChapter } from '../ui/coming.js';

export const mount = comingChapter({
  number: 5,
  title: 'Replays',
  lede: 'With a fixed step, a replay does not need to store the world: the inputs of every tick and the seeds of the random number generators are enough to compute it again, bit for bit.',
  coming: [
    'Play one of the talk’s games, then watch the replay, scrub its timeline, step back a tick.',
    'Download the replay file and load it again — it plays identically at any display rate.',
    'Highscores that cannot be faked: the server re-simulates a replay before it accepts a score.',
  ],
  today:
    'The replay format, recorder, player and verifier already exist in the library (replay/, documented in docs/replay-format.md): about 600 bytes of inputs per minute of play.',
});
