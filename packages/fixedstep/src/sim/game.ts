/**
 * Game definitions: the one place a game declares who it is, how fast it ticks, what its input
 * is and how it is built. The loop, the replay recorder and verifier, the network sessions, the
 * relay, the highscore server and the CLI all take a definition — so the tick rate, the input
 * schema and the version are written once, and a user's game plugs into every one of them the way
 * the built-in games do.
 * @module
 */
import type { ButtonInput } from './buttons.js';
import type { InputSchema } from './input-schema.js';
import type { Simulation } from './simulation.js';
import { StateSchema } from './state-schema.js';

/** How one run of a game starts: everything a replay header or a match needs to rebuild tick 0. */
export interface GameSetup {
  /** The seed of every random number the game draws (u32). */
  readonly seed: number;
  /** Players: inputs per tick. */
  readonly players: number;
  /** The game's own options as canonical bytes (what {@link GameDefinition.options} made). */
  readonly options: Uint8Array;
}

/**
 * A deterministic game, as the library's tools need to know it.
 *
 * @typeParam I — one player's input for one tick (the {@link InputSchema}'s type).
 * @typeParam S — the simulation `create` returns.
 */
export interface GameDefinition<I = ButtonInput, S extends Simulation<I> = Simulation<I>> {
  /** Stable id: 1–32 of `A–Z a–z 0–9 _ - .`. Stored in replays, sent in the protocol. */
  readonly id: string;
  /**
   * An integer from 0 to 2^32 − 1, bumped whenever a change alters the simulation: old replays
   * then fail to verify with a clear "version" message instead of diverging, and clients of two
   * versions cannot share a room.
   */
  readonly version: number;
  /** A human title (for lists and help screens). Default: the id. */
  readonly title?: string;
  /**
   * Ticks per second: an integer from 1 to 100 000. The one place the tick rate is written:
   * `new FixedLoop({ step: game })`, the recorder, sessions and the relay all read it here.
   */
  readonly tickRate: number;
  /** What a player's input is: buttons and quantised axes. */
  readonly input: InputSchema<I>;
  /** Fewest players a run may have (≥ 1). */
  readonly minPlayers: number;
  /** Most players a run may have (≤ 64). */
  readonly maxPlayers: number;
  /** The simulation at tick 0 for `setup`. Throws a RangeError for a setup it cannot play. */
  create(setup: GameSetup): S;
  /**
   * The canonical option bytes of a new run of `players` players with `seed` (stored in replay
   * headers and sent to every client of a room). Default: no options (empty bytes).
   */
  options?(players: number, seed: number): Uint8Array;
  /** The run's score, for highscore tables (higher is better). Default: no highscores. */
  score?(sim: S): number;
  /** Whether the run has ended (a highscore may only be submitted for an ended run). */
  isOver?(sim: S): boolean;
  /** A deterministic bot: `player`'s input for the next tick, reading (never stepping) `sim`. */
  bot?(sim: S, player: number): I;
  /**
   * What the game's `save()` bytes are, column by column, with the precision each number needs
   * on a client ({@link fixedstep!defineStateSchema}; the module named, so that the link also
   * resolves where another package's reference inherits this comment). Optional: with one,
   * state-sync rooms send each entity's changed fields as small integers — and snap their own
   * world to what they sent, so the game's floats move in steps of the declared precision on the
   * server. Does not change replays, lockstep or rollback.
   */
  readonly stateSchema?: StateSchema;
}

/** A game definition whose input type and simulation do not matter (registries, servers). */
// eslint-disable-next-line @typescript-eslint/no-explicit-any -- any: a registry holds games of every input type
export type AnyGameDefinition = GameDefinition<any, Simulation<any>>;

const ID = /^[A-Za-z0-9_.-]{1,32}$/;

/**
 * Checks a game definition and returns it frozen. Throws a RangeError naming the first field that
 * is wrong (id, version, tick rate, player counts, input schema, missing `create`).
 */
export function defineGame<I, S extends Simulation<I>>(
  definition: GameDefinition<I, S>,
): Readonly<GameDefinition<I, S>> {
  const d = definition;
  const bad = (why: string): never => {
    throw new RangeError(`defineGame${typeof d.id === 'string' ? ` "${d.id}"` : ''}: ${why}`);
  };
  if (typeof d.id !== 'string' || !ID.test(d.id)) bad('id must be 1-32 of A-Z a-z 0-9 _ - .');
  if (!Number.isInteger(d.version) || d.version < 0 || d.version > 0xffffffff) {
    bad(`version must be an integer from 0 to 2^32 - 1, got ${String(d.version)}`);
  }
  if (!Number.isInteger(d.tickRate) || d.tickRate < 1 || d.tickRate > 100_000) {
    bad(`tickRate must be an integer from 1 to 100000 Hz, got ${String(d.tickRate)}`);
  }
  if (
    !Number.isInteger(d.minPlayers) ||
    !Number.isInteger(d.maxPlayers) ||
    d.minPlayers < 1 ||
    d.maxPlayers < d.minPlayers ||
    d.maxPlayers > 64
  ) {
    bad(
      `players must satisfy 1 ≤ minPlayers ≤ maxPlayers ≤ 64, got ${d.minPlayers}…${d.maxPlayers}`,
    );
  }
  if (typeof d.input !== 'object' || !(d.input.descriptor instanceof Uint8Array)) {
    bad('input must be an input schema (defineInput, or BUTTON_WORD)');
  }
  if (typeof d.create !== 'function') bad('create(setup) is missing');
  if (d.stateSchema !== undefined && !(d.stateSchema instanceof StateSchema)) {
    bad('stateSchema must be made by defineStateSchema');
  }
  return Object.freeze({ ...d });
}

/** The option bytes a new run of `game` gets (empty when the game has no options). */
export function gameOptions(game: AnyGameDefinition, players: number, seed: number): Uint8Array {
  return game.options ? game.options(players, seed) : new Uint8Array(0);
}

/**
 * A checked {@link GameSetup} for `game`: players within its range, a u32 seed, options from the
 * game (unless given). Throws a RangeError naming the value that is wrong.
 */
export function gameSetup(
  game: AnyGameDefinition,
  players: number,
  seed: number,
  options?: Uint8Array,
): GameSetup {
  if (!Number.isInteger(players) || players < game.minPlayers || players > game.maxPlayers) {
    throw new RangeError(
      `${game.id}: players must be from ${game.minPlayers} to ${game.maxPlayers}, got ${String(players)}`,
    );
  }
  if (!Number.isInteger(seed) || seed < 0 || seed > 0xffffffff) {
    throw new RangeError(`${game.id}: seed must be a u32, got ${String(seed)}`);
  }
  return Object.freeze({ seed, players, options: options ?? gameOptions(game, players, seed) });
}

/** Finds a game by id in a list (a server's or CLI's registry). */
export function findGameById<G extends AnyGameDefinition>(
  games: readonly G[],
  id: string,
): G | undefined {
  return games.find((g) => g.id === id);
}
