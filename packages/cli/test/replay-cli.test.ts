import { spawnSync } from 'node:child_process';
import { mkdtemp, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { BUTTON_WORD, ByteWriter, Fnv1a64, ReplayRecorder, gameSetup } from 'fixedstep';
import { run } from '@fixedstep/cli';
import { coinDash } from '../../../examples/coin-dash/src/game.js';
import { recordRunner } from '../../server/test/replay-fixtures.js';

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

describe('fixedstep replay on hostile files', () => {
  it.each([
    ['/dev/zero', /it is a device/],
    [os.tmpdir(), /it is a directory/],
  ])('refuses %s with a message and exit 1, without reading it', async (p, message) => {
    for (const sub of ['info', 'verify']) {
      const r = await cli(['replay', sub, p]);
      expect(r.code).toBe(1);
      expect(r.stderr).toMatch(message);
    }
  });

  it('refuses a FIFO without waiting for a writer', async () => {
    const fifo = path.join(dir, 'pipe.fsr');
    expect(spawnSync('mkfifo', [fifo]).status).toBe(0);
    const r = await cli(['replay', 'info', fifo]);
    expect(r.code).toBe(1);
    expect(r.stderr).toContain('it is a FIFO (named pipe), not a replay file');
  });

  it('prints names from the file without control characters', async () => {
    const evil = recordRunner(120, {}, 'eve\u001b]0;pwned\u0007\u001b[31mred\u009b2J');
    const p = await file('evil.fsr', evil.bytes);
    const text = await cli(['replay', 'info', p]);
    expect(text.code).toBe(0);
    expect(text.stdout).toContain('eve]0;pwned[31mred2J');
    const codes = Array.from({ length: text.stdout.length }, (_, i) => text.stdout.charCodeAt(i));
    expect(codes.filter((c) => (c < 32 && c !== 10) || (c >= 0x7f && c <= 0x9f))).toEqual([]);
    const json = await cli(['replay', 'info', p, '--json']);
    expect((JSON.parse(json.stdout) as { players: string[] }).players).toEqual([
      'eve]0;pwned[31mred2J',
    ]);
  });

  it('refuses a replay of millions of empty keyframes before allocating them', async () => {
    // 3 M ticks, a keyframe after every tick, each an empty snapshot: a small file that used to
    // make the reader build one object per keyframe.
    const p = await file('keyframes.fsr', keyframeBomb(3_000_000));
    const before = process.memoryUsage().heapUsed;
    const r = await cli(['replay', 'info', p]);
    expect(r.code).toBe(3);
    expect(r.stderr).toMatch(/TOO_LARGE.*keyframe count is 3000000, limit 100000/);
    expect(process.memoryUsage().heapUsed - before).toBeLessThan(200 * 1024 * 1024);
  });

  it('verifies a replay of a game from a --games module, and names a bad module', async () => {
    const game = new URL('../../../examples/coin-dash/src/game.ts', import.meta.url).pathname;
    const p = await file('coin.fsr', recordCoinDash(600));
    const ok = await cli(['replay', 'verify', p, '--quiet', '--games', game]);
    expect(ok.stderr).toBe('');
    expect(ok.stdout).toMatch(/^ok: coin-dash v1, 600 ticks reproduced/);
    expect(ok.code).toBe(0);
    // Without the module the built-in games do not know it.
    const unknown = await cli(['replay', 'verify', p, '--quiet']);
    expect(unknown.code).toBe(3);
    expect(unknown.stderr).toContain('unknown game "coin-dash"');
    const notGames = await file(
      'not-games.mjs',
      new TextEncoder().encode('export default { hello: 1 };'),
    );
    const bad = await cli(['replay', 'verify', p, '--games', notGames]);
    expect(bad.code).toBe(1);
    expect(bad.stderr).toContain(`games module "${notGames}": not a valid game definition`);
    const none = await cli(['replay', 'verify', p, '--games', path.join(dir, 'missing.mjs')]);
    expect(none.stderr).toContain('no such file');
    // A top-level await that never settles: refused with a message after the import timeout,
    // not Node's silent exit code 13.
    const stuck = await file(
      'stuck.mjs',
      new TextEncoder().encode('await new Promise(() => {});\nexport default [];'),
    );
    process.env.FIXEDSTEP_GAMES_IMPORT_TIMEOUT_MS = '300';
    try {
      const hung = await cli(['replay', 'verify', p, '--games', stuck]);
      expect(hung.code).toBe(1);
      expect(hung.stderr).toContain(`games module "${stuck}": still loading after 0.3 s`);
      expect(hung.stderr).toContain('top level await');
    } finally {
      delete process.env.FIXEDSTEP_GAMES_IMPORT_TIMEOUT_MS;
    }
  });
});

function recordCoinDash(ticks: number): Uint8Array {
  const setup = gameSetup(coinDash, 1, 5);
  const rec = ReplayRecorder.forGame(coinDash, setup, ['cat'], { checkpointEvery: 60 });
  const sim = coinDash.create(setup);
  rec.start(sim);
  for (let t = 0; t < ticks; t++) {
    const input = coinDash.bot!(sim, 0);
    sim.step([input]);
    rec.record([input], sim);
  }
  return rec.finish();
}

/**
 * A well-formed replay file of `ticks` ticks with a checkpoint and an empty keyframe after every
 * tick (written section by section, as docs/replay-format.md lays them out): 9 bytes a tick.
 */
function keyframeBomb(ticks: number): Uint8Array {
  const section = (w: ByteWriter, id: number, payload: Uint8Array) =>
    w.u8(id).u32(payload.length).bytes(payload);
  const game = new ByteWriter()
    .str('runner')
    .str('1')
    .varint(1)
    .varint(60)
    .varint(1)
    .u32(1)
    .varint(0)
    .varint(1)
    .str('x')
    .varint(BUTTON_WORD.descriptor.length)
    .bytes(BUTTON_WORD.descriptor)
    .finish();
  const tickSection = new ByteWriter().u32(ticks).u64(0n).varint(1).varint(1).finish();
  const stream = new ByteWriter()
    .varint(0)
    .varint(ticks - 1)
    .finish();
  const inputs = new ByteWriter().varint(stream.length).bytes(stream).finish();
  const checkpoints = new Uint8Array((ticks + 1) * 8); // all 0, the final hash too
  const keyframes = new Uint8Array(ticks); // a 0-byte length each
  const body = new ByteWriter(ticks * 9 + 1024);
  section(body, 1, game);
  section(body, 2, tickSection);
  section(body, 3, inputs);
  section(body, 4, checkpoints);
  section(body, 5, keyframes);
  const sections = body.finish();
  const total = 16 + sections.length + 8;
  const head = new ByteWriter()
    .bytes(new TextEncoder().encode('FSREPLAY'))
    .u32(2)
    .u32(total)
    .finish();
  const file = new Uint8Array(total);
  file.set(head, 0);
  file.set(sections, 16);
  const sum = new Fnv1a64().update(file.subarray(0, total - 8)).digest();
  new DataView(file.buffer).setBigUint64(total - 8, sum, true);
  return file;
}
