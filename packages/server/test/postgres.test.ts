import { spawn, type ChildProcess } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import pg from 'pg';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { PgCluster, pgBin } from './pg-cluster.js';
import { recordRunner } from './replay-fixtures.js';

/**
 * Two server processes sharing one PostgreSQL server (Debian's, started here in a scratch folder
 * on a free port, as the `postgres` user when we are root: PostgreSQL refuses to run as root).
 * Concurrent submissions go to both — each run to both at once, and a renamed copy too — and one
 * process is killed with SIGKILL mid-way. Afterwards every acknowledged score (every 201) is in the
 * table under the name it was acknowledged with, and no run was accepted twice.
 */
const skip =
  pgBin === undefined
    ? (process.env.FIXEDSTEP_PG_SKIP ?? 'PostgreSQL is not installed')
    : undefined;
if (skip !== undefined) console.log(`skipped: two server processes on one PostgreSQL: ${skip}`);

let cluster: PgCluster | undefined;
let url: string;
const children: ChildProcess[] = [];

function startServerProcess(): Promise<{ child: ChildProcess; port: number }> {
  const script = fileURLToPath(new URL('./fixtures/pg-server.ts', import.meta.url));
  const child = spawn(process.execPath, ['--conditions=source', '--import', 'tsx', script], {
    env: { ...process.env, DATABASE_URL: url },
    stdio: ['ignore', 'pipe', 'inherit'],
  });
  children.push(child);
  return new Promise((resolve, reject) => {
    let out = '';
    child.stdout.on('data', (d: Buffer) => {
      out += d.toString();
      const m = /^(\d+)\n/.exec(out);
      if (m) resolve({ child, port: Number(m[1]) });
    });
    child.once('exit', (code) => {
      reject(new Error(`the server process exited (${String(code)}) before listening`));
    });
  });
}

beforeAll(async () => {
  if (skip !== undefined) return;
  cluster = await PgCluster.create(pgBin!);
  cluster.start();
  url = cluster.url;
}, 120_000);

afterAll(() => {
  for (const c of children) if (c.exitCode === null && c.signalCode === null) c.kill('SIGKILL');
  cluster?.remove();
});

interface Answer {
  status: number;
  body: { entry?: { replayId: string; name: string }; repeated?: boolean; code?: string };
}

describe.skipIf(skip !== undefined)('two server processes sharing one PostgreSQL', () => {
  it('lose no acknowledged score and accept no run twice, through concurrent submissions and kill -9', async () => {
    const [a, b] = await Promise.all([startServerProcess(), startServerProcess()]);
    const runs = Array.from({ length: 30 }, (_, i) => ({
      honest: recordRunner(300 + 11 * i, {}, `p${i}`),
      renamed: recordRunner(300 + 11 * i, {}, `q${i}`),
    }));
    let answered = 0;
    let killed = false;
    const post = async (
      port: number,
      bytes: Uint8Array,
      score: number,
    ): Promise<Answer | undefined> => {
      try {
        const res = await fetch(`http://127.0.0.1:${port}/api/highscores?score=${score}`, {
          method: 'POST',
          body: Buffer.from(bytes),
        });
        const answer = { status: res.status, body: (await res.json()) as Answer['body'] };
        if (++answered >= 25 && !killed) {
          killed = true;
          b.child.kill('SIGKILL'); // mid-way: B has more submissions in flight
        }
        return answer;
      } catch {
        return undefined; // the connection died with its process: not acknowledged
      }
    };
    const answers = await Promise.all(
      runs.flatMap(({ honest, renamed }, i) => {
        const score = honest.game.hud().score!;
        const [first, second] = i % 2 === 0 ? [a, b] : [b, a];
        return [
          post(first.port, honest.bytes, score),
          post(second.port, honest.bytes, score),
          post(second.port, renamed.bytes, score),
        ];
      }),
    );
    expect(killed).toBe(true);
    const acknowledged = answers.filter((x): x is Answer => x?.status === 201);
    expect(acknowledged.length).toBeGreaterThanOrEqual(15);

    const client = new pg.Client({ connectionString: url });
    await client.connect();
    const rows = (
      await client.query<{ run_id: string; name: string }>('select run_id, name from highscores')
    ).rows;
    const replays = (await client.query<{ n: string }>('select count(*) as n from replays'))
      .rows[0]!.n;
    await client.end();
    const table = new Map(rows.map((r) => [r.run_id, r.name]));
    // Every acknowledged score is there, under the name it was acknowledged with.
    for (const ack of acknowledged)
      expect(table.get(ack.body.entry!.replayId)).toBe(ack.body.entry!.name);
    // No run twice: one row per run, never both the honest and the renamed copy, a replay per row.
    expect(table.size).toBe(rows.length);
    expect(rows.length).toBeLessThanOrEqual(runs.length);
    expect(Number(replays)).toBe(rows.length);
    const added = acknowledged
      .filter((x) => x.body.repeated !== true)
      .map((x) => x.body.entry!.replayId);
    expect(new Set(added).size).toBe(added.length);
    // A refused copy was refused as another's run.
    expect(answers.filter((x) => x?.status === 409).map((x) => x!.body.code)).not.toContain(
      undefined,
    );
    expect(new Set(answers.filter((x) => x?.status === 409).map((x) => x!.body.code))).toEqual(
      new Set(['RUN_TAKEN']),
    );
    // The survivor still answers, and a run B took before it died is known to A.
    const survivor = await fetch(`http://127.0.0.1:${a.port}/readyz`);
    expect(survivor.status).toBe(200);
  }, 240_000);
});
