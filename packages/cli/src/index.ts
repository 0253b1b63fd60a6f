/**
 * @fixedstep/cli — the `fixedstep` command: `serve` (the lab and the whole server of
 * `@fixedstep/server` on one port), the talk's experiments, and replay tools. `run(argv)` runs it
 * from code and resolves with the exit code.
 * @packageDocumentation
 * @module @fixedstep/cli
 */
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
