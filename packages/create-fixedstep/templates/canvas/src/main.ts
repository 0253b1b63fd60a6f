/**
 * Your game drawn on a plain `<canvas>` (2D), no engine: the browser's requestAnimationFrame
 * calls `frame` (src/play.ts: the loop, the input, the replay, online play), and `draw` paints
 * the field from the state it hands over, interpolated between the last two ticks.
 */
import { FrameDriver, animationFrameScheduler } from 'fixedstep';
import { COINS, COIN_RADIUS, PLAYER_RADIUS } from './game.js';
import { COLORS, SCALE, field, play } from './play.js';

const ctx = field.getContext('2d')!;
const css = (color: number) => `#${color.toString(16).padStart(6, '0')}`;

const frame = play(draw);
new FrameDriver(animationFrameScheduler(), frame).start();

function draw(xy: Float64Array, players: number): void {
  ctx.fillStyle = css(COLORS.background);
  ctx.fillRect(0, 0, field.width, field.height);
  ctx.fillStyle = css(COLORS.coin);
  for (let c = 0; c < COINS; c++) {
    disc(xy[2 * (players + c)]!, xy[2 * (players + c) + 1]!, COIN_RADIUS);
  }
  for (let p = 0; p < players; p++) {
    ctx.fillStyle = css(COLORS.players[p]!);
    disc(xy[2 * p]!, xy[2 * p + 1]!, PLAYER_RADIUS);
  }
}

function disc(x: number, y: number, r: number): void {
  ctx.beginPath();
  ctx.arc(x * SCALE, y * SCALE, r * SCALE, 0, 2 * Math.PI);
  ctx.fill();
}
