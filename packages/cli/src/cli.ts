import { existsSync, readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { INTEGRATOR_METHODS, type IntegratorMethod } from 'fixedstep';
import { TALK_INTEGRATOR_EXPERIMENT } from '@fixedstep/games';
import {
  UsageError,
  convertValue,
  formatOptions,
  parseOptions,
  type OptionSpec,
  type OptionValue,
} from './args.js';
import {
  formatIntegratorTable,
  integratorCsv,
  runIntegratorExperiment,
  type IntegratorExperimentOptions,
} from './experiments/integrators.js';
import {
  TUNNEL_HELP,
  formatTunnelTable,
  parseTunnel,
  runTunnelExperiment,
  tunnelCsv,
  type TunnelExperimentOptions,
} from './experiments/tunnel.js';
import {
  REPLAY_INFO_HELP,
  REPLAY_VERIFY_HELP,
  parseReplayInfo,
  parseReplayVerify,
  replayInfo,
  replayVerify,
} from './replay.js';
import {
  GamesModuleError,
  createServer,
  loadGames,
  parseOriginPolicy,
  prepareStore,
  type PreparedStore,
  type OriginPolicy,
} from '@fixedstep/server';
import { lineChartSvg } from './svg.js';
import { CHECK_HELP, parseCheck, runCheckCommand, type CheckCommand } from './check/command.js';

/** Exit codes: 0 done, 1 it failed while running, 2 the command line was wrong. */
export const EXIT_OK = 0;
export const EXIT_FAILURE = 1;
export const EXIT_USAGE = 2;

export const DEFAULT_PORT = 8080;
export const DEFAULT_HOST = '127.0.0.1';

/**
 * Where the built lab is, seen from this file (`src/` or `dist/` of packages/cli): in a checkout
 * of the repository, Vite's output `apps/lab/dist` (the freshest); in the installed package, the
 * copy `npm run build` puts in `lab/` and the tarball ships.
 */
export function defaultLabRoot(): string {
  const checkout = fileURLToPath(new URL('../../../apps/lab/dist', import.meta.url));
  const packaged = fileURLToPath(new URL('../lab', import.meta.url));
  return existsSync(path.join(checkout, 'index.html')) ? checkout : packaged;
}

/** Where `npm run docs` puts the API reference, served at `/docs/` (same layout as the lab's). */
export function defaultDocsRoot(): string {
  return fileURLToPath(new URL('../../../artifacts/api', import.meta.url));
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
  serve                     Serve the lab (the talk, live) on http://localhost:${DEFAULT_PORT}/
  experiment integrators    Energy and phase error of six integrators on a spring
  experiment tunnel         How often bodies tunnel through walls, with and without CCD
  replay info <file>        What a replay file holds
  replay verify <file>      Re-simulate a replay and check every stored hash
  check <module>            Is your game deterministic? Sync test, guard, save/load round
                            trip, and the same inputs in Node and every installed browser

Options:
  -h, --help     Show this help (or a command's: fixedstep serve --help)
  -v, --version  Print the version

Exit codes: 0 ok, 1 runtime error, 2 usage error (replay: 3 invalid file, 4 does not reproduce;
check: 3 unusable module, 4 not deterministic, 5 the game threw).
`;

const SERVE_OPTIONS: OptionSpec[] = [
  {
    name: 'port',
    short: 'p',
    kind: 'integer',
    min: 0,
    max: 65535,
    valueName: 'n',
    help: `Port to listen on, 0 for any free one (default: $PORT, else ${DEFAULT_PORT})`,
  },
  {
    name: 'host',
    kind: 'string',
    valueName: 'address',
    help: `Interface to listen on (default: ${DEFAULT_HOST}, this machine only;\nuse 0.0.0.0 to open the lab to your network)`,
  },
  {
    name: 'data',
    kind: 'string',
    valueName: 'dir',
    help: 'Where the highscore table is kept (default: ./fixedstep-data)',
  },
  {
    name: 'root',
    kind: 'string',
    valueName: 'dir',
    help: 'Directory to serve (default: the built lab, apps/lab/dist)',
  },
  {
    name: 'games',
    kind: 'string',
    valueName: 'module',
    help: 'Your games: an ES module whose default (or "games") export is a game\ndefinition or an array of them (default: the built-in games)',
  },
  {
    name: 'trust-proxy',
    kind: 'string',
    valueName: 'header',
    help: 'Behind a reverse proxy on this machine: the header it puts the client\naddress in (x-forwarded-for, x-real-ip), for every per-address cap and\nrate limit. A proxy elsewhere: FIXEDSTEP_PROXY_HEADER and\nFIXEDSTEP_TRUSTED_PROXIES instead (docs/deploy.md)',
  },
  {
    name: 'allowed-origins',
    kind: 'string',
    valueName: 'list',
    help: 'Which pages may open the WebSockets (relay, state sync, signalling,\nquick match): same-origin (the default: pages of this server only), a\ncomma-separated list like https://game.example, or any\n(default: $FIXEDSTEP_ALLOWED_ORIGINS, else same-origin)',
  },
  {
    name: 'workers',
    kind: 'integer',
    min: 0,
    max: 64,
    valueName: 'n',
    help: 'Verification worker threads (default: cores - 1, at least 1)',
  },
  {
    name: 'max-connections',
    kind: 'integer',
    min: 1,
    max: 1_000_000,
    valueName: 'n',
    help: 'Most open connections (default: the open-file limit - 256, ≤ 10000)',
  },
  { name: 'help', short: 'h', kind: 'flag', help: 'Show this help' },
];

export const SERVE_HELP = `fixedstep serve — serve the lab

Serves the built lab, the highscore API (replays re-simulated in worker threads; scores and
their replays in PostgreSQL) and, on the same port: the multiplayer relay at /ws/<room>
(WebSocket; server-ordered inputs for lockstep and rollback, desync detection), state-sync
rooms at /state/<room> (the server runs the game and sends the world), WebRTC signalling for
peer-to-peer matches at /signal/<room>, a quick-match queue at /match; /healthz, /readyz and
/metrics (Prometheus). Every WebSocket surface takes pages of this server only unless
--allowed-origins says otherwise, and caps sockets and rooms per client address.

Ctrl-C stops at once; SIGTERM drains first (no new rooms; running matches get
$FIXEDSTEP_DRAIN_MS, default 25000 ms). Caps, allowed origins, the trusted proxy and the
quick-match ticket secret shared by a deployment's processes ($FIXEDSTEP_MATCH_SECRET) and the
STUN/TURN servers signalling announces ($FIXEDSTEP_ICE_SERVERS) come from FIXEDSTEP_* variables
(docs/deploy.md, docs/webrtc.md).

Scores go to the embedded PostgreSQL (PGlite) in <data>/pglite, or to the PostgreSQL server
of $DATABASE_URL when it is set (then any number of server processes may share it).

Usage:
  fixedstep serve [--port <n>] [--host <address>] [--root <dir>] [--data <dir>] [--games <module>]

Options:
${formatOptions(SERVE_OPTIONS)}

The lab ships in the package; in a checkout of the repository, build it first: npm run build
`;

const INTEGRATORS_OPTIONS: OptionSpec[] = [
  {
    name: 'omega',
    kind: 'number',
    min: 0,
    max: 1e6,
    valueName: 'rad/s',
    help: 'Angular frequency ω = √(k/m) (default: √20 ≈ 4.472, k = 20 N/m, m = 1 kg)',
  },
  {
    name: 'dt',
    kind: 'number',
    min: 1e-6,
    max: 10,
    valueName: 's',
    help: "Time step (default: 0.03, the talk's TIME_STEP)",
  },
  {
    name: 'duration',
    kind: 'number',
    min: 1e-6,
    max: 1e6,
    valueName: 's',
    help: 'Simulated time (default: 10)',
  },
  {
    name: 'x0',
    kind: 'number',
    min: -1e6,
    max: 1e6,
    valueName: 'm',
    help: 'Start position (default: 1)',
  },
  {
    name: 'v0',
    kind: 'number',
    min: -1e6,
    max: 1e6,
    valueName: 'm/s',
    help: 'Start velocity (default: 0)',
  },
  {
    name: 'methods',
    kind: 'string',
    valueName: 'list',
    help: `Comma-separated subset of: ${INTEGRATOR_METHODS.join(', ')}`,
  },
  {
    name: 'csv',
    kind: 'string',
    valueName: 'file',
    help: 'Write the sampled series (t, x, energy ratio per method) as CSV',
  },
  {
    name: 'svg',
    kind: 'string',
    valueName: 'file',
    help: 'Write a plot of the energy ratio over time as SVG',
  },
  { name: 'help', short: 'h', kind: 'flag', help: 'Show this help' },
];

export const INTEGRATORS_HELP = `fixedstep experiment integrators — six integrators on the harmonic oscillator

Runs explicit Euler, semi-implicit Euler, backward Euler, position Verlet, velocity Verlet and
RK4 on x'' = -ω²x and prints each one's energy ratio E(T)/E(0), its largest energy error and its
phase error against the exact solution.

Usage:
  fixedstep experiment integrators [options]

Options:
${formatOptions(INTEGRATORS_OPTIONS)}

Example:
  fixedstep experiment integrators --dt 0.03 --duration 10 --svg energy.svg
`;

/** What the command line asks for. */
export type Command =
  | { kind: 'help'; text: string }
  | { kind: 'version' }
  | {
      kind: 'serve';
      port: number;
      host: string;
      root: string | undefined;
      data?: string;
      games?: string;
      trustProxy?: string;
      allowedOrigins?: OriginPolicy;
      workers?: number;
      maxConnections?: number;
      databaseUrl?: string;
    }
  | {
      kind: 'experiment-integrators';
      options: IntegratorExperimentOptions;
      csv?: string;
      svg?: string;
    }
  | { kind: 'experiment-tunnel'; options: TunnelExperimentOptions; csv?: string }
  | { kind: 'replay-info'; file: string; json: boolean }
  | { kind: 'replay-verify'; file: string; quiet: boolean; games?: string }
  | CheckCommand
  | { kind: 'usage-error'; message: string; help: string };

/** A port from the command line or the environment: an integer from 0 to 65535, or undefined. */
export function parsePort(text: string): number | undefined {
  if (!/^\d{1,5}$/.test(text)) return undefined;
  const n = Number(text);
  return n <= 65535 ? n : undefined;
}

function str(v: OptionValue | undefined): string | undefined {
  return typeof v === 'string' ? v : undefined;
}
function num(v: OptionValue | undefined, fallback: number): number {
  return typeof v === 'number' ? v : fallback;
}

function parseServe(
  rest: readonly string[],
  env: Readonly<Record<string, string | undefined>>,
): Command {
  const { values } = parseOptions('serve', rest, SERVE_OPTIONS);
  if (values.help) return { kind: 'help', text: SERVE_HELP };
  let port = DEFAULT_PORT;
  const envPort = env.PORT;
  if (envPort !== undefined && envPort !== '')
    port = convertValue(SERVE_OPTIONS[0]!, 'PORT', envPort) as number;
  const originList = str(values['allowed-origins']);
  let origins: OriginPolicy | undefined;
  try {
    if (originList !== undefined) origins = parseOriginPolicy(originList, '--allowed-origins');
  } catch (e) {
    throw new UsageError((e as Error).message);
  }
  return {
    kind: 'serve',
    port: num(values.port, port),
    host: str(values.host) ?? DEFAULT_HOST,
    root: str(values.root),
    ...(str(values.data) !== undefined ? { data: str(values.data) } : {}),
    ...(str(values.games) !== undefined ? { games: str(values.games) } : {}),
    ...(str(values['trust-proxy']) !== undefined ? { trustProxy: str(values['trust-proxy']) } : {}),
    ...(origins !== undefined ? { allowedOrigins: origins } : {}),
    ...(typeof values.workers === 'number' ? { workers: values.workers } : {}),
    ...(typeof values['max-connections'] === 'number'
      ? { maxConnections: values['max-connections'] }
      : {}),
    ...(env.DATABASE_URL !== undefined && env.DATABASE_URL !== ''
      ? { databaseUrl: env.DATABASE_URL }
      : {}),
  };
}

function parseIntegrators(rest: readonly string[]): Command {
  const { values } = parseOptions('experiment integrators', rest, INTEGRATORS_OPTIONS);
  if (values.help) return { kind: 'help', text: INTEGRATORS_HELP };
  const list = str(values.methods);
  const methods = list === undefined ? [...INTEGRATOR_METHODS] : list.split(',');
  const unknown = methods.filter((m) => !(INTEGRATOR_METHODS as readonly string[]).includes(m));
  if (unknown.length > 0 || methods.length === 0) {
    throw new UsageError(
      `--methods: unknown method "${unknown[0] ?? ''}"; choose from ${INTEGRATOR_METHODS.join(', ')}`,
    );
  }
  const x0 = num(values.x0, TALK_INTEGRATOR_EXPERIMENT.x0);
  const v0 = num(values.v0, TALK_INTEGRATOR_EXPERIMENT.v0);
  if (x0 === 0 && v0 === 0)
    throw new UsageError('--x0 and --v0 cannot both be 0: the oscillator would have no energy');
  const dt = num(values.dt, TALK_INTEGRATOR_EXPERIMENT.dt);
  const duration = num(values.duration, TALK_INTEGRATOR_EXPERIMENT.duration);
  if (duration / dt > 1e7)
    throw new UsageError(
      `--duration / --dt is ${Math.round(duration / dt)} steps; at most 10 000 000`,
    );
  return {
    kind: 'experiment-integrators',
    options: {
      omega: num(values.omega, TALK_INTEGRATOR_EXPERIMENT.omega),
      dt,
      duration,
      x0,
      v0,
      methods: methods as IntegratorMethod[],
    },
    ...(str(values.csv) !== undefined ? { csv: str(values.csv) } : {}),
    ...(str(values.svg) !== undefined ? { svg: str(values.svg) } : {}),
  };
}

const COMMANDS: Record<
  string,
  {
    help: string;
    parse: (rest: readonly string[], env: Readonly<Record<string, string | undefined>>) => Command;
  }
> = {
  serve: { help: SERVE_HELP, parse: parseServe },
  'experiment integrators': { help: INTEGRATORS_HELP, parse: (rest) => parseIntegrators(rest) },
  'experiment tunnel': { help: TUNNEL_HELP, parse: (rest) => parseTunnel(rest) },
  'replay info': { help: REPLAY_INFO_HELP, parse: (rest) => parseReplayInfo(rest) },
  'replay verify': { help: REPLAY_VERIFY_HELP, parse: (rest) => parseReplayVerify(rest) },
  check: { help: CHECK_HELP, parse: (rest) => parseCheck(rest) },
};

/**
 * Parses the arguments (without \`node\` and the script). Pure: the environment is passed in, only
 * \`PORT\` is read from it; \`--port\` wins over \`PORT\`.
 */
export function parseArgs(
  argv: readonly string[],
  env: Readonly<Record<string, string | undefined>> = {},
): Command {
  const [first, ...rest] = argv;
  if (first === undefined || first === '-h' || first === '--help' || first === 'help') {
    const topic = COMMANDS[rest.join(' ')];
    return { kind: 'help', text: first === 'help' && topic ? topic.help : MAIN_HELP };
  }
  if (first === '-v' || first === '--version') return { kind: 'version' };
  if (first.startsWith('-'))
    return { kind: 'usage-error', message: `unknown option: ${first}`, help: MAIN_HELP };
  const group = first === 'experiment' || first === 'replay';
  const name =
    group && rest[0] !== undefined && !rest[0].startsWith('-') ? `${first} ${rest[0]}` : first;
  const command = COMMANDS[name];
  if (!command) {
    const message =
      first === 'experiment'
        ? 'experiment needs a name: integrators or tunnel'
        : first === 'replay'
          ? 'replay needs a subcommand: info or verify'
          : `unknown command: ${first}`;
    return { kind: 'usage-error', message, help: MAIN_HELP };
  }
  try {
    return command.parse(name === first ? rest : rest.slice(1), env);
  } catch (error) {
    if (error instanceof UsageError)
      return { kind: 'usage-error', message: error.message, help: command.help };
    throw error;
  }
}

/** Where the command writes, and what it waits on (injected so tests can run it). */
export interface CliIo {
  out(text: string): void;
  err(text: string): void;
  /** Progress of long work (e.g. `done` of `total` cells); the default draws a bar on stderr. */
  progress?(done: number, total: number): void;
  /**
   * Resolves when the process is asked to stop. Default: SIGINT (Ctrl-C: stop at once) or SIGTERM
   * (resolves with `'SIGTERM'`: running relay matches get up to `FIXEDSTEP_DRAIN_MS`, default
   * 25 000 ms, to end first — a rolling update or a scale-down).
   */
  stopSignal?: Promise<unknown>;
}

const processIo: CliIo = {
  out: (text) => process.stdout.write(text),
  err: (text) => process.stderr.write(text),
  progress: (done, total) => {
    if (!process.stderr.isTTY) return;
    const width = 30;
    const fill = Math.round((done / total) * width);
    process.stderr.write(
      `\r[${'#'.repeat(fill)}${'.'.repeat(width - fill)}] ${done}/${total}${done === total ? '\n' : ''}`,
    );
  },
};

function signals(): Promise<NodeJS.Signals> {
  return new Promise((resolve) => {
    const stop = (signal: NodeJS.Signals) => {
      process.off('SIGINT', stop);
      process.off('SIGTERM', stop);
      resolve(signal);
    };
    process.on('SIGINT', stop);
    process.on('SIGTERM', stop);
  });
}

/** How long a SIGTERM lets running relay matches go on: `FIXEDSTEP_DRAIN_MS`, default 25 s. */
function drainTimeoutMs(env: Readonly<Record<string, string | undefined>>): number {
  const raw = env.FIXEDSTEP_DRAIN_MS?.trim();
  if (raw === undefined || raw === '') return 25_000;
  const ms = Number(raw);
  if (!(Number.isInteger(ms) && ms >= 0 && ms <= 3_600_000)) {
    throw new Error(`FIXEDSTEP_DRAIN_MS: "${raw}" is not a whole number of ms from 0 to 3600000`);
  }
  return ms;
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
    case 'experiment-integrators': {
      const exp = runIntegratorExperiment(command.options);
      io.out(formatIntegratorTable(exp));
      return writeOutputs(io, [
        [command.csv, () => integratorCsv(exp)],
        [
          command.svg,
          () =>
            lineChartSvg(
              exp.results.map((r) => ({ label: r.label, x: r.t, y: r.energy })),
              {
                title: `Energy E(t)/E(0), ω = ${command.options.omega.toFixed(3)} rad/s, dt = ${command.options.dt} s`,
                xLabel: 'time (s)',
                yLabel: 'energy ratio (log scale)',
                logY: true,
                yRange: [-3, 6],
              },
            ),
        ],
      ]);
    }
    case 'experiment-tunnel': {
      const table = runTunnelExperiment(command.options, (done, total) => {
        io.progress?.(done, total);
      });
      io.out(formatTunnelTable(table));
      return writeOutputs(io, [[command.csv, () => tunnelCsv(table)]]);
    }
    case 'replay-info':
      return replayInfo(command, io);
    case 'replay-verify':
      return replayVerify(command, io);
    case 'check':
      return runCheckCommand(command, io, env);
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
      const dataDir = path.resolve(command.data ?? 'fixedstep-data');
      let server;
      let drainMs: number;
      try {
        drainMs = drainTimeoutMs(process.env);
        const games = await loadGames(command.games === undefined ? [] : [command.games]);
        // Fast: checks and locks the data folder (or names the PostgreSQL server); the database
        // opens while the server already listens (the highscore API answers 503 until then).
        const prepared = await prepareStore({
          dataDir,
          ...(command.databaseUrl !== undefined ? { databaseUrl: command.databaseUrl } : {}),
        });
        // The server opens it while it listens, and tries again while it cannot (a PostgreSQL
        // server that is down); what opening did (a folder set aside, a table imported) is said.
        const store: PreparedStore = {
          ...prepared,
          open: async () => {
            const opened = await prepared.open();
            for (const note of opened.notes) io.out(`fixedstep: ${note}\n`);
            return opened;
          },
        };
        server = await createServer({
          port: command.port,
          host: command.host,
          root,
          docs: defaultDocsRoot(),
          games,
          store,
          ...(command.trustProxy !== undefined ? { trustProxy: command.trustProxy } : {}),
          ...(command.allowedOrigins !== undefined
            ? { allowedOrigins: command.allowedOrigins }
            : {}),
          ...(command.workers !== undefined ? { verification: { workers: command.workers } } : {}),
          ...(command.maxConnections !== undefined
            ? { limits: { maxConnections: command.maxConnections } }
            : {}),
          log: (message, error) => {
            io.err(
              `fixedstep: ${message}${error === undefined ? '' : `: ${error instanceof Error ? error.message : JSON.stringify(error)}`}\n`,
            );
          },
        });
        io.out(`fixedstep lab: ${server.url} (press Ctrl-C to stop)\n`);
        io.out(`games: ${games.games.map((g) => `${g.id} v${g.version}`).join(', ')}\n`);
        io.out(`highscores kept in ${prepared.description}\n`);
      } catch (error) {
        const message = error instanceof Error ? error.message : String(error);
        io.err(`fixedstep: ${error instanceof GamesModuleError ? '' : ''}${message}\n`);
        return EXIT_FAILURE;
      }
      if (command.host === '0.0.0.0' || command.host === '::') {
        io.out(`(listening on every interface, port ${server.port})\n`);
      }
      const signal = await (io.stopSignal ?? signals());
      if (signal === 'SIGTERM') {
        io.out(
          `fixedstep: draining (no new rooms; running matches get up to ${drainMs} ms), then stopping\n`,
        );
        await server.drain(drainMs);
      }
      io.out('fixedstep: stopping (finishing queued verifications, closing rooms and the store)\n');
      await server.close();
      return EXIT_OK;
    }
  }
}

/** Writes each `[file, contents]` whose file was asked for; 1 with a message if one cannot be written. */
function writeOutputs(io: CliIo, outputs: [string | undefined, () => string][]): number {
  for (const [file, make] of outputs) {
    if (file === undefined) continue;
    try {
      writeFileSync(file, make());
      io.out(`wrote ${file}\n`);
    } catch (error) {
      io.err(
        `fixedstep: cannot write ${file}: ${error instanceof Error ? error.message : String(error)}\n`,
      );
      return EXIT_FAILURE;
    }
  }
  return EXIT_OK;
}

/** True when this module is the program (`node dist/cli.js`), not an import. */
function isMain(): boolean {
  const entry = process.argv[1];
  return entry !== undefined && import.meta.url === pathToFileURL(path.resolve(entry)).href;
}

if (isMain()) {
  process.exitCode = await run(process.argv.slice(2));
}
