import {
  FixedLoop,
  SimulatedDisplay,
  VariableLoop,
  type ButtonInput,
  type Loop,
  type SimulatedDisplayOptions,
} from 'fixedstep';
import type { Game } from '../game.js';

/** Options of {@link playOnDisplay}. */
export interface PlayOnDisplayOptions {
  /**
   * `'fixed'`: the production {@link FixedLoop} at the game's tick rate, each update a
   * `game.step` (continuous detection). `'variable'`: the talk's naive {@link VariableLoop}, one
   * `game.update(dt)` per display frame with that frame's Δt (discrete detection).
   */
  loop: 'fixed' | 'variable';
  /** The simulated display: rate, jitter, hitches (repeatable: seeded). */
  display: SimulatedDisplayOptions;
  /** Seconds of display time to play. */
  seconds: number;
  /** Fills `out[p]` with player p's input for the next update (a bot, a script …). */
  inputs: (game: Game, out: ButtonInput[]) => void;
  /** Called after every update (for measurements). */
  afterUpdate?: (game: Game) => void;
}

/** What {@link playOnDisplay} did. */
export interface PlayOnDisplayResult {
  /** Display frames. */
  frames: number;
  /** Updates (steps or `update` calls). */
  updates: number;
  /** The longest Δt one update was given, seconds. */
  maxDt: number;
}

/**
 * Plays a game headless on a simulated display, the way the lab plays it on a real one: the
 * display's frames drive a loop, the loop says how many updates to run and with what Δt. The
 * same game and inputs under `'fixed'` and `'variable'` show the talk's point side by side.
 * Stops early when the game is over.
 */
export function playOnDisplay(game: Game, options: PlayOnDisplayOptions): PlayOnDisplayResult {
  const display = new SimulatedDisplay(options.display);
  const loop: Loop =
    options.loop === 'fixed' ? new FixedLoop({ step: game.info.tickRate }) : new VariableLoop();
  const inputs: ButtonInput[] = new Array<ButtonInput>(game.info.maxPlayers).fill(0);
  const start = display.next().time;
  loop.frame(start);
  const end = start + options.seconds * 1000;
  let frames = 0;
  let updates = 0;
  let maxDt = 0;
  while (!game.over) {
    const t = display.next().time;
    if (t > end) break;
    frames++;
    const n = loop.frame(t);
    for (let j = 0; j < n; j++) {
      options.inputs(game, inputs);
      if (options.loop === 'fixed') game.step(inputs);
      else game.update(loop.dt, inputs);
      if (loop.dt > maxDt) maxDt = loop.dt;
      updates++;
      options.afterUpdate?.(game);
    }
  }
  return { frames, updates, maxDt };
}
