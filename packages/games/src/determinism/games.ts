/**
 * Every game of the registry, traced four ways: a bot match; its replay file played back; the match
 * moved into a fresh game by `save()` → `load()` every 500 ticks; and the match's inputs as
 * timestamped button events fed through the fixed loop on every simulated display. A game added to
 * `GAMES` is picked up with no change here.
 */
import { ReplayRecorder, fnv1a64Hex, hex64, readReplay, type ButtonInput } from 'fixedstep';
import type { Game, GameConfig, RegisteredGame } from '../games/game.js';
import { replayOptionsFor } from '../games/replay.js';
import {
  displayRun,
  inputsToScript,
  rateLabel,
  sampledInputs,
  timestepOf,
  traceDisplay,
  type TraceButtonEvent,
} from './display.js';
import { gameFields } from './layouts.js';
import type { TraceRun, TraceScene } from './trace.js';

/** The seed of every traced game. */
export const TRACE_GAME_SEED = 20261122;

/** Players of a traced game: two where the game allows it (so multi-player paths run), else its minimum. */
export function tracePlayers(def: RegisteredGame): number {
  return Math.min(def.info.maxPlayers, Math.max(def.info.minPlayers, 2));
}

/** The config of a traced game. */
function traceConfig(def: RegisteredGame): GameConfig {
  return { seed: TRACE_GAME_SEED, players: tracePlayers(def) };
}

/** What a bot match leaves behind: per-player inputs per tick, and the replay file. */
export interface BotRecording {
  readonly config: GameConfig;
  /** `inputs[p][t]`: player p's input at tick t. */
  readonly inputs: readonly Uint32Array[];
  /** The replay file of the match (recorded with `ReplayRecorder`). */
  readonly replay: Uint8Array;
  /** Per player, the inputs as timestamped button events. */
  readonly scripts: readonly (readonly TraceButtonEvent[])[];
  /**
   * Per player, what a `ButtonSampler` makes of the scripts: the bot's inputs, plus a "pressed"
   * bit wherever a bot holds a button from a tick it was up without saying it pressed it.
   */
  readonly sampled: readonly Uint32Array[];
  /** Ticks whose sampled inputs differ from the bot's (see {@link BotRecording.sampled}). */
  readonly resampledTicks: number;
}

function stepMsOf(def: RegisteredGame): number {
  return def.info.stepSeconds * 1000;
}

function createGame(def: RegisteredGame, config: GameConfig): Game {
  return def.create(config);
}

/**
 * The bot plays every seat for `ticks` ticks, recorded as it goes.
 */
function botMatch(def: RegisteredGame, ticks: number): BotRecording {
  const config = traceConfig(def);
  const game = createGame(def, config);
  const names = Array.from({ length: config.players }, (_, p) => `bot${String(p)}`);
  const recorder = new ReplayRecorder(
    replayOptionsFor(def, config, names, { checkpointEvery: 60, keyframeEvery: 600 }),
  );
  recorder.start(game);
  const inputs = names.map(() => new Uint32Array(ticks));
  const frame: ButtonInput[] = names.map(() => 0);
  for (let t = 0; t < ticks; t++) {
    for (let p = 0; p < config.players; p++) frame[p] = inputs[p]![t] = def.bot(game, p) >>> 0;
    game.step(frame);
    recorder.record(frame, game);
  }
  const stepMs = stepMsOf(def);
  const scripts = inputs.map((seat) => inputsToScript(seat, stepMs));
  const sampled = scripts.map((script) => sampledInputs(script, ticks, stepMs));
  let resampled = 0;
  for (let t = 0; t < ticks; t++) {
    for (let p = 0; p < config.players; p++) {
      if (sampled[p]![t] !== inputs[p]![t]) {
        resampled++;
        break;
      }
    }
  }
  return {
    config,
    inputs,
    replay: recorder.finish(),
    scripts,
    sampled,
    resampledTicks: resampled,
  };
}

/** How often the `reloaded` scenes move the state into a fresh instance (snapshot round trip). */
const RELOAD_EVERY = 500;

/** How often a run checks `hash()` against the FNV-1a 64 of `save()` (the Simulation contract). */
const CONTRACT_EVERY = 600;

/** Throws unless `game.hash()` is the FNV-1a 64 of `state` (its `save()` bytes). */
function checkHashContract(game: Game, state: Uint8Array, tick: number): void {
  const want = fnv1a64Hex(state);
  const got = hex64(game.hash());
  if (got !== want) {
    throw new Error(
      `${game.info.id}: hash() is ${got} but the FNV-1a 64 of save() is ${want} after tick ${String(tick)}`,
    );
  }
}

/** A run that steps `game` with `inputsAt(t)` and returns its state after each tick. */
function steppedRun(game: Game, inputsAt: (tick: number, out: number[]) => void): TraceRun {
  const frame: number[] = [];
  let tick = 0;
  return {
    next(): Uint8Array {
      inputsAt(tick++, frame);
      game.step(frame);
      const state = game.save();
      if (tick % CONTRACT_EVERY === 1) checkHashContract(game, state, tick);
      return state;
    },
  };
}

/**
 * A run in which the bot plays every seat of a new traced game. After each tick `afterTick` is
 * given the game, its state and the ticks so far, and returns the game to go on with.
 */
function botRun(
  def: RegisteredGame,
  afterTick: (game: Game, state: Uint8Array, tick: number) => Game,
): TraceRun {
  const config = traceConfig(def);
  let game = createGame(def, config);
  const frame: ButtonInput[] = Array.from({ length: config.players }, () => 0);
  let tick = 0;
  return {
    next(): Uint8Array {
      for (let p = 0; p < config.players; p++) frame[p] = def.bot(game, p) >>> 0;
      game.step(frame);
      const state = game.save();
      game = afterTick(game, state, ++tick);
      return state;
    },
  };
}

/** The trace scenes of one game; see the module comment. */
export function gameScenes(
  def: RegisteredGame,
  ticks: number,
  rates: readonly number[],
): TraceScene[] {
  const id = def.info.id;
  let recording: BotRecording | undefined;
  const record = (): BotRecording => {
    recording ??= botMatch(def, ticks);
    return recording;
  };
  let fieldsGame: Game | undefined;
  const fields = (state: Uint8Array) => {
    fieldsGame ??= createGame(def, traceConfig(def));
    return gameFields(fieldsGame, state);
  };

  const bot: TraceScene = {
    id: `game/${id}/bot`,
    title: `${def.info.title}: a ${String(ticks)}-tick bot match, ${String(tracePlayers(def))} seat(s), step() per tick`,
    ticks,
    start: () =>
      botRun(def, (game, state, tick) => {
        if (tick % CONTRACT_EVERY === 1) checkHashContract(game, state, tick);
        return game;
      }),
    fields,
  };

  const replay: TraceScene = {
    id: `game/${id}/replay`,
    title: `${def.info.title}: the bot match’s replay file, read and re-simulated`,
    ticks,
    sameAs: bot.id,
    start(): TraceRun {
      const file = readReplay(record().replay);
      if (file.header.gameId !== id) {
        throw new Error(`replay of ${file.header.gameId}, expected ${id}`);
      }
      const game = createGame(def, def.decodeConfig(file.header.config));
      const cursor = file.inputCursor();
      return steppedRun(game, (_, out) => {
        cursor.next(out);
      });
    },
    fields,
  };

  const reloaded: TraceScene = {
    id: `game/${id}/reloaded`,
    title: `${def.info.title}: the bot match, moved every ${String(RELOAD_EVERY)} ticks into a fresh game by save() → load()`,
    ticks,
    sameAs: bot.id,
    start: () =>
      botRun(def, (game, state, tick) => {
        if (tick % RELOAD_EVERY !== 0) return game;
        const fresh = createGame(def, traceConfig(def));
        fresh.load(state);
        return fresh;
      }),
    fields,
  };

  const sampled: TraceScene = {
    id: `game/${id}/sampled`,
    title: `${def.info.title}: the match’s inputs as a ButtonSampler delivers them (timestamped presses), step() per tick`,
    ticks,
    start(): TraceRun {
      const r = record();
      const game = createGame(def, r.config);
      return steppedRun(game, (t, out) => {
        out.length = r.sampled.length;
        for (let p = 0; p < r.sampled.length; p++) out[p] = r.sampled[p]![t]!;
      });
    },
    fields,
  };

  const displays = rates.map((hz): TraceScene => ({
    id: `game/${id}@${rateLabel(hz)}`,
    title: `${def.info.title}: the match as timestamped presses, FixedLoop on a ${String(hz)} Hz display, jitter, hitches`,
    ticks,
    sameAs: sampled.id,
    start(): TraceRun {
      const r = record();
      const game = createGame(def, r.config);
      return displayRun({
        step: timestepOf(def.info.stepSeconds, def.info.tickRate),
        display: traceDisplay(hz),
        scripts: r.scripts,
        advance: (inputs) => {
          game.step(inputs);
          return game.save();
        },
      });
    },
    fields,
  }));

  return [bot, replay, reloaded, sampled, ...displays];
}

/** The bot match of a game, recorded (for reports: how many ticks a sampler cannot reproduce). */
export function recordBotMatch(def: RegisteredGame, ticks: number): BotRecording {
  return botMatch(def, ticks);
}
