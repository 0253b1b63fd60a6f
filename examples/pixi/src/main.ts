/**
 * PixiJS 8 draws, fixedstep steps: the ball of ball.ts at its 60 ticks a second on any display,
 * the arrow keys sampled by timestamp, the ball drawn between its last two ticks.
 */
// PixiJS builds its shader code with `new Function` unless this module is loaded first: with it,
// the page runs under a Content-Security-Policy without 'unsafe-eval' — `fixedstep serve`'s.
import 'pixi.js/unsafe-eval';
import { Application, Graphics } from 'pixi.js';
import {
  FixedLoop,
  FrameStepper,
  InputSampler,
  InterpolationBuffer,
  attachKeyboard,
  trackVisibility,
} from 'fixedstep';
import { HEIGHT, RADIUS, WIDTH, ballGame } from './ball.js';

const SCALE = 60; // pixels per metre
const ball = ballGame.create({ seed: 1, players: 1, options: new Uint8Array(0) });
const app = new Application();
await app.init({ width: WIDTH * SCALE, height: HEIGHT * SCALE, background: '#10141c' });
document.querySelector('#game')!.appendChild(app.canvas);
const sprite = new Graphics().circle(0, 0, RADIUS * SCALE).fill(0x4cc2ff);
app.stage.addChild(sprite);

// #region glue
const input = new InputSampler(ballGame.input);
const keys = { ArrowLeft: 'left', ArrowRight: 'right', ArrowUp: 'up', ArrowDown: 'down' };
attachKeyboard(window, input, { ...keys, Space: 'kick' });
const loop = new FixedLoop({ step: ballGame }); // the game's tick rate
trackVisibility(document, loop);
const view = new InterpolationBuffer({ fields: 2, capacity: 1 });
view.store(0, ball.x, ball.y);
const stepper = new FrameStepper({
  loop,
  input,
  update: (_dt, tickInput) => {
    view.beginTick();
    ball.step([tickInput]);
    view.store(0, ball.x, ball.y);
  },
  render: (alpha) => {
    const xy = view.interpolate(alpha);
    sprite.position.set(xy[0]! * SCALE, xy[1]! * SCALE);
  },
});
// Inside a listener `lastTime` is still the previous frame's timestamp, and `deltaMS` is clamped
// to 100 ms and scaled by `ticker.speed`: this frame's timestamp is lastTime + elapsedMS.
app.ticker.add((ticker) => stepper.frame(ticker.lastTime + ticker.elapsedMS));
// #endregion glue

// For tests and the curious: the live objects, and where the ball was drawn (in metres).
Object.assign(window, {
  recipe: { game: ball, loop, drawn: () => [sprite.x / SCALE, sprite.y / SCALE] },
});
