import type { ButtonInput } from 'fixedstep';
import {
  DIR_BUTTONS as DIR_BUTTONS_,
  DIR_X as DIR_X_,
  DIR_Y as DIR_Y_,
  FIRE,
  STRAFE,
  nearestLineOf as nearestLineOf_,
} from '../arena/motion.js';
import { nearestVisible as nearestVisible_, walkTo as walkTo_ } from '../arena/seek.js';
import {
  CTF as CTF_,
  FLAG_STAND_X as FLAG_STAND_X_,
  FLAG_STAND_Y as FLAG_STAND_Y_,
  GUARD_X as GUARD_X_,
  GUARD_Y as GUARD_Y_,
  LANE_Y as LANE_Y_,
  ctfNav as ctfNav_,
} from './layout.js';
import type { CtfGame } from './game.js';

// Local copies of imported bindings: some loaders (vitest, tsx) read an import through a
// getter on every use, which costs in hot loops.
const DIR_BUTTONS = DIR_BUTTONS_;
const DIR_X = DIR_X_;
const DIR_Y = DIR_Y_;
const nearestLineOf = nearestLineOf_;
const nearestVisible = nearestVisible_;
const walkTo = walkTo_;
const CTF = CTF_;
const FLAG_STAND_X = FLAG_STAND_X_;
const FLAG_STAND_Y = FLAG_STAND_Y_;
const GUARD_X = GUARD_X_;
const GUARD_Y = GUARD_Y_;
const LANE_Y = LANE_Y_;
const ctfNav = ctfNav_;

/** Farther than this, a bot does not shoot (a bullet flies 720 units). */
const RANGE = 320;
/** An attacker ignores enemies farther than this. */
const ATTACKER_RANGE = 100;
/** A runner (the first bot of each team) shoots only what is in its way. */
const RUNNER_RANGE = 70;
/** Nearer than this, a defender manoeuvres to get a shot. */
const ENGAGE = 260;
/** Nearer than this, an attacker (not carrying a flag) manoeuvres to get a shot. */
const ENGAGE_ATTACKER = 100;
/** A shot is taken when the target is within this of a firing line. */
const ALIGN = 6;
/** The clearance a line of fire needs from walls (a bullet's radius plus some of the spread). */
const LOS_CLEARANCE = 6;
/** How far ahead a sidestep is checked for walls. */
const PROBE = 14;

/** Within this of the centre line, a lane has done its job. */
const LANE_REACHED = 24;

/** A lane (0–3) for `slot`: a hash of the seed, the slot and the current 15 s period. */
function laneOf(seed: number, slot: number, tick: number): number {
  let h = Math.imul(seed ^ 0x9e3779b9, 0x85ebca6b) ^ Math.imul(slot + 1, 0xc2b2ae35);
  h = Math.imul(h ^ Math.floor(tick / 900), 0x27d4eb2f);
  h ^= h >>> 15;
  return (h >>> 0) % 4;
}

/** Scratch (never state): a signed distance, a squared one, an offset. */
const perp = new Float64Array(1);
const offset = new Float64Array(2);
const dist2 = new Float64Array(1);

/**
 * The capture-the-flag AI, for one slot: a pure function of the state (it reads, never writes,
 * and draws no random numbers), so the registry's bot and the game's own bots are the same code
 * and a replay needs only the inputs.
 *
 * Roles by a slot's rank in its team: 0 runner (slots 0 and 1: goes for the flag, shoots only
 * what is in its way), 1 defender, 2 and 3 attackers. Each tick: if a visible enemy is within the
 * role's range and sits on one of the eight firing lines, face it and fire. Otherwise pick a
 * goal — carrying the enemy flag: home (a carrier does not fight); own flag dropped: go return
 * it; own flag carried: hunt the carrier; defender: guard the flag; the others: the enemy flag
 * (or escort the team's carrier), crossing the centre by one of four lanes. A defender (or an
 * attacker, at closer range) with an enemy near sidesteps onto a firing line; everyone else walks
 * the navigation grid to the goal. Line of sight is a swept test against the walls, so thin
 * walls block it as they block bullets.
 */
export function ctfBotInput(game: CtfGame, p: number): ButtonInput {
  const s = game.state;
  if (s.alive[p] === 0) return 0;
  const walls = game.walls;
  const x = s.x[p]!;
  const y = s.y[p]!;
  const team = p & 1;
  const foe = 1 - team;
  const carrying = game.carrying(p) >= 0;

  // The nearest visible enemy in range (attackers look less far: they have a flag to take).
  const role = p >> 1; // 0: runner, 1: defender, 2–3: attackers
  const defender = role === 1;
  const runner = role === 0;
  // A carrier does not stop to fight: it runs home.
  const range = carrying ? 0 : defender ? RANGE : runner ? RUNNER_RANGE : ATTACKER_RANGE;
  // In sight: clear for the bullet and most of its spread. The enemies are on every other slot.
  const target = nearestVisible(
    walls,
    s.x,
    s.y,
    p,
    range,
    LOS_CLEARANCE,
    s.alive,
    s.x,
    s.y,
    dist2,
    foe,
    2,
  );
  const best = dist2[0]!;
  let line = -1;
  if (target >= 0) {
    // No lead: a target that is itself sidestepping reverses every few ticks, and leading it
    // only makes both bots dance.
    offset[0] = s.x[target]! - x;
    offset[1] = s.y[target]! - y;
    line = nearestLineOf(offset, perp);
    if (line >= 0 && Math.abs(perp[0]!) < ALIGN && s.protect[target] === 0) {
      return DIR_BUTTONS[line]! | FIRE;
    }
  }

  // The goal.
  const own = s.flagState[team]!;
  let gx: number;
  let gy: number;
  if (carrying) {
    gx = FLAG_STAND_X[team]!;
    gy = FLAG_STAND_Y[team]!;
  } else if (own !== 0) {
    // Own flag away: return it (dropped) or chase whoever has it (carried).
    gx = s.flagX[team]!;
    gy = s.flagY[team]!;
  } else if (defender) {
    gx = GUARD_X[team]!;
    gy = GUARD_Y[team]!;
  } else {
    gx = s.flagX[foe]!;
    gy = s.flagY[foe]!;
  }
  // Attackers and carriers cross the centre by one of four lanes, chosen per slot and per
  // 15 s by a hash of the seed, so the two teams do not all meet head-on in the middle.
  if ((carrying || !defender) && own === 0) {
    const half = CTF.width / 2;
    const side = x < half ? 0 : 1;
    const goalSide = gx < half ? 0 : 1;
    if (side !== goalSide && Math.abs(x - half) > LANE_REACHED) {
      const lane = laneOf(game.seed, p, s.tick);
      gx = half;
      gy = LANE_Y[lane]!;
    }
  }

  // Close enemy, not carrying: sidestep onto a firing line (strafing keeps the facing).
  const engage = defender ? ENGAGE : runner ? 0 : ENGAGE_ATTACKER;
  if (line >= 0 && !carrying && best < engage * engage) {
    const side = perp[0]! > 0 ? (line + 2) & 7 : (line + 6) & 7;
    const ux = DIR_X[side]!;
    const uy = DIR_Y[side]!;
    // Only where there is room, and where the target stays in sight (else it would flicker
    // between sidestepping and walking on).
    // (The walls' register form: see `Walls`.)
    const q = walls.query;
    q[0] = x;
    q[1] = y;
    q[2] = x + ux * PROBE;
    q[3] = y + uy * PROBE;
    if (walls.clearQuery(CTF.playerRadius)) {
      q[0] = x + ux * 3;
      q[1] = y + uy * 3;
      q[2] = s.x[target]!;
      q[3] = s.y[target]!;
      if (walls.clearQuery(LOS_CLEARANCE)) return DIR_BUTTONS[side]! | STRAFE;
    }
  }

  const dx = gx - x;
  const dy = gy - y;
  if (dx * dx + dy * dy < 16) return 0;
  const nav = ctfNav();
  const q = nav.query;
  q[0] = x;
  q[1] = y;
  q[2] = gx;
  q[3] = gy;
  return walkTo(nav);
}
