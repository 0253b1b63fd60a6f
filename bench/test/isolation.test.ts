/**
 * The runner runs every suite in a process of its own (a suite's allocation figures depended on
 * which suites ran before it, in one process), with the same output and JSON as one process would
 * give. Runs `bench/run.ts` on fixture suites.
 */
import { execFile } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { afterAll, describe, expect, it } from 'vitest';
import type { NoteSection, SuiteReport } from '../lib/report.js';

const bench = fileURLToPath(new URL('..', import.meta.url));
const fixtures = join(bench, 'test', 'fixtures', 'suites');
const scratch = mkdtempSync(join(tmpdir(), 'bench-isolation-'));
afterAll(() => {
  rmSync(scratch, { recursive: true, force: true });
});

interface Run {
  code: number;
  stdout: string;
  stderr: string;
}

/** `npm run bench -- …args` on the fixture suites (the same Node options as the npm script). */
function runBench(args: string[]): Promise<Run> {
  return new Promise((resolve) => {
    execFile(
      process.execPath,
      ['--conditions=source', '--expose-gc', '--import', 'tsx', join(bench, 'run.ts'), ...args],
      { env: { ...process.env, FIXEDSTEP_BENCH_SUITES_DIR: fixtures }, cwd: bench },
      (error, stdout, stderr) => {
        resolve({ code: error ? Number(error.code ?? 1) : 0, stdout, stderr });
      },
    );
  });
}

function notes(report: SuiteReport): string[] {
  return report.sections.filter((s): s is NoteSection => s.kind === 'note').map((s) => s.text);
}

describe('the bench runner', { timeout: 60_000 }, () => {
  it('runs each suite in a process of its own and gathers their reports', async () => {
    const json = join(scratch, 'two.json');
    const run = await runBench(['first', 'second', '--json', json]);
    expect(run.stderr).toBe('');
    expect(run.code).toBe(0);
    const result = JSON.parse(readFileSync(json, 'utf8')) as {
      gc: boolean;
      suites: SuiteReport[];
    };
    expect(result.gc).toBe(true);
    expect(result.suites.map((s) => [s.name, s.ok])).toEqual([
      ['first', true],
      ['second', true],
    ]);
    const [first, second] = result.suites.map((s) => notes(s)[0]!);
    // The second suite's process has not seen the first suite run, and is another process.
    expect(second).toMatch(/ran here before: none$/);
    const pid = (note: string) => /^pid (\d+);/.exec(note)?.[1];
    expect(pid(first!)).toBeDefined();
    expect(pid(second!)).not.toBe(pid(first!));
    // The output reads as one run: headers, sections, the summary line.
    expect(run.stdout).toMatch(/== first: fixture: marks its process\n\n {2}pid \d+/);
    expect(run.stdout).toMatch(/== second:[^\n]*\n\n {2}pid \d+[^\n]*\n\nnumbers\n/);
    expect(run.stdout).toMatch(/2 suite\(s\) in [\d.]+ s\n/);
    // Its process imported its own suite's file, not the others' (nor what they import).
    expect(notes(result.suites[1]!)[1]).toBe('suite files imported here: second');
  });

  it('reports a suite whose process dies as failed, and runs the others', async () => {
    const json = join(scratch, 'crash.json');
    const run = await runBench(['crash', 'second', '--json', json]);
    expect(run.code).toBe(1);
    expect(run.stdout).toMatch(/about to exit/);
    expect(run.stderr).toMatch(
      /suite crash failed: its process exited \(code 3\) without a report/,
    );
    const result = JSON.parse(readFileSync(json, 'utf8')) as { suites: SuiteReport[] };
    expect(result.suites.map((s) => [s.name, s.ok])).toEqual([
      ['crash', false],
      ['second', true],
    ]);
    expect(run.stdout).toMatch(/FAILED: crash/);
  });

  it('ends a suite that still holds its process after its report, naming what held it', async () => {
    const json = join(scratch, 'linger.json');
    const run = await runBench(['linger', 'second', '--json', json]);
    expect(run.code).toBe(0);
    expect(run.stderr).toMatch(
      /suite linger still alive 3 s after its report \(holding: [^)]*TCPServerWrap × 1[^)]*Timeout × 1[^)]*\); ending it/,
    );
    const result = JSON.parse(readFileSync(json, 'utf8')) as { suites: SuiteReport[] };
    expect(result.suites.map((s) => [s.name, s.ok])).toEqual([
      ['linger', true],
      ['second', true],
    ]);
    // Its process is gone: the run did not end before it did.
    const pid = Number(/^pid (\d+);/.exec(notes(result.suites[0]!)[0]!)?.[1]);
    expect(pid).toBeGreaterThan(0);
    expect(() => process.kill(pid, 0)).toThrow(/ESRCH/);
  });
});
