import { describe, expect, it } from 'vitest';
import { FixedLoop, VariableLoop, hex64, type Loop } from 'fixedstep';
import {
  OBSTACLE_KINDS,
  RUNNER_TUNING,
  RunnerButtons,
  RunnerGame,
  RunnerRig,
  type ScriptedInput,
} from '@fixedstep/games';

/**
 * The talk's movement demo on the runner: one scripted play — a free jump at 1.0 s, then a jump
 * at `pressMs` for the first obstacle (a tall one at 40 m with seed 1) — fed with timestamps
 * through a loop and a simulated display, like `LoopRig`.
 */
const SEED = 1;
const END_MS = 4500;

function script(pressMs: number): ScriptedInput[] {
  const jump = RunnerButtons.jump;
  return [
    { timeMs: 1000, button: jump, down: true },
    { timeMs: 1080, button: jump, down: false },
    { timeMs: pressMs, button: jump, down: true },
    { timeMs: pressMs + 80, button: jump, down: false },
  ];
}

interface Play {
  /** Whether the run ended (a crash) by END_MS. */
  over: boolean;
  /** Where the player stands at the end, m. */
  distance: number;
  /** Highest feet height of the free jump, m. */
  apex: number;
  /** Ground covered by the free jump, take-off to landing, m. */
  length: number;
  /** The state hash after every update. */
  hashes: string[];
}

function play(loop: Loop, hz: number, pressMs: number, jitter = 0): Play {
  const game = new RunnerGame({ seed: SEED, players: 1 });
  let apex = 0;
  let takeoff = NaN;
  let landing = NaN;
  let grounded = true;
  const hashes: string[] = [];
  const rig: RunnerRig = new RunnerRig({
    game,
    loop,
    display: { hz, jitter, seed: 3 },
    script: script(pressMs),
    onUpdate: () => {
      hashes.push(hex64(game.hash()));
      if (rig.realMs >= 2500) return; // only the free jump
      apex = Math.max(apex, game.y);
      if (grounded && !game.onGround) takeoff = game.distance;
      if (!grounded && game.onGround) landing = game.distance;
      grounded = game.onGround;
    },
  });
  rig.runUntil(END_MS);
  return { over: game.over, distance: game.distance, apex, length: landing - takeoff, hashes };
}

const fixed = () => new FixedLoop({ step: RUNNER_TUNING.tickRate });
const variable = () => new VariableLoop();

/** Whether the player crashed into the first obstacle (and not anything else). */
function crashedAtFirst(p: Play): boolean {
  const first = RUNNER_TUNING.firstObstacle;
  return p.over && p.distance > first - RUNNER_TUNING.playerWidth && p.distance < first + 0.5;
}

describe('runner: the same play under a variable Δt and a fixed step', () => {
  it('the course: seed 1 puts a tall obstacle first, at 40 m', () => {
    const game = new RunnerGame({ seed: SEED, players: 1 });
    expect(OBSTACLE_KINDS[game.obstacleKind(0)]!.name).toBe('tall');
    expect(game.obstacleX(0)).toBe(RUNNER_TUNING.firstObstacle);
  });

  // A press at 3510 ms clears the tall obstacle at 60 Hz (any press from 3470 to 3715 ms does);
  // at 20 Hz only presses from 3555 ms on clear it.
  const PRESS_MS = 3510;

  it('variable Δt: the jump is lower and shorter at 20 Hz, and the same play crashes', () => {
    const at60 = play(variable(), 60, PRESS_MS);
    const at20 = play(variable(), 20, PRESS_MS);
    // Exact: v²/2g = 2.03 m. Semi-implicit Euler loses about v·Δt/2: 0.1 m at 60 Hz, 0.3 m at 20 Hz.
    expect(at60.apex).toBeCloseTo(1.9333, 4);
    expect(at20.apex).toBeCloseTo(1.74, 4);
    expect(at60.length).toBeCloseTo(6.59, 2);
    expect(at20.length).toBeCloseTo(6.08, 2);
    expect(at60.over).toBe(false);
    expect(at60.distance).toBeGreaterThan(RUNNER_TUNING.firstObstacle + 5);
    expect(crashedAtFirst(at20)).toBe(true);
  });

  it('variable Δt: a late press fails at 60 Hz and clears at 20 Hz — the frame rate decides', () => {
    const late = 3735;
    expect(crashedAtFirst(play(variable(), 60, late))).toBe(true);
    expect(play(variable(), 20, late).over).toBe(false);
  });

  it('fixed step: the same outcome and the same hash every tick at 20, 60 and 144 Hz', () => {
    for (const pressMs of [PRESS_MS, 3735]) {
      const runs = [
        play(fixed(), 60, pressMs),
        play(fixed(), 20, pressMs),
        play(fixed(), 144, pressMs),
        play(fixed(), 144, pressMs, 0.3),
      ];
      const reference = runs[0]!;
      expect(reference.over).toBe(pressMs !== PRESS_MS);
      for (const run of runs) {
        expect(run.over).toBe(reference.over);
        expect(run.apex).toBe(reference.apex);
        expect(run.length).toBe(reference.length);
        // The displays end on different ticks (a 20 Hz frame runs 3); every shared tick is equal.
        const ticks = Math.min(run.hashes.length, reference.hashes.length);
        expect(ticks).toBeGreaterThanOrEqual(268);
        expect(run.hashes.slice(0, ticks)).toEqual(reference.hashes.slice(0, ticks));
      }
      expect(reference.apex).toBeCloseTo(1.9333, 4);
    }
  });
});
