import { mkdtemp, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import {
  DEFAULT_PORT,
  EXIT_FAILURE,
  EXIT_OK,
  EXIT_USAGE,
  MAIN_HELP,
  SERVE_HELP,
  parseArgs,
  run,
} from '@fixedstep/cli';
import { startServer } from '@fixedstep/server';

function capture(stop?: Promise<void>) {
  const io = { stdout: '', stderr: '' };
  return {
    io,
    cli: {
      out: (t: string) => {
        io.stdout += t;
      },
      err: (t: string) => {
        io.stderr += t;
      },
      ...(stop ? { stopSignal: stop } : {}),
    },
  };
}

describe('parseArgs', () => {
  it('shows help with no arguments, -h, --help and help', () => {
    for (const argv of [[], ['-h'], ['--help'], ['help']]) {
      expect(parseArgs(argv)).toEqual({ kind: 'help', text: MAIN_HELP });
    }
    expect(parseArgs(['serve', '--help'])).toEqual({ kind: 'help', text: SERVE_HELP });
    expect(parseArgs(['serve', '-h'])).toEqual({ kind: 'help', text: SERVE_HELP });
    expect(parseArgs(['help', 'serve'])).toEqual({ kind: 'help', text: SERVE_HELP });
  });

  it('serves on 127.0.0.1:8080 by default', () => {
    expect(parseArgs(['serve'])).toEqual({
      kind: 'serve',
      port: DEFAULT_PORT,
      host: '127.0.0.1',
      root: undefined,
    });
    expect(DEFAULT_PORT).toBe(8080);
  });

  it('takes PORT from the environment, and --port over it', () => {
    expect(parseArgs(['serve'], { PORT: '3000' })).toMatchObject({ port: 3000 });
    expect(parseArgs(['serve', '--port', '4000'], { PORT: '3000' })).toMatchObject({ port: 4000 });
    expect(parseArgs(['serve', '--port=4001'])).toMatchObject({ port: 4001 });
    expect(parseArgs(['serve', '-p', '0'])).toMatchObject({ port: 0 });
    expect(parseArgs(['serve'], { PORT: '' })).toMatchObject({ port: 8080 });
  });

  it('takes --host and --root', () => {
    expect(parseArgs(['serve', '--host', '0.0.0.0', '--root=/tmp/x'])).toEqual({
      kind: 'serve',
      port: 8080,
      host: '0.0.0.0',
      root: '/tmp/x',
    });
  });

  it('takes --allowed-origins: same-origin (the default, and what --help says), a list, or any', () => {
    expect(SERVE_HELP).toMatch(/same-origin \(the default: pages of this server only\)/);
    expect(SERVE_HELP).not.toMatch(/default: any/);
    expect(SERVE_HELP).toContain('/signal/<room>');
    expect(parseArgs(['serve'])).not.toHaveProperty('allowedOrigins');
    expect(parseArgs(['serve', '--allowed-origins', 'same-origin'])).toMatchObject({
      allowedOrigins: 'same-origin',
    });
    expect(
      parseArgs(['serve', '--allowed-origins', 'https://a.example, http://b.example:8080']),
    ).toMatchObject({ allowedOrigins: ['https://a.example', 'http://b.example:8080'] });
    expect(parseArgs(['serve', '--allowed-origins=any'])).toMatchObject({ allowedOrigins: 'any' });
    expect(parseArgs(['serve', '--allowed-origins', 'a.example'])).toMatchObject({
      kind: 'usage-error',
      message:
        '--allowed-origins: "a.example" is not an origin like https://game.example (or same-origin, or any)',
    });
  });

  it.each([
    [['bogus'], 'unknown command: bogus'],
    [['--bogus'], 'unknown option: --bogus'],
    [['serve', '--port'], '--port needs a value'],
    [['serve', '--port', 'abc'], '--port must be an integer from 0 to 65535, got "abc"'],
    [['serve', '--port', '70000'], '--port must be an integer from 0 to 65535, got "70000"'],
    [['serve', '-p', '-1'], '-p must be an integer from 0 to 65535, got "-1"'],
    [['serve', '-p', '--host'], '-p needs a value'],
    [['serve', '--port', '80.5'], '--port must be an integer from 0 to 65535, got "80.5"'],
    [['serve', '--host'], '--host needs a value'],
    [['serve', '--verbose'], 'unknown option for serve: --verbose'],
    [['serve', 'extra'], 'unexpected argument for serve: extra'],
  ])('reports a usage error for %j', (argv, message) => {
    expect(parseArgs(argv)).toMatchObject({ kind: 'usage-error', message });
  });

  it('reports a bad PORT in the environment', () => {
    expect(parseArgs(['serve'], { PORT: 'eighty' })).toMatchObject({
      kind: 'usage-error',
      message: 'PORT must be an integer from 0 to 65535, got "eighty"',
    });
  });
});

describe('run', () => {
  it('prints help and exits 0', async () => {
    const { io, cli } = capture();
    expect(await run(['--help'], {}, cli)).toBe(EXIT_OK);
    expect(io.stdout).toContain('fixedstep serve');
    expect(io.stderr).toBe('');
  });

  it('prints the version and exits 0', async () => {
    const { io, cli } = capture();
    expect(await run(['--version'], {}, cli)).toBe(EXIT_OK);
    expect(io.stdout).toMatch(/^\d+\.\d+\.\d+\n$/);
  });

  it('exits 2 with the message and the help on a usage error', async () => {
    const { io, cli } = capture();
    expect(await run(['serve', '--port', 'x'], {}, cli)).toBe(EXIT_USAGE);
    expect(io.stderr).toContain('fixedstep: --port must be an integer');
    expect(io.stderr).toContain('Usage:');
    expect(io.stdout).toBe('');
  });

  it('exits 1 when there is nothing to serve', async () => {
    const { io, cli } = capture();
    const missing = path.join(os.tmpdir(), 'fixedstep-no-such-dir');
    expect(await run(['serve', '--root', missing, '--port', '0'], {}, cli)).toBe(EXIT_FAILURE);
    expect(io.stderr).toContain(`no index.html in ${missing}`);
  });

  it('serves, prints the URL, and exits 0 when stopped', async () => {
    const dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-cli-'));
    try {
      await writeFile(path.join(dir, 'index.html'), 'hello');
      let stop!: () => void;
      const stopped = new Promise<void>((resolve) => {
        stop = resolve;
      });
      const { io, cli } = capture(stopped);
      const done = run(['serve', '--root', dir, '--data', dir], { PORT: '0' }, cli);
      await expect
        .poll(() => io.stdout)
        .toMatch(
          /^fixedstep lab: http:\/\/localhost:\d+\/ \(press Ctrl-C to stop\)\ngames: runner v\d+, ctf v\d+, survival v\d+\nhighscores kept in PGlite in .*pglite\n$/,
        );
      const url = /http:\/\/localhost:\d+\//.exec(io.stdout)![0].replace('localhost', '127.0.0.1');
      expect(await (await fetch(url)).text()).toBe('hello');
      stop();
      expect(await done).toBe(EXIT_OK);
      expect(io.stdout).toContain('fixedstep: stopping');
    } finally {
      await rm(dir, { recursive: true, force: true });
    }
  });

  it('exits 1 with a clear message when the port is in use', async () => {
    const dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-cli-'));
    const busy = await startServer({ port: 0, root: dir });
    try {
      await writeFile(path.join(dir, 'index.html'), 'hello');
      const { io, cli } = capture();
      expect(
        await run(['serve', '--root', dir, '--data', dir, '--port', String(busy.port)], {}, cli),
      ).toBe(EXIT_FAILURE);
      expect(io.stderr).toBe(
        `fixedstep: port ${busy.port} on 127.0.0.1 is already in use (choose another with --port)\n`,
      );
    } finally {
      await busy.close();
      await rm(dir, { recursive: true, force: true });
    }
  });
});
