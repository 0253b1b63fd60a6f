import { existsSync, readFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { startServer } from './serve.js';

/** Exit codes: 0 done, 1 it failed while running, 2 the command line was wrong. */
export const EXIT_OK = 0;
export const EXIT_FAILURE = 1;
export const EXIT_USAGE = 2;

export const DEFAULT_PORT = 8080;
export const DEFAULT_HOST = '127.0.0.1';

/** Where the built lab is, seen from this file (`src/` or `dist/` of packages/cli). */
export function defaultLabRoot(): string {
  return fileURLToPath(new URL('../../../apps/lab/dist', import.meta.url));
}

function version(): string {
  try {
    const pkg = JSON.parse(
      readFileSync(fileURLToPath(new URL('../package.json', import.meta.url)), 'utf8'),
    ) as { version?: string };
    return pkg.version ?? 'unknown';
  } catch {
    return 'unknown';
  }
}

export const MAIN_HELP = `fixedstep — fixed-step, deterministic simulation

Usage:
  fixedstep <command> [options]

Commands:
  serve        Serve the lab (the talk, live) on http://localhost:${DEFAULT_PORT}/

Options:
  -h, --help     Show this help (or a command's: fixedstep serve --help)
  -v, --version  Print the version

Exit codes: 0 ok, 1 runtime error, 2 usage error.
`;

export const SERVE_HELP = `fixedstep serve — serve the lab

Usage:
  fixedstep serve [--port <n>] [--host <address>] [--root <dir>]

Options:
  -p, --port <n>       Port to listen on, 0 for any free one (default: $PORT, else ${DEFAULT_PORT})
      --host <address> Interface to listen on (default: ${DEFAULT_HOST}, this machine only;
                       use 0.0.0.0 to open the lab to your network)
      --root <dir>     Directory to serve (default: the built lab, apps/lab/dist)
  -h, --help           Show this help

Build the lab first with: npm run build
`;

/** What the command line asks for. */
export type Command =
  | { kind: 'help'; text: string }
  | { kind: 'version' }
  | { kind: 'serve'; port: number; host: string; root: string | undefined }
  | { kind: 'usage-error'; message: string; help: string };

function usage(message: string, help = MAIN_HELP): Command {
  return { kind: 'usage-error', message, help };
}

/** A port from the command line or the environment: an integer from 0 to 65535, or undefined. */
export function parsePort(text: string): number | undefined {
  if (!/^\d{1,5}$/.test(text)) return undefined;
  const n = Number(text);
  return n <= 65535 ? n : undefined;
}

/**
 * Parses the arguments (without `node` and the script). Pure: the environment is passed in, only
 * `PORT` is read from it; `--port` wins over `PORT`.
 */
export function parseArgs(
  argv: readonly string[],
  env: Readonly<Record<string, string | undefined>> = {},
): Command {
  const [first, ...rest] = argv;
  if (first === undefined || first === '-h' || first === '--help' || first === 'help') {
    if (first === 'help' && rest[0] === 'serve') return { kind: 'help', text: SERVE_HELP };
    return { kind: 'help', text: MAIN_HELP };
  }
  if (first === '-v' || first === '--version') return { kind: 'version' };
  if (first.startsWith('-')) return usage(`unknown option: ${first}`);
  if (first !== 'serve') return usage(`unknown command: ${first}`);

  let port: number | undefined;
  let host = DEFAULT_HOST;
  let root: string | undefined;
  const envPort = env.PORT;
  if (envPort !== undefined && envPort !== '') {
    port = parsePort(envPort);
    if (port === undefined) {
      return usage(`PORT must be an integer from 0 to 65535, got "${envPort}"`, SERVE_HELP);
    }
  }
  for (let i = 0; i < rest.length; i++) {
    const arg = rest[i]!;
    if (arg === '-h' || arg === '--help') return { kind: 'help', text: SERVE_HELP };
    const eq = arg.indexOf('=');
    const name = arg.startsWith('--') && eq > 0 ? arg.slice(0, eq) : arg;
    const inline = arg.startsWith('--') && eq > 0 ? arg.slice(eq + 1) : undefined;
    const value = (): string | undefined => {
      if (inline !== undefined) return inline;
      const next = rest[i + 1];
      if (next === undefined || next.startsWith('-')) return undefined;
      i++;
      return next;
    };
    if (name === '-p' || name === '--port') {
      const v = value();
      if (v === undefined) return usage(`${name} needs a value`, SERVE_HELP);
      port = parsePort(v);
      if (port === undefined) {
        return usage(`${name} must be an integer from 0 to 65535, got "${v}"`, SERVE_HELP);
      }
    } else if (name === '--host') {
      const v = value();
      if (v === undefined || v === '') return usage('--host needs a value', SERVE_HELP);
      host = v;
    } else if (name === '--root') {
      const v = value();
      if (v === undefined || v === '') return usage('--root needs a value', SERVE_HELP);
      root = v;
    } else if (arg.startsWith('-')) {
      return usage(`unknown option for serve: ${arg}`, SERVE_HELP);
    } else {
      return usage(`unexpected argument for serve: ${arg}`, SERVE_HELP);
    }
  }
  return { kind: 'serve', port: port ?? DEFAULT_PORT, host, root };
}

/** Where the command writes, and what it waits on (injected so tests can run it). */
export interface CliIo {
  out(text: string): void;
  err(text: string): void;
  /** Resolves when the process is asked to stop (Ctrl-C). Default: SIGINT or SIGTERM. */
  stopSignal?: Promise<void>;
}

const processIo: CliIo = {
  out: (text) => process.stdout.write(text),
  err: (text) => process.stderr.write(text),
};

function signals(): Promise<void> {
  return new Promise((resolve) => {
    const stop = () => {
      process.off('SIGINT', stop);
      process.off('SIGTERM', stop);
      resolve();
    };
    process.on('SIGINT', stop);
    process.on('SIGTERM', stop);
  });
}

/**
 * Runs the command and resolves with the exit code. `serve` resolves only once the server has
 * stopped (on Ctrl-C), or at once with 1 if it could not start.
 */
export async function run(
  argv: readonly string[],
  env: Readonly<Record<string, string | undefined>> = process.env,
  io: CliIo = processIo,
): Promise<number> {
  const command = parseArgs(argv, env);
  switch (command.kind) {
    case 'help':
      io.out(command.text);
      return EXIT_OK;
    case 'version':
      io.out(`${version()}\n`);
      return EXIT_OK;
    case 'usage-error':
      io.err(`fixedstep: ${command.message}\n\n${command.help}`);
      return EXIT_USAGE;
    case 'serve': {
      const root = path.resolve(command.root ?? defaultLabRoot());
      if (!existsSync(path.join(root, 'index.html'))) {
        io.err(
          command.root === undefined
            ? `fixedstep: the lab is not built (no index.html in ${root}); run: npm run build\n`
            : `fixedstep: nothing to serve: no index.html in ${root}\n`,
        );
        return EXIT_FAILURE;
      }
      let server;
      try {
        server = await startServer({ port: command.port, host: command.host, root });
      } catch (error) {
        io.err(`fixedstep: ${error instanceof Error ? error.message : String(error)}\n`);
        return EXIT_FAILURE;
      }
      io.out(`fixedstep lab: ${server.url}\n`);
      if (command.host === '0.0.0.0' || command.host === '::') {
        io.out(`(listening on every interface, port ${server.port})\n`);
      }
      await (io.stopSignal ?? signals());
      await server.close();
      return EXIT_OK;
    }
  }
}

/** True when this module is the program (`node dist/cli.js`), not an import. */
function isMain(): boolean {
  const entry = process.argv[1];
  return entry !== undefined && import.meta.url === pathToFileURL(path.resolve(entry)).href;
}

if (isMain()) {
  process.exitCode = await run(process.argv.slice(2));
}
