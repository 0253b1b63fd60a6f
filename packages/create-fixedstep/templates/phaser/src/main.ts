/**
 * Your game drawn by Phaser 4: a scene of circles, moved each frame to where src/play.ts says the
 * players and coins are, between the last two ticks.
 *
 * Phaser draws; it does not run the game. Its clock, its `delta` and its physics (Arcade,
 * Matter) play no part in the simulation: none is configured, and the scene's `update` only
 * passes the frame's timestamp to fixedstep's loop, which decides how many fixed steps the game
 * takes. That is what keeps the game deterministic — the same on every machine, in a replay, on
 * the server — while Phaser draws at whatever rate the display runs.
 */
import Phaser from 'phaser';
import { COINS, COIN_RADIUS, PLAYER_RADIUS } from './game.js';
import { COLORS, MAX_PLAYERS, SCALE, field, play, type Frame } from './play.js';

class Field extends Phaser.Scene {
  private frame: Frame | undefined;
  private readonly players: Phaser.GameObjects.Arc[] = [];
  private readonly coins: Phaser.GameObjects.Arc[] = [];

  create(): void {
    for (let c = 0; c < COINS; c++) {
      this.coins.push(this.add.circle(0, 0, COIN_RADIUS * SCALE, COLORS.coin).setVisible(false));
    }
    for (let p = 0; p < MAX_PLAYERS; p++) {
      const color = COLORS.players[p]!;
      this.players.push(this.add.circle(0, 0, PLAYER_RADIUS * SCALE, color).setVisible(false));
    }
    this.frame = play((xy, players) => {
      this.draw(xy, players);
    });
  }

  // `time` is the requestAnimationFrame timestamp. Phaser's `delta` (the second argument) is
  // smoothed — Phaser averages recent frames and replaces outliers — so it is never used here.
  override update(time: number): void {
    this.frame?.(time);
  }

  private draw(xy: Float64Array, players: number): void {
    this.players.forEach((arc, p) => {
      arc.setVisible(p < players);
      if (p < players) arc.setPosition(xy[2 * p]! * SCALE, xy[2 * p + 1]! * SCALE);
    });
    this.coins.forEach((arc, c) => {
      const i = players + c;
      arc.setVisible(true).setPosition(xy[2 * i]! * SCALE, xy[2 * i + 1]! * SCALE);
    });
  }
}

// WebGL where the browser has it, else Canvas 2D: the choice Phaser.AUTO makes, which Phaser
// refuses to make for a canvas of the page's own (it probes a spare canvas the same way).
const webGL = document.createElement('canvas').getContext('webgl') !== null;
new Phaser.Game({
  type: webGL ? Phaser.WEBGL : Phaser.CANVAS,
  canvas: field,
  width: field.width,
  height: field.height,
  backgroundColor: COLORS.background,
  // fixedstep's input sampler reads the keyboard (each key with its own timestamp): Phaser's
  // keyboard plugin stays off, so it neither captures keys nor keeps a second copy of them.
  input: { keyboard: false },
  scene: Field,
});
