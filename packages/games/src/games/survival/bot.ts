import type { ButtonInput } from 'fixedstep';
import {
  DIR_BUTTONS as DIR_BUTTONS_,
  DIR_X as DIR_X_,
  DIR_Y as DIR_Y_,
  FIRE,
  STRAFE,
  nearestLineOf as nearestLineOf_,
} from '../arena/motion.js';
import {
  nearestLive as nearestLive_,
  nearestVisible as nearestVisible_,
  walkTo as walkTo_,
} from '../arena/seek.js';
import { SURVIVAL as SURVIVAL_, survivalNav as survivalNav_ } from './layout.js';
import type { SurvivalGame } from './game.js';

// Local copies of imported bindings: some loaders (vitest, tsx) read an import through a
// getter on every use, which costs in hot loops.
const DIR_BUTTONS = DIR_BUTTONS_;
const DIR_X = DIR_X_;
const DIR_Y = DIR_Y_;
const nearestLineOf = nearestLineOf_;
const nearestLive = nearestLive_;
const nearestVisible = nearestVisible_;
const walkTo = walkTo_;
const SURVIVAL = SURVIVAL_;
const survivalNav = survivalNav_;
/** Farther than this, the bot does not shoot. */
const RANGE = 480;
/** A shot is taken when the target is within this of a firing line. */
const ALIGN = 6;
/** How far ahead each escape route is checked and scored. */
const PROBE = 30;
/** With no enemy nearer than this, a lined-up bot stands still to shoot. */
const CALM = 90;
/** Enemies nearer than this to a probe point count as danger. */
const DANGER = 200;

/** Scratch (never state): a signed distance, a squared one, an offset, the live enemies. */
const perp = new Float64Array(1);
const offset = new Float64Array(2);
const dist2 = new Float64Array(1);
const live = new Int32Array(SURVIVAL_.enemyCapacity);

/**
 * The survival bot, for one player: a pure function of the state (reads only, no random
 * numbers). Each tick it scores the eight directions and standing still — walls ahead rule a
 * direction out; the nearer the enemies to where it would be, the worse; drifting from the
 * centre costs a little; closing on a firing line to the nearest visible enemy gains a little —
 * and takes the best, strafing so it keeps its aim. With no enemy in sight or near, it walks
 * the navigation grid to the nearest one. When that enemy sits on the line it is
 * facing it fires; on another line, it turns to it (one step that way) and fires.
 */
export function survivalBotInput(game: SurvivalGame, p: number): ButtonInput {
  const s = game.state;
  if (s.alive[p] !== 1) return 0;
  const walls = game.walls;
  const x = s.x[p]!;
  const y = s.y[p]!;

  // The nearest visible enemy in range, and how to line up a shot at it.
  const clearance = SURVIVAL.bulletRadius + 4;
  const target = nearestVisible(
    walls,
    s.x,
    s.y,
    p,
    RANGE,
    clearance,
    s.enemyAlive,
    s.ex,
    s.ey,
    dist2,
  );
  let line = -1;
  let aligned = false;
  if (target >= 0) {
    offset[0] = s.ex[target]! - x;
    offset[1] = s.ey[target]! - y;
    line = nearestLineOf(offset, perp);
    aligned = line >= 0 && Math.abs(perp[0]!) < ALIGN;
    if (aligned && line !== s.facing[p]) return DIR_BUTTONS[line]! | FIRE;
  }

  // Nothing in sight and nothing near: go and find the nearest enemy (the wave will not end
  // while one waits behind a wall).
  const nearest = nearestLive(s.x, s.y, p, s.enemyAlive, s.ex, s.ey, dist2);
  const nearest2 = dist2[0]!;
  if (target < 0 && nearest >= 0 && nearest2 > DANGER * DANGER) {
    const nav = survivalNav();
    const q = nav.query;
    q[0] = x;
    q[1] = y;
    q[2] = s.ex[nearest]!;
    q[3] = s.ey[nearest]!;
    return walkTo(nav);
  }

  // The live enemies, in slot order (each direction sums their danger in that order).
  let n = 0;
  for (let e = 0; e < SURVIVAL.enemyCapacity; e++) if (s.enemyAlive[e] !== 0) live[n++] = e;

  // Where to go: score standing still and the eight directions.
  const cx = SURVIVAL.width / 2;
  const cy = SURVIVAL.height / 2;
  let choice = -1;
  let bestScore = -Infinity;
  for (let d = -1; d < 8; d++) {
    let qx = x;
    let qy = y;
    if (d >= 0) {
      qx = x + DIR_X[d]! * PROBE;
      qy = y + DIR_Y[d]! * PROBE;
      const q = walls.query;
      q[0] = x;
      q[1] = y;
      q[2] = qx;
      q[3] = qy;
      if (!walls.clearQuery(SURVIVAL.playerRadius)) continue;
    }
    let danger = 0;
    for (let k = 0; k < n; k++) {
      const e = live[k]!;
      const dx = s.ex[e]! - qx;
      const dy = s.ey[e]! - qy;
      const d2 = dx * dx + dy * dy;
      if (d2 < DANGER * DANGER) danger += 1 / (d2 + 100);
    }
    const ox = qx - cx;
    const oy = qy - cy;
    let score = -4000 * danger - 0.00001 * (ox * ox + oy * oy);
    if (target >= 0 && !aligned && d >= 0) {
      // Moving by d changes the target's offset from the firing line by −(d × line normal).
      const nx = -DIR_Y[line]!;
      const ny = DIR_X[line]!;
      const gain = (perp[0]! > 0 ? 1 : -1) * (DIR_X[d]! * nx + DIR_Y[d]! * ny);
      if (gain > 0) score += 0.2 * gain;
    }
    if (score > bestScore) {
      bestScore = score;
      choice = d;
    }
  }
  // Lined up and nothing close: stand and fire (moving would spoil the aim).
  if (aligned && nearest2 > CALM * CALM) return FIRE;
  let input = aligned ? FIRE : 0;
  if (choice >= 0) input |= DIR_BUTTONS[choice]! | STRAFE;
  return input;
}
