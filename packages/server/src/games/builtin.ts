/**
 * The built-in games (Runner, Capture the flag, Survival) as a games module: what `fixedstep
 * serve` and `fixedstep replay verify` load when no `--games` is given, and what the verification
 * workers import by this module's URL.
 * @module
 */
import type { AnyGameDefinition } from 'fixedstep';
import { GAMES } from '@fixedstep/games';

const games: readonly AnyGameDefinition[] = GAMES;
export default games;
