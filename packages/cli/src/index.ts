/**
 * @fixedstep/cli — the `fixedstep` command and its server.
 * @packageDocumentation
 */
export { startServer, mimeType, resolveRequestPath, displayHost, DOCS_NOT_BUILT } from './serve.js';
export type { ServeOptions, RunningServer } from './serve.js';
export {
  run,
  parseArgs,
  parsePort,
  defaultLabRoot,
  MAIN_HELP,
  SERVE_HELP,
  DEFAULT_PORT,
  DEFAULT_HOST,
  EXIT_OK,
  EXIT_FAILURE,
  EXIT_USAGE,
} from './cli.js';
export type { Command, CliIo } from './cli.js';
export {
  HighscoreStore,
  highscoreApi,
  checkSubmission,
  SubmissionError,
  TABLE_SIZE,
} from './highscores.js';
export type { HighscoreEntry, HighscoreApiOptions, ApiHandler } from './highscores.js';
