/**
 * The talk's games as chapters 5 (replays), 6 (network) and 9 (games) all see them: the registry
 * in the chapter's order, the keys, the score the server ranks, hashes as hex, names, seeds and
 * file names. No DOM here.
 */
import { hex64, type Simulation } from 'fixedstep';
import type { DisplaySpec as ClockDisplaySpec, DisplayRate } from '../shell/display-clock.js';
import { GAMES, type Game, type RegisteredGame, type GameInfo } from '@fixedstep/games';

/** The games, in the order the chapters list them. */
export const GAME_IDS = ['runner', 'ctf', 'survival'] as const;
export type GameId = (typeof GAME_IDS)[number];

/** The simulated display rates the game chapters offer. */
export { DISPLAY_RATES, type DisplayRate } from '../shell/display-clock.js';

/** A simulated display of one of those rates, with its jitter (see DisplayClock). */
export interface DisplaySpec extends ClockDisplaySpec {
  hz: DisplayRate;
}

/** The registry entry of a game id; a RangeError naming the id for an unknown one. */
export function gameDef(id: string): RegisteredGame {
  const def = GAMES.find((g) => g.info.id === id);
  if (!def) throw new RangeError(`no game "${id}"`);
  return def;
}

/** The `KeyboardEvent.code` → button map of a game, from its `info.buttons`. */
export function keyMap(info: GameInfo): Record<string, number> {
  const out: Record<string, number> = {};
  for (const b of info.buttons) for (const k of b.keys) out[k] = b.button;
  return out;
}

const KEY_NAMES: Readonly<Record<string, string>> = {
  Space: 'Space',
  ArrowUp: '↑',
  ArrowDown: '↓',
  ArrowLeft: '←',
  ArrowRight: '→',
  ShiftLeft: 'Shift',
  ShiftRight: 'Shift',
  Enter: 'Enter',
};

/** A key code as printed on the key: `KeyW` → `W`, `ArrowUp` → `↑`. */
export function keyLabel(code: string): string {
  if (KEY_NAMES[code]) return KEY_NAMES[code];
  const m = /^(?:Key|Digit)(.)$/.exec(code);
  return m ? m[1]! : code;
}

/** The game's own name for its score (`info.scoreKey`, default `score`). */
export function scoreKeyOf(def: RegisteredGame): string {
  return def.info.scoreKey ?? 'score';
}

/** The game's score as the server will rank it, or undefined if its HUD has none. */
export function scoreOf(def: RegisteredGame, game: Game): number | undefined {
  return game.hud()[scoreKeyOf(def)];
}

/** Whether the server can rank this game (its HUD has the score key). */
export function isRanked(def: RegisteredGame): boolean {
  return scoreOf(def, def.create({ seed: 1, players: 1 })) !== undefined;
}

/** A simulation's hash as 16 hex digits. */
export function hashHex(sim: Pick<Simulation, 'hash'>): string {
  const h = sim.hash();
  return hex64(BigInt.asUintN(64, typeof h === 'bigint' ? h : BigInt(h)));
}

/** A name as the replay header stores it: printable, trimmed, at most 32 characters. */
export function cleanName(name: string): string {
  const printable = Array.from(name)
    .filter((ch) => ch >= ' ' && ch !== '\u007f')
    .join('')
    .trim();
  return Array.from(printable).slice(0, 32).join('') || 'player';
}

/** A place where something went through a wall, and when (session ms). */
export interface Breach {
  x: number;
  y: number;
  atMs: number;
  /** What went through. */
  what: 'bullet' | 'player' | 'enemy';
}

/** A fresh random seed (u32). Seeds only pick the course: the game stays deterministic. */
export function randomSeed(): number {
  const a = new Uint32Array(1);
  crypto.getRandomValues(a);
  return a[0]!;
}

/** Bytes per minute of play of a replay of `bytes` bytes and `ticks` ticks at `tickRate` Hz. */
export function bytesPerMinute(bytes: number, ticks: number, tickRate: number): number {
  const minutes = ticks / tickRate / 60;
  return minutes > 0 ? bytes / minutes : NaN;
}

/** A file name for a replay: `runner-seed-123-2024-05-01T10-20-30.fsr`. */
export function replayFileName(gameId: string, seed: number, when: Date): string {
  const stamp = when.toISOString().slice(0, 19).replace(/:/g, '-');
  return `${gameId}-seed-${seed}-${stamp}.fsr`;
}

const HUD_LABELS: Readonly<Record<string, string>> = {
  score: 'Score',
  highscore: 'Highscore',
  kills: 'Kills',
  flags: 'Flags captured',
  deaths: 'Deaths',
  red: 'Red captures',
  blue: 'Blue captures',
  timeLeft: 'Time left (s)',
  throughWalls: 'Through walls',
  lives: 'Lives',
  wave: 'Wave',
  cleared: 'Waves cleared',
  enemies: 'Enemies',
};

/** The label of a HUD entry (`kills` → `Kills`). */
export function hudLabel(key: string): string {
  return HUD_LABELS[key] ?? key;
}

/** The runner's HUD line as on the slide: `SCORE 0 / HIGHSCORE 35730` (no zero padding). */
export function runnerHud(score: number, highscore: number): string {
  return `SCORE ${score} / HIGHSCORE ${highscore}`;
}
