/**
 * A local npm registry for the package tests: Verdaccio (a devDependency) with its storage in a
 * scratch folder, on 127.0.0.1 at a port the system picks, proxying the public registry for
 * third-party dependencies only — `fixedstep`, `@fixedstep/*` and `create-fixedstep` come from
 * what a test publishes, never from the uplink. And long-running programs (the registry,
 * `fixedstep serve`) started in a process group of their own, so that stopping one stops what it
 * started too (`npx` runs the command as a child).
 */
import { spawn, type ChildProcess } from 'node:child_process';
import { writeFile } from 'node:fs/promises';
import { createServer } from 'node:net';
import path from 'node:path';
import { repo } from './pack-helpers.js';

/** A program started by {@link startProgram}: what it printed so far, its end, and a way to stop it. */
export interface Program {
  readonly child: ChildProcess;
  /** Everything it wrote to stdout and stderr, in order. */
  output(): string;
  /** Resolves with its exit code (or the signal's name) when it has ended. */
  readonly exited: Promise<number | string>;
  /**
   * Stops it and everything it started: `signal` to the process group, SIGKILL if the group is
   * still there after `graceMs`. Resolves when the program has ended.
   */
  stop(signal?: NodeJS.Signals, graceMs?: number): Promise<void>;
}

/** Starts `file args` in `cwd` as the leader of a new process group (never through a shell). */
export function startProgram(
  file: string,
  args: readonly string[],
  cwd: string,
  env: NodeJS.ProcessEnv = {},
): Program {
  const child = spawn(file, args, {
    cwd,
    detached: true,
    stdio: ['ignore', 'pipe', 'pipe'],
    env: { ...process.env, NO_COLOR: '1', ...env },
  });
  let text = '';
  child.stdout.on('data', (d: Buffer) => (text += d.toString()));
  child.stderr.on('data', (d: Buffer) => (text += d.toString()));
  const exited = new Promise<number | string>((resolve) => {
    child.on('exit', (code, signal) => {
      resolve(code ?? signal ?? 'unknown');
    });
    child.on('error', () => {
      resolve('spawn failed');
    });
  });
  const kill = (signal: NodeJS.Signals): void => {
    if (child.pid === undefined) return;
    try {
      process.kill(-child.pid, signal);
    } catch {
      // The group is gone already.
    }
  };
  return {
    child,
    output: () => text,
    exited,
    async stop(signal = 'SIGTERM', graceMs = 10_000) {
      kill(signal);
      let timer: NodeJS.Timeout | undefined;
      const late = new Promise<'late'>((resolve) => {
        timer = setTimeout(() => {
          resolve('late');
        }, graceMs);
      });
      const how = await Promise.race([exited, late]);
      clearTimeout(timer);
      // The leader may be gone while a child of it still runs: the group gets SIGKILL either way.
      kill('SIGKILL');
      if (how === 'late') await exited;
    },
  };
}

/**
 * Polls `check` until it returns a value other than undefined; fails with `what` and the program's
 * output if the program ends first or `timeoutMs` passes.
 */
export async function waitFor<T>(
  what: string,
  check: () => Promise<T | undefined>,
  program: Program,
  timeoutMs = 60_000,
): Promise<T> {
  const deadline = Date.now() + timeoutMs;
  let ended: number | string | undefined;
  void program.exited.then((how) => (ended = how));
  for (;;) {
    const value = await check().catch(() => undefined);
    if (value !== undefined) return value;
    if (ended !== undefined) {
      throw new Error(`${what}: the program ended (${String(ended)}) first:\n${program.output()}`);
    }
    if (Date.now() > deadline) {
      throw new Error(`${what}: not within ${timeoutMs} ms:\n${program.output()}`);
    }
    // Not a sleep standing in for a state: the state is polled, this only paces the polling.
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
}

/**
 * A port that was free a moment ago, for a program that cannot report the port it was given
 * (Verdaccio, asked for port 0, reports 0).
 */
export function freePort(): Promise<number> {
  return new Promise((resolve, reject) => {
    const server = createServer();
    server.once('error', reject);
    server.listen(0, '127.0.0.1', () => {
      const address = server.address();
      server.close(() => {
        if (address !== null && typeof address === 'object') resolve(address.port);
        else reject(new Error('no port'));
      });
    });
  });
}

/** A running local registry. */
export interface Registry {
  /** Its address, `http://127.0.0.1:<port>/`. */
  readonly url: string;
  /**
   * An npm user configuration naming it as the registry, with the token npm insists on before it
   * publishes (Verdaccio lets anyone publish our packages): pass it as NPM_CONFIG_USERCONFIG.
   */
  readonly npmrc: string;
  readonly program: Program;
  stop(): Promise<void>;
}

/** Our packages: published to the registry under test only, never looked up upstream. */
const OURS = ['fixedstep', 'create-fixedstep', '@fixedstep/*'];

/** Starts Verdaccio with its configuration, storage and npmrc in `dir` (an empty scratch folder). */
export async function startRegistry(dir: string): Promise<Registry> {
  const config = path.join(dir, 'verdaccio.yaml');
  const url = `http://127.0.0.1:${await freePort()}/`;
  const ours = OURS.map((p) => `  '${p}':\n    access: $all\n    publish: $all\n`).join('');
  await writeFile(
    config,
    `storage: ${JSON.stringify(path.join(dir, 'storage'))}
auth:
  htpasswd:
    file: ${JSON.stringify(path.join(dir, 'htpasswd'))}
uplinks:
  npmjs:
    url: https://registry.npmjs.org/
    timeout: 60s
    maxage: 30m
packages:
${ours}  '**':
    access: $all
    proxy: npmjs
web:
  enable: false
max_body_size: 100mb
listen: ${url}
log: { type: stdout, format: pretty, level: warn }
`,
  );
  const program = startProgram(
    process.execPath,
    [path.join(repo, 'node_modules/verdaccio/bin/verdaccio'), '--config', config],
    dir,
  );
  try {
    await waitFor(
      'Verdaccio answering',
      async () => ((await fetch(`${url}-/ping`)).ok ? true : undefined),
      program,
    );
    const host = url.replace(/^http:/, '');
    const npmrc = path.join(dir, 'npmrc');
    await writeFile(npmrc, `registry=${url}\n${host}:_authToken=local-test-token\n`);
    return { url, npmrc, program, stop: () => program.stop() };
  } catch (error) {
    await program.stop('SIGKILL');
    throw error;
  }
}
