import { mkdtemp, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { run } from '@fixedstep/cli';
import { recordRunner } from './replay-fixtures.js';

let dir: string;
beforeAll(async () => {
  dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-replay-'));
});
afterAll(async () => {
  await rm(dir, { recursive: true, force: true });
});

async function cli(args: string[]) {
  const out = { stdout: '', stderr: '', progress: [] as number[] };
  const code = await run(
    args,
    {},
    {
      out: (t) => (out.stdout += t),
      err: (t) => (out.stderr += t),
      progress: (done) => out.progress.push(done),
    },
  );
  return { code, ...out };
}

async function file(name: string, bytes: Uint8Array): Promise<string> {
  const p = path.join(dir, name);
  await writeFile(p, bytes);
  return p;
}

describe('fixedstep replay', () => {
  it('info prints what the file holds, as text and as JSON', async () => {
    const p = await file('a.fsr', recordRunner(1800).bytes);
    const text = await cli(['replay', 'info', p]);
    expect(text.code).toBe(0);
    expect(text.stdout).toMatch(/game\s+runner/);
    expect(text.stdout).toMatch(/ticks\s+1800/);
    const json = await cli(['replay', 'info', p, '--json']);
    const facts = JSON.parse(json.stdout) as {
      ticks: number;
      tickRate: number;
      players: string[];
      sections: unknown[];
    };
    expect(facts.ticks).toBe(1800);
    expect(facts.tickRate).toBe(60);
    expect(facts.players).toEqual(['ada']);
    expect(facts.sections.length).toBeGreaterThanOrEqual(5);
  });

  it('verify reproduces an honest replay, with progress, and exits 0', async () => {
    const p = await file('honest.fsr', recordRunner(3600).bytes);
    const r = await cli(['replay', 'verify', p]);
    expect(r.code).toBe(0);
    expect(r.stdout).toMatch(/^ok: runner v\d+, 3600 ticks reproduced, final hash [0-9a-f]{16}/);
    expect(r.progress.at(-1)).toBe(3600);
    expect(r.progress.length).toBeGreaterThan(10);
  });

  it('verify names where a forged replay stops reproducing, and exits 4', async () => {
    const p = await file('forged.fsr', recordRunner(3600, { editTick: 1000 }).bytes);
    const r = await cli(['replay', 'verify', p, '--quiet']);
    expect(r.code).toBe(4);
    // The first jump after tick 1000 is gone, so the runner crashes soon after; with a
    // checkpoint every 60 ticks the verifier names a window of 60 ticks after the edit.
    expect(r.stdout).toContain('MISMATCH: runner');
    const [, lo, hi] = /in \((\d+), (\d+)\]/.exec(r.stdout)!.map(Number);
    expect(hi! - lo!).toBe(60);
    expect(lo).toBeGreaterThanOrEqual(960);
    expect(hi).toBeLessThan(1200);
    expect(r.progress).toHaveLength(0);
  });

  it('verify refuses a replay whose header claims another seed', async () => {
    const p = await file('seed.fsr', recordRunner(600, { claimSeed: 8 }).bytes);
    const r = await cli(['replay', 'verify', p]);
    expect(r.code).toBe(4);
    expect(r.stdout).toContain('after tick 0');
  });

  it('exits 3 for a damaged file, 1 for a missing one, 2 without a file', async () => {
    const bytes = recordRunner(600).bytes.slice();
    bytes[40] = bytes[40]! ^ 0xff;
    const damaged = await cli(['replay', 'verify', await file('bad.fsr', bytes)]);
    expect(damaged.code).toBe(3);
    expect(damaged.stderr).toMatch(/not a valid replay \(BAD_CHECKSUM\)/);
    const garbage = await cli([
      'replay',
      'info',
      await file('garbage.txt', new TextEncoder().encode('hello')),
    ]);
    expect(garbage.code).toBe(3);
    const missing = await cli(['replay', 'info', path.join(dir, 'nope.fsr')]);
    expect(missing.code).toBe(1);
    expect(missing.stderr).toContain('cannot read');
    expect((await cli(['replay', 'verify'])).code).toBe(2);
    expect((await cli(['replay'])).stderr).toContain('replay needs a subcommand: info or verify');
  });
});
