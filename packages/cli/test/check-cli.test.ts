/**
 * `fixedstep check` in Node (browsers: e2e/check.e2e.test.ts): a correct game passes every check,
 * and each broken game of ./fixtures/check is caught by the checks that should catch it, naming
 * the call or the field and the tick. Unusable modules and command lines get a message and their
 * own exit code.
 */
import { mkdtemp, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { run } from '@fixedstep/cli';

const fixtures = fileURLToPath(new URL('./fixtures/check/', import.meta.url));

let dir: string;
beforeAll(async () => {
  dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-check-'));
});
afterAll(async () => {
  await rm(dir, { recursive: true, force: true });
});

async function check(args: string[], env: Record<string, string> = {}) {
  const out = { stdout: '', stderr: '', progress: [] as [number, number][] };
  const code = await run(['check', ...args], env, {
    out: (t) => (out.stdout += t),
    err: (t) => (out.stderr += t),
    progress: (done, total) => out.progress.push([done, total]),
  });
  return { code, ...out };
}

/** The report's line of one check: `PASS  guard  …`. */
function line(stdout: string, check: string): string {
  const found = stdout.split('\n').find((l) => new RegExp(`^  [A-Z]+ +${check} `).test(l));
  if (found === undefined) throw new Error(`no line for ${check} in:\n${stdout}`);
  return found.trim();
}

async function file(name: string, text: string): Promise<string> {
  const p = path.join(dir, name);
  await writeFile(p, text);
  return p;
}

describe('fixedstep check: the broken games', () => {
  it('passes a correct game, with progress to the last tick', async () => {
    const r = await check([path.join(fixtures, 'correct.ts'), '--engines', 'node']);
    expect(r.stderr).toBe('');
    expect(line(r.stdout, 'guard')).toBe(
      'PASS  guard       600 guarded ticks: no clock, Math.random, crypto or engine math called',
    );
    expect(line(r.stdout, 'twins')).toBe('PASS  twins       two runs agree at all 600 ticks');
    expect(line(r.stdout, 'sync-test')).toBe(
      'PASS  sync-test   600 ticks saved, loaded and resimulated: equal states',
    );
    expect(line(r.stdout, 'round-trip')).toBe(
      'PASS  round-trip  saved at tick 200, loaded into a fresh copy: equal bytes, and equal states for 400 more ticks',
    );
    expect(r.stdout).toContain('deterministic: 4 checks passed');
    expect(r.code).toBe(0);
    // 4 checks × 600 ticks, reported in order and ending at the total.
    expect(r.progress.at(-1)).toEqual([2400, 2400]);
    const done = r.progress.map(([d]) => d);
    expect(done).toEqual([...done].sort((a, b) => a - b));
  });

  // Each broken game: what each check says. `undefined`: not asserted (a clock's effect depends
  // on when the milliseconds tick over, so only the guard's verdict is certain for it).
  const table: {
    fixture: string;
    guard?: string;
    twins?: string;
    syncTest?: string;
    roundTrip?: string;
  }[] = [
    {
      fixture: 'engine-math',
      guard: 'FAIL  guard       Math.cos called during the step of tick 0 — engine math',
      twins: 'PASS',
      syncTest: 'PASS',
      roundTrip: 'PASS',
    },
    {
      fixture: 'engine-math-wind',
      guard: 'FAIL  guard       Math.sin called during the step of tick 0 — engine math',
      twins: 'PASS',
      syncTest: 'PASS',
      roundTrip: 'PASS',
    },
    {
      fixture: 'clock',
      guard: 'FAIL  guard       Date.now called during the step of tick 0 — a clock',
    },
    {
      fixture: 'math-random',
      guard: 'FAIL  guard       Math.random called during the step of tick 0 — unseeded randomness',
      twins:
        'FAIL  twins       two runs from the same setup with the same inputs differ after tick 1, at x[0]',
      syncTest:
        'FAIL  sync-test   resimulating tick 0 from its loaded state gave another state at tick 1, at x[0]',
    },
    {
      fixture: 'unsaved-field',
      guard: 'PASS',
      twins: 'PASS',
      syncTest:
        'FAIL  sync-test   resimulating tick 0 from its loaded state gave another state at tick 1, at rng[0]',
      roundTrip:
        'FAIL  round-trip  a copy loaded at tick 200 differs from the original after tick 203, at rng[0]',
    },
    {
      fixture: 'set-order',
      guard: 'PASS',
      twins: 'PASS',
      syncTest:
        'FAIL  sync-test   resimulating tick 93 from its loaded state gave another state at tick 94, at vx[3]',
      roundTrip:
        'FAIL  round-trip  a copy loaded at tick 200 differs from the original after tick 201, at vx[3]',
    },
    {
      fixture: 'float32-save',
      guard: 'PASS',
      twins: 'PASS',
      syncTest:
        'FAIL  sync-test   resimulating tick 0 from its loaded state gave another state at tick 1, at x[0]',
      roundTrip:
        'FAIL  round-trip  a copy loaded at tick 200 differs from the original after tick 201, at x[0]',
    },
  ];

  it.each(table)('catches and names $fixture', async (row) => {
    const r = await check([path.join(fixtures, `${row.fixture}.ts`), '--engines', 'node', '-q']);
    expect(r.stderr).toBe('');
    for (const [check, want] of [
      ['guard', row.guard],
      ['twins', row.twins],
      ['sync-test', row.syncTest],
      ['round-trip', row.roundTrip],
    ] as const) {
      // eslint-disable-next-line vitest/no-conditional-expect -- a row asserts only what is certain
      if (want !== undefined) expect(line(r.stdout, check).slice(0, want.length)).toBe(want);
    }
    expect(r.stdout).toMatch(/NOT DETERMINISTIC: \d of 4 checks failed/);
    expect(r.stdout).toContain('not deterministic (exit 4)');
    expect(r.code).toBe(4);
    expect(r.progress).toEqual([]); // -q
  });

  it('shows both values of the first differing field, and the others that differ', async () => {
    const r = await check([path.join(fixtures, 'float32-save.ts'), '--engines', 'node', '-q']);
    expect(r.stdout).toContain(
      'field x[0] (f64, column "x" row 0 of 4, byte 20); 27 of 133 bytes differ',
    );
    expect(r.stdout).toMatch(/first run: 56\.01896561727226 \(0x404c026d7720f766\)/);
    expect(r.stdout).toMatch(/rerun: 56\.0189656014499 \(0x404c026d76fefcf7\)/);
    expect(r.stdout).toMatch(/also differ: x\[1\], x\[2\], x\[3\], y\[0\], .*vx\[0\]/);
  });

  it('names the byte when the game has no state schema, and says how to get the field', async () => {
    const p = await file(
      'no-schema.ts',
      `import game from ${JSON.stringify(path.join(fixtures, 'set-order.ts'))};\n` +
        `const { stateSchema: _, ...rest } = game;\nexport default { ...rest, id: 'no-schema' };\n`,
    );
    const r = await check([p, '--engines', 'node', '-q']);
    expect(line(r.stdout, 'sync-test')).toBe(
      'FAIL  sync-test   resimulating tick 93 from its loaded state gave another state at tick 94, at byte 108',
    );
    expect(r.stdout).toContain('give the game a stateSchema made with defineStateSchema');
    expect(r.code).toBe(4);
  });

  it('--ticks and --seed change the run; --game picks one game of several', async () => {
    const p = await file(
      'two.ts',
      `import a from ${JSON.stringify(path.join(fixtures, 'correct.ts'))};\n` +
        `import b from ${JSON.stringify(path.join(fixtures, 'set-order.ts'))};\nexport default [a, b];\n`,
    );
    const both = await check([p, '--engines', 'node', '--ticks', '120', '-q']);
    expect(both.stdout).toContain('2 games (arena-correct, arena-set-order)');
    expect(both.stdout).toContain('arena-correct v1: 120 ticks, seed 1, 2 players');
    expect(line(both.stdout.split('arena-set-order v1')[1]!, 'sync-test')).toMatch(/^FAIL/);
    expect(both.code).toBe(4);
    const one = await check([
      p,
      '--game',
      'arena-correct',
      '--engines',
      'node',
      '--seed',
      '7',
      '-q',
    ]);
    expect(one.stdout).toContain('1 game (arena-correct)');
    expect(one.stdout).toContain('arena-correct v1: 600 ticks, seed 7, 2 players');
    expect(one.code).toBe(0);
  });

  it('--json: the same verdicts for scripts, and only JSON on stdout', async () => {
    const r = await check([path.join(fixtures, 'set-order.ts'), '--engines', 'node', '--json']);
    const report = JSON.parse(r.stdout) as {
      exitCode: number;
      games: {
        id: string;
        plan: { ticks: number; seed: number; players: number };
        results: { check: string; status: string; tick?: number; field?: string }[];
      }[];
    };
    expect(report.exitCode).toBe(4);
    expect(report.games.map((g) => g.id)).toEqual(['arena-set-order']);
    expect(report.games[0]!.plan).toMatchObject({ ticks: 600, seed: 1, players: 2 });
    expect(
      report.games[0]!.results.map((x) => [x.check, x.status, x.tick ?? null, x.field ?? null]),
    ).toEqual([
      ['guard', 'pass', null, null],
      ['twins', 'pass', null, null],
      ['sync-test', 'fail', 94, 'vx[3]'],
      ['round-trip', 'fail', 201, 'vx[3]'],
    ]);
    expect(r.code).toBe(4);
  });

  it('a game that throws in its step: exit 5, the tick and the error named', async () => {
    const p = await file(
      'throws.ts',
      `import game from ${JSON.stringify(path.join(fixtures, 'correct.ts'))};\n` +
        `export default { ...game, id: 'throws', create(setup) {\n` +
        `  const sim = game.create(setup);\n  const step = sim.step.bind(sim);\n` +
        `  sim.step = (inputs) => { if (sim.tick === 42) throw new RangeError('no tick 42 here'); step(inputs); };\n` +
        `  return sim;\n} };\n`,
    );
    const r = await check([p, '--engines', 'node', '-q']);
    expect(line(r.stdout, 'guard')).toBe(
      'ERROR guard       the game threw in a step at tick 42: RangeError: no tick 42 here',
    );
    expect(r.stdout).toContain('THE GAME THREW in guard, twins, sync-test, round-trip');
    expect(r.code).toBe(5);
  });
});

describe('fixedstep check: modules and command lines it cannot use', () => {
  it('a module that does not exist, throws on import, has no games or never loads: exit 3', async () => {
    const missing = await check([path.join(dir, 'nope.js')]);
    expect(missing.stderr).toMatch(/games module ".*nope\.js": no such file/);
    expect(missing.code).toBe(3);

    const throws = await check([await file('throws.mjs', "throw new Error('boom at import');\n")]);
    expect(throws.stderr).toMatch(/": cannot be imported: boom at import/);
    expect(throws.code).toBe(3);

    const empty = await check([await file('empty.mjs', 'export default [];\n')]);
    expect(empty.stderr).toMatch(/the list of games is empty/);
    expect(empty.code).toBe(3);

    const notGames = await check([await file('not-games.mjs', 'export const x = 1;\n')]);
    expect(notGames.stderr).toMatch(/no default export and no "games" export/);
    expect(notGames.code).toBe(3);

    const stuck = await file('stuck.mjs', 'await new Promise(() => {});\nexport default [];\n');
    const hung = await check([stuck], { FIXEDSTEP_GAMES_IMPORT_TIMEOUT_MS: '300' });
    expect(hung.stderr).toContain(`games module "${stuck}": still loading after 0.3 s`);
    expect(hung.code).toBe(3);

    const other = await check([path.join(fixtures, 'correct.ts'), '--game', 'pong']);
    expect(other.stderr).toContain('has no game "pong"; it has arena-correct');
    expect(other.code).toBe(3);
  });

  it('usage errors: exit 2 with the help', async () => {
    const none = await check([]);
    expect(none.stderr).toContain('check needs a games module');
    expect(none.stderr).toContain('fixedstep check — is your game deterministic?');
    expect(none.code).toBe(2);
    const ticks = await check(['game.js', '--ticks', '0']);
    expect(ticks.stderr).toContain('--ticks must be an integer from 1 to 1000000, got "0"');
    expect(ticks.code).toBe(2);
    const engines = await check(['game.js', '--engines', 'node,opera']);
    expect(engines.stderr).toContain('--engines: unknown engine "opera"');
    expect(engines.code).toBe(2);
    const help = await check(['--help']);
    expect(help.stdout).toContain('Exit codes: 0 every check passed');
    expect(help.code).toBe(0);
  });

  it('a browser asked for by name that is not installed: skipped, said, exit 1', async () => {
    const r = await check([path.join(fixtures, 'correct.ts'), '--engines', 'webkit', '-q'], {
      PATH: '/nonexistent',
      MINIBROWSER_PATH: '/nonexistent/MiniBrowser',
    });
    // Xvfb is looked up on PATH, so with an empty PATH WebKitGTK cannot run here.
    expect(line(r.stdout, 'webkit')).toMatch(/^SKIP {2}webkit +asked for, but not installed: /);
    expect(r.code).toBe(1);
  });
});
