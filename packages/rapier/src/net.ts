/**
 * A Rapier scene as a networked game: what `SimulatedMatch`, the relay's catalogue and the replay
 * verifier need (identity, a factory from a config, the config's bytes, a bot).
 */
import { ByteReader, ByteWriter, type MatchGame, type MatchGameConfig } from 'fixedstep';
import { RapierSimulation, type RapierSceneDef } from './simulation.js';

/** Options of {@link rapierMatchGame}. */
export interface RapierMatchGameOptions<S> {
  /** The game's id in rooms and replays. */
  readonly id: string;
  /** Its version (a replay or room of another version is refused). Default 1. */
  readonly version?: number;
  /** Ticks per second; must be the scene's. Default 60. */
  readonly tickRate?: number;
  readonly minPlayers?: number;
  readonly maxPlayers?: number;
  /** The scene for a config (its `players` is set from the config). */
  scene(config: MatchGameConfig): RapierSceneDef<number, S>;
  /** A deterministic bot: the input of `player` for the next tick, reading the simulation. */
  readonly bot?: (sim: RapierSimulation<number, S>, player: number) => number;
}

/**
 * A Rapier scene as a `MatchGame` of fixedstep's networking: `SimulatedMatch`, `relayGameOf` and
 * `RollbackSession`/`LockstepSession` (`createSimulation: (w) => game.create(game.decodeConfig(w.config))`).
 * The config is 5 bytes: the seed (u32) and the players (u8). Needs `await loadRapier()` before
 * `create`.
 */
export function rapierMatchGame<S>(
  options: RapierMatchGameOptions<S>,
): Omit<MatchGame, 'create'> & { create(config: MatchGameConfig): RapierSimulation<number, S> } {
  const tickRate = options.tickRate ?? 60;
  const minPlayers = options.minPlayers ?? 1;
  const maxPlayers = options.maxPlayers ?? 8;
  const checkPlayers = (players: number): number => {
    if (!(Number.isInteger(players) && players >= minPlayers && players <= maxPlayers)) {
      throw new RangeError(
        `${options.id}: players must be from ${minPlayers} to ${maxPlayers}, got ${String(players)}`,
      );
    }
    return players;
  };
  const bot = options.bot;
  return {
    info: {
      id: options.id,
      version: options.version ?? 1,
      tickRate,
      minPlayers,
      maxPlayers,
    },
    create(config) {
      const players = checkPlayers(config.players);
      const scene = options.scene(config);
      const tr = scene.tickRate ?? 60;
      if (tr !== tickRate) {
        throw new RangeError(`${options.id}: the scene ticks at ${tr} Hz, the game at ${tickRate}`);
      }
      return new RapierSimulation({ ...scene, players });
    },
    encodeConfig: (config) =>
      new ByteWriter(8).u32(config.seed).u8(checkPlayers(config.players)).finish(),
    decodeConfig(bytes) {
      const r = new ByteReader(bytes);
      const seed = r.u32();
      const players = checkPlayers(r.u8());
      r.end();
      return { seed, players };
    },
    ...(bot
      ? {
          bot: (sim: RapierSimulation<number, S>, player: number) => bot(sim, player),
        }
      : {}),
  };
}
