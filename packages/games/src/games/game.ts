import {
  defineGame,
  defineInput,
  type ButtonInput,
  type GameDefinition as LibraryGameDefinition,
  type GameSetup,
  type InputSchema,
  type Simulation,
  type StateSchema,
} from 'fixedstep';
import { decodeGameConfig, encodeGameConfig } from './config.js';

/**
 * What every game of the talk is: a deterministic {@link Simulation} over per-player
 * {@link ButtonInput}s, plus what the lab, the replays, the server and the bots need to know.
 *
 * `step(inputs)` advances one fixed step of {@link GameInfo.stepSeconds}. `update(dt, inputs)`
 * advances by any `dt`: the lab uses it with a variable-Δt loop to show what breaks. Only `step`
 * is deterministic across frame rates; replays, networking and highscores use only `step`.
 */
export interface Game extends Simulation {
  readonly info: GameInfo;
  /** Advance by `dt` seconds (the variable-Δt demo). Not for replays or networking. */
  update(dt: number, inputs: readonly ButtonInput[]): void;
  /** The HUD numbers, as on the slides (e.g. { score, highscore } or { kills, lives }). */
  hud(): Readonly<Record<string, number>>;
  /** Whether the game has ended (all players out, time up …). */
  readonly over: boolean;
}

export interface GameInfo {
  /** Stable id, used in replay files and by the server: `runner`, `ctf`, `survival`. */
  readonly id: string;
  /** Bumped whenever a change alters the simulation (old replays then fail clearly). */
  readonly version: number;
  readonly title: string;
  /** Seconds per fixed step. */
  readonly stepSeconds: number;
  /** Ticks per second (= 1 / stepSeconds when that is an integer). */
  readonly tickRate: number;
  /** Players the game supports. */
  readonly minPlayers: number;
  readonly maxPlayers: number;
  /** The `hud()` entry that is the game's score for highscore tables. Default `'score'`. */
  readonly scoreKey?: string;
  /** Buttons (0–15) and the keys the lab maps to them, for help screens and input wiring. */
  readonly buttons: readonly { button: number; name: string; keys: readonly string[] }[];
}

/** How a game is started: everything a replay header needs to build it again. */
export interface GameConfig {
  /** Seed of every random number the game draws. */
  seed: number;
  /** Number of (human or bot) players. */
  players: number;
}

/** A bot: given the game (read-only use) and its player index, the input for the next tick. */
export type Bot = (game: Game, player: number) => ButtonInput;

/**
 * One entry of the game registry: a library {@link LibraryGameDefinition} (what replays, the
 * relay, the server and the CLI take) plus the lab's {@link GameInfo}, a bot, and the config
 * codec. Its option bytes are the canonical config (seed, players), as replay headers have
 * always stored them.
 */
export interface RegisteredGame extends LibraryGameDefinition<ButtonInput, Game> {
  readonly info: GameInfo;
  readonly input: InputSchema;
  create(config: GameConfig | GameSetup): Game;
  /** A bot that plays reasonably (deterministic: no clocks, no Math.random). */
  readonly bot: Bot;
  /** Canonical bytes of a config, for replay headers; and back. */
  encodeConfig(config: GameConfig): Uint8Array;
  decodeConfig(bytes: Uint8Array): GameConfig;
}

/**
 * A talk game's registry entry: the library definition from `info` (id, version, tick rate,
 * players), an input schema of the named buttons (`{ jump: 0, duck: 1 }`), the score rule (the
 * HUD's `info.scoreKey`), and the config codec.
 */
export function talkGame(
  info: GameInfo,
  buttons: Readonly<Record<string, number>>,
  create: (config: GameConfig) => Game,
  bot: Bot,
  stateSchema?: StateSchema,
): RegisteredGame {
  const names = Object.entries(buttons)
    .sort((a, b) => a[1] - b[1])
    .map(([name, i], k) => {
      if (i !== k) throw new RangeError(`${info.id}: buttons must be numbered 0, 1, 2 … in order`);
      return name;
    });
  const scoreKey = info.scoreKey ?? 'score';
  const decodeConfig = (bytes: Uint8Array) =>
    decodeGameConfig(bytes, info.minPlayers, info.maxPlayers);
  const definition: RegisteredGame = {
    id: info.id,
    version: info.version,
    title: info.title,
    tickRate: info.tickRate,
    minPlayers: info.minPlayers,
    maxPlayers: info.maxPlayers,
    input: defineInput({ buttons: names }),
    info,
    create: (setup) => {
      // A setup from a replay or a room carries the config bytes: they must agree with it.
      if ('options' in setup && setup.options.length > 0) {
        const c = decodeConfig(setup.options);
        if (c.seed !== setup.seed || c.players !== setup.players) {
          throw new RangeError(
            `${info.id}: config bytes say seed ${c.seed} and ${c.players} players`,
          );
        }
      }
      return create({ seed: setup.seed, players: setup.players });
    },
    options: (players, seed) => encodeGameConfig({ seed, players }),
    score: (game) => game.hud()[scoreKey] ?? 0,
    isOver: (game) => game.over,
    bot,
    encodeConfig: encodeGameConfig,
    decodeConfig,
    ...(stateSchema ? { stateSchema } : {}),
  };
  return defineGame(definition) as RegisteredGame;
}
