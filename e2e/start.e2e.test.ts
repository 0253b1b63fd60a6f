/**
 * `npm start` on a fresh copy of the repository (the files a clone of the working tree would have,
 * no node_modules, nothing built): it installs only what serving needs, prints a line per stage,
 * reaches the server's start line, serves the lab, and stops on Ctrl-C; a second start skips
 * every stage; a changed source rebuilds only the stage it feeds. Runs scripts/start.mjs directly
 * (what `npm start` runs), with npm's cache preferred over the registry.
 */
import { execFileSync, spawn } from 'node:child_process';
import { existsSync, readdirSync } from 'node:fs';
import { appendFile, copyFile, mkdir, mkdtemp, rm } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';

const repo = fileURLToPath(new URL('..', import.meta.url));
let copy: string;

interface Started {
  output: string;
  code: number | null;
}

/**
 * Runs `node scripts/start.mjs --port 0` in the copy until the server prints its URL, fetches the
 * lab from it, then sends Ctrl-C (SIGINT) and waits for the exit.
 */
function start(): Promise<Started & { page: string }> {
  return new Promise((resolve, reject) => {
    const child = spawn(process.execPath, ['scripts/start.mjs', '--port', '0'], {
      cwd: copy,
      env: { ...process.env, npm_config_prefer_offline: 'true', NO_COLOR: '1' },
      stdio: ['ignore', 'pipe', 'pipe'],
    });
    let output = '';
    let page: Promise<string> | undefined;
    const onData = (d: Buffer) => {
      output += d.toString('utf8');
      const url = /fixedstep lab: (http:\/\/localhost:\d+\/) \(press Ctrl-C to stop\)/.exec(output);
      if (url && !page) {
        page = fetch(url[1]!.replace('localhost', '127.0.0.1'))
          .then((r) => r.text())
          .finally(() => child.kill('SIGINT'));
      }
    };
    child.stdout.on('data', onData);
    child.stderr.on('data', onData);
    child.on('error', reject);
    child.on('exit', (code) => {
      if (!page) {
        resolve({ output, code, page: '' });
        return;
      }
      page.then(
        (text) => {
          resolve({ output, code, page: text });
        },
        (error: unknown) => {
          reject(error instanceof Error ? error : new Error(String(error)));
        },
      );
    });
  });
}

beforeAll(async () => {
  copy = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-start-'));
  // What a clone would hold: tracked files and new files that are not ignored, as they are now.
  const files = execFileSync(
    'git',
    ['ls-files', '-z', '--cached', '--others', '--exclude-standard'],
    {
      cwd: repo,
      encoding: 'utf8',
    },
  )
    .split('\0')
    .filter((f) => f !== '' && existsSync(path.join(repo, f)));
  for (const f of files) {
    await mkdir(path.dirname(path.join(copy, f)), { recursive: true });
    await copyFile(path.join(repo, f), path.join(copy, f));
  }
});

afterAll(async () => {
  await rm(copy, { recursive: true, force: true });
});

describe('npm start on a fresh copy', () => {
  it('installs what serving needs, builds, serves the lab and stops on Ctrl-C, a line per stage', async () => {
    const first = await start();
    const out = first.output;
    expect(out).toMatch(
      /^▸ 1\/4 Dependencies: installing what the lab and the server need \(npm ci --no-audit --no-fund --workspace packages\/server --workspace packages\/cli --workspace apps\/lab\)$/m,
    );
    expect(out).toMatch(/^✓ 1\/4 Dependencies: installed in [\d.]+ m?s$/m);
    expect(out).toMatch(/^✓ 2\/4 Library, games, server, CLI: compiled \d+ files in [\d.]+ m?s$/m);
    expect(out).toMatch(/^✓ 3\/4 Lab: built in [\d.]+ m?s$/m);
    expect(out).toMatch(/^▸ 4\/4 Server: starting/m);
    // No EBADENGINE, no install-script notice, no deprecation: nothing for the user to wonder about.
    expect(out).not.toMatch(/npm warn|EBADENGINE|install-scripts/i);
    // On failure the received value is the output, which says why.
    expect(first.page || out).toContain('<title>fixedstep lab</title>');
    expect(first.code).toBe(0);
    // Only the lab's and the server's dependencies: no compiler, linter, browser driver or peers.
    const installed = readdirSync(path.join(copy, 'node_modules'));
    expect(installed).toEqual(expect.arrayContaining(['vite', 'ws', 'uplot', 'fixedstep']));
    for (const tool of [
      'typescript',
      'eslint',
      'playwright-core',
      'vitest',
      'matter-js',
      'typedoc',
    ]) {
      expect(installed).not.toContain(tool);
    }
  });

  it('stops when the npm that started it is killed with SIGTERM (npm does not pass it on)', async () => {
    // `npm start` in a process group of its own, so whatever is left can be cleaned up below.
    const npm = spawn('npm', ['start', '--', '--port', '0'], {
      cwd: copy,
      env: { ...process.env, npm_config_prefer_offline: 'true', NO_COLOR: '1' },
      stdio: ['ignore', 'pipe', 'pipe'],
      detached: true,
    });
    try {
      let output = '';
      const url = await new Promise<string>((resolve, reject) => {
        const onData = (d: Buffer) => {
          output += d.toString('utf8');
          const m = /fixedstep lab: (http:\/\/localhost:\d+\/)/.exec(output);
          if (m) resolve(m[1]!.replace('localhost', '127.0.0.1'));
        };
        npm.stdout.on('data', onData);
        npm.stderr.on('data', onData);
        npm.on('exit', (code) => {
          reject(new Error(`npm start exited (${String(code)}) before serving:\n${output}`));
        });
      });
      expect((await fetch(url)).status).toBe(200);
      process.kill(npm.pid!, 'SIGTERM');
      // The server notices that npm is gone, drains (no match is running) and closes its port.
      let closed = false;
      for (const deadline = Date.now() + 60_000; !closed && Date.now() < deadline;) {
        closed = await fetch(url).then(
          () => false,
          () => true,
        );
        if (!closed) await new Promise((r) => setTimeout(r, 100));
      }
      expect(closed, `still serving at ${url} after npm was killed:\n${output}`).toBe(true);
    } finally {
      try {
        process.kill(-npm.pid!, 'SIGKILL');
      } catch {
        // The group is gone already: nothing was left behind.
      }
    }
  });

  it('a second start skips every stage; a changed source rebuilds only what it feeds', async () => {
    const warm = await start();
    expect(warm.output).toMatch(/^✓ 1\/4 Dependencies: up to date/m);
    expect(warm.output).toMatch(
      /^✓ 2\/4 Library, games, server, CLI: up to date \(sources unchanged/m,
    );
    expect(warm.output).toMatch(/^✓ 3\/4 Lab: up to date \(sources unchanged/m);
    expect(warm.output).not.toMatch(/^▸ [123]\/4/m);
    expect(warm.page || warm.output).toContain('<title>fixedstep lab</title>');
    expect(warm.code).toBe(0);

    // The CLI's sources feed the compile stage, not the lab.
    await appendFile(path.join(copy, 'packages/server/src/index.ts'), '// changed\n');
    const changed = await start();
    expect(changed.output).toMatch(/^✓ 2\/4 Library, games, server, CLI: compiled \d+ files in/m);
    expect(changed.output).toMatch(/^✓ 3\/4 Lab: up to date/m);
    expect(changed.code).toBe(0);
  });
});
