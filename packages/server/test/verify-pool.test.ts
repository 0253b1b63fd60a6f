/**
 * Verification off the event loop (issue: "20 small forged replays froze GET / for seconds"):
 * submissions are re-simulated in worker threads with a bounded queue. The `gate` game's
 * verification waits in its worker until this test creates a file, so the test holds a
 * verification open as long as it likes — no timing involved: were verification on the event
 * loop, the server could not answer anything while the gate is shut, and the test would hang.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import type { AnyGameDefinition } from 'fixedstep';
import type { FixedstepServer } from '../src/app.js';
import { gaugeOf, recordRun, startGatedServer, type GatedServer } from './verify-runs.js';

let gated: GatedServer;
let server: FixedstepServer;
let games: readonly AnyGameDefinition[];
beforeAll(async () => {
  gated = await startGatedServer('verify');
  ({ server, games } = gated);
}, 120_000);
afterAll(() => gated.close());

const run = (id: string, seed: number) => recordRun(games, id, seed);

const url = (p: string) => `http://127.0.0.1:${server.port}${p}`;
const submit = ({ bytes, score }: { bytes: Uint8Array; score: number }) =>
  fetch(url(`/api/highscores?score=${score}`), { method: 'POST', body: Buffer.from(bytes) });

const gauge = (name: string) => gaugeOf(server.port, name);

describe('verification in worker threads', () => {
  it('answers GET / and the API while a verification runs, queues one more, refuses the next with 503 and Retry-After', async () => {
    const first = submit(run('gate', 1));
    await expect.poll(() => gauge('fixedstep_verifications_running'), { timeout: 30_000 }).toBe(1);

    // The worker is stuck at the gate; the event loop is not.
    expect((await fetch(url('/'))).status).toBe(200);
    expect((await fetch(url('/api/highscores?game=gate'))).status).toBe(200);

    const second = submit(run('gate', 2));
    await expect.poll(() => gauge('fixedstep_verification_queue_length')).toBe(1);
    const refused = await submit(run('gate', 3));
    expect(refused.status).toBe(503);
    expect(Number(refused.headers.get('retry-after'))).toBeGreaterThan(0);
    expect(await refused.json()).toMatchObject({ code: 'BUSY' });

    gated.openGate();
    expect((await first).status).toBe(201);
    expect((await second).status).toBe(201);
    const table = (await (await fetch(url('/api/highscores?game=gate'))).json()) as {
      entries: unknown[];
    };
    expect(table.entries).toHaveLength(2);
    // The refused run was never looked at: sent again now, it is accepted.
    expect((await submit(run('gate', 3))).status).toBe(201);
  });

  it('pre-checks in the worker too: junk waits for a free worker (the event loop answers meanwhile), then is refused', async () => {
    gated.closeGate();
    const held = submit(run('gate', 7));
    await expect.poll(() => gauge('fixedstep_verifications_running'), { timeout: 30_000 }).toBe(1);
    let junkAnswered = false;
    const junk = fetch(url('/api/highscores?score=1'), {
      method: 'POST',
      body: Buffer.from(new Uint8Array(64)),
    }).then((r) => {
      junkAnswered = true;
      return r;
    });
    // Its pre-check waits for the one worker, stuck at the gate; the event loop does not.
    await expect.poll(() => gauge('fixedstep_verification_queue_length')).toBe(1);
    expect((await fetch(url('/healthz'))).status).toBe(200);
    expect(junkAnswered).toBe(false);
    gated.openGate();
    const refused = await junk;
    expect(refused.status).toBe(422);
    expect((await held).status).toBe(201);
  });

  it('a verifier thread that dies fails only its submission (500), and a new one takes the next', async () => {
    const crashed = await submit(run('crash', 4));
    expect(crashed.status).toBe(500);
    expect(await crashed.json()).toMatchObject({ code: 'VERIFIER_CRASHED' });
    const honest = await submit(run('counter', 5));
    expect(honest.status).toBe(201);
    // A crash is not a refusal of the run: once the verifier can finish it, the same run is
    // judged on its own (here: it reproduces, so it is accepted).
    expect((await submit(run('counter', 6))).status).toBe(201);
  });
});
