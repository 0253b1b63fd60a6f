/**
 * A Rapier scene as a game definition: what `SimulatedMatch`, the relay, network sessions, the
 * replay recorder and verifier, and the highscore server take.
 */
import {
  BUTTON_WORD,
  defineGame,
  type ButtonInput,
  type GameDefinition,
  type GameSetup,
  type InputSchema,
} from 'fixedstep';
import { RapierSimulation, type RapierSceneDef } from './simulation.js';

/** Options of {@link rapierGame}. */
export interface RapierGameOptions<S> {
  /** The game's id in rooms and replays. */
  readonly id: string;
  /** Its version (a replay or room of another version is refused). Default 1. */
  readonly version?: number;
  /** Ticks per second; must be the scene's. Default 60. */
  readonly tickRate?: number;
  readonly minPlayers?: number;
  readonly maxPlayers?: number;
  /** The input schema. Default `BUTTON_WORD`. */
  readonly input?: InputSchema;
  /** The scene for a setup (its `players` is set from the setup). */
  scene(setup: GameSetup): RapierSceneDef<number, S>;
  /** A deterministic bot: the input of `player` for the next tick, reading the simulation. */
  readonly bot?: (sim: RapierSimulation<number, S>, player: number) => ButtonInput;
}

/**
 * A Rapier scene as a fixedstep game definition. Needs `await loadRapier()` before `create`
 * (which stays synchronous, as replay factories and network sessions need).
 */
export function rapierGame<S>(
  options: RapierGameOptions<S>,
): Readonly<GameDefinition<ButtonInput, RapierSimulation<number, S>>> {
  const tickRate = options.tickRate ?? 60;
  const bot = options.bot;
  return defineGame<ButtonInput, RapierSimulation<number, S>>({
    id: options.id,
    version: options.version ?? 1,
    tickRate,
    input: options.input ?? BUTTON_WORD,
    minPlayers: options.minPlayers ?? 1,
    maxPlayers: options.maxPlayers ?? 8,
    create(setup) {
      const scene = options.scene(setup);
      const tr = scene.tickRate ?? 60;
      if (tr !== tickRate) {
        throw new RangeError(`${options.id}: the scene ticks at ${tr} Hz, the game at ${tickRate}`);
      }
      return new RapierSimulation({ ...scene, players: setup.players });
    },
    ...(bot ? { bot: (sim: RapierSimulation<number, S>, player: number) => bot(sim, player) } : {}),
  });
}
