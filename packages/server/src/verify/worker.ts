/**
 * A verification worker thread: imports the server's games modules (the same URLs the main thread
 * loaded) and re-simulates the submissions it is sent, one at a time. Started by
 * {@link VerifierPool}; not meant to be imported.
 * @module
 */
import { parentPort, workerData } from 'node:worker_threads';
import type { AnyGameDefinition, ReplayLimits } from 'fixedstep';
import { importGames } from '../games/load.js';
import { precheckPlain, resimulate } from './check.js';
import { lowerThreadPriority } from '../worker-script.js';

interface Data {
  modules: string[];
}
interface Job {
  id: number;
  kind: 'precheck' | 'verify';
  bytes: Uint8Array;
  claimedScore: number;
  limits: Partial<ReplayLimits>;
}

lowerThreadPriority();
const port = parentPort;
if (port === null) throw new Error('verify/worker.js runs as a worker thread of VerifierPool');
const { modules } = workerData as Data;

const byId = new Map<string, AnyGameDefinition>();
try {
  for (const url of modules) for (const g of await importGames(url)) byId.set(g.id, g);
  port.postMessage({ ready: true });
} catch (error) {
  port.postMessage({ ready: false, error: error instanceof Error ? error.message : String(error) });
}
const games = [...byId.values()];

port.on('message', (job: Job) => {
  let result;
  try {
    result =
      job.kind === 'precheck'
        ? precheckPlain(job.bytes, job.claimedScore, games, job.limits)
        : resimulate(job.bytes, job.claimedScore, games, job.limits);
  } catch (error) {
    result = { ok: false, status: 500, code: 'VERIFIER_ERROR', message: String(error) };
  }
  port.postMessage({ id: job.id, result });
});
