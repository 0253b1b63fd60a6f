/**
 * Phaser 4 draws, fixedstep steps: the ball of ball.ts at its 60 ticks a second on any display,
 * the arrow keys sampled by timestamp, the ball drawn between its last two ticks.
 */
import Phaser from 'phaser';
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
let sprite: Phaser.GameObjects.Arc | undefined;

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
    sprite?.setPosition(xy[0]! * SCALE, xy[1]! * SCALE);
  },
});
class Field extends Phaser.Scene {
  create() {
    sprite = this.add.circle(0, 0, RADIUS * SCALE, 0x4cc2ff);
  }
  // `time` is the requestAnimationFrame timestamp; Phaser's `delta` is smoothed: never step on it.
  override update(time: number) {
    stepper.frame(time);
  }
}
// #endregion glue

new Phaser.Game({
  type: Phaser.AUTO,
  parent: 'game',
  width: WIDTH * SCALE,
  height: HEIGHT * SCALE,
  backgroundColor: '#10141c',
  scene: Field,
});

// For tests and the curious: the live objects, and where the ball was drawn (in metres).
Object.assign(window, {
  recipe: {
    game: ball,
    loop,
    drawn: () => [(sprite?.x ?? NaN) / SCALE, (sprite?.y ?? NaN) / SCALE],
  },
});
