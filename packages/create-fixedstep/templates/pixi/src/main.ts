/**
 * Your game drawn by PixiJS 8: circles (Graphics) on the stage, moved each frame to where
 * src/play.ts says the players and coins are, between the last two ticks.
 *
 * PixiJS draws; it does not run the game. Its ticker calls fixedstep's loop with the frame's
 * timestamp, and the loop decides how many fixed steps the game takes — the ticker's `deltaMS`
 * (clamped to 100 ms, scaled by `ticker.speed`) plays no part in the simulation.
 */
// PixiJS builds its shader code with `new Function` unless this module is loaded first: with it,
// the page runs under a Content-Security-Policy without 'unsafe-eval' — `fixedstep serve`'s.
import 'pixi.js/unsafe-eval';
import { Application, Graphics } from 'pixi.js';
import { COINS, COIN_RADIUS, PLAYER_RADIUS } from './game.js';
import { COLORS, MAX_PLAYERS, SCALE, field, play } from './play.js';

const app = new Application();
await app.init({
  canvas: field,
  width: field.width,
  height: field.height,
  background: COLORS.background,
  antialias: true,
});
const disc = (radius: number, color: number) => {
  const g = new Graphics().circle(0, 0, radius * SCALE).fill(color);
  g.visible = false;
  return app.stage.addChild(g);
};
const coins = Array.from({ length: COINS }, () => disc(COIN_RADIUS, COLORS.coin));
const players = COLORS.players.slice(0, MAX_PLAYERS).map((c) => disc(PLAYER_RADIUS, c));

const frame = play((xy, playing) => {
  players.forEach((g, p) => {
    g.visible = p < playing;
    if (g.visible) g.position.set(xy[2 * p]! * SCALE, xy[2 * p + 1]! * SCALE);
  });
  coins.forEach((g, c) => {
    const i = playing + c;
    g.visible = true;
    g.position.set(xy[2 * i]! * SCALE, xy[2 * i + 1]! * SCALE);
  });
});
// Inside a listener `lastTime` is still the previous frame's timestamp: this frame's is
// lastTime + elapsedMS (the raw time since then). The stage is rendered after the listeners.
app.ticker.add((ticker) => {
  frame(ticker.lastTime + ticker.elapsedMS);
});
