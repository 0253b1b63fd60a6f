import { availableParallelism } from 'node:os';
import { Worker } from 'node:worker_threads';
import type { AnyGameDefinition, ReplayLimits } from 'fixedstep';
import {
  SubmissionError,
  precheckPlain,
  resimulate,
  submissionLimits,
  type PrecheckResult,
  type Resimulation,
} from './check.js';
import { workerScript } from '../worker-script.js';

/** Options of {@link VerifierPool}. */
export interface VerifierPoolOptions {
  /**
   * Games modules (URLs) every worker imports — the same ones the server loaded, so the workers run
   * the same game code. Required when `workers` > 0.
   */
  modules?: readonly string[];
  /** The games, for inline verification (`workers: 0`). */
  games?: readonly AnyGameDefinition[];
  /**
   * Worker threads. Default: the cores minus one (at least 1), at most 8. 0 verifies inline on the
   * calling thread (it then blocks the event loop while it runs: for tests and benchmarks).
   */
  workers?: number;
  /**
   * Submissions that may wait for a worker. Default 32. One more is refused at once with a
   * {@link SubmissionError} 503 `BUSY` and a `Retry-After`, instead of growing a backlog.
   */
  maxQueue?: number;
  /** Replay limits of a submission. Default {@link submissionLimits}. */
  limits?: Partial<ReplayLimits>;
  /** Called when a verification ends: seconds it took (queue wait included) and its outcome code. */
  onDone?: (seconds: number, outcome: string) => void;
}

interface Job {
  id: number;
  /** `precheck`: only the cheap checks and the run id; `verify`: the re-simulation. */
  kind: 'precheck' | 'verify';
  bytes: Uint8Array;
  claimedScore: number;
  started: number;
  resolve: (r: Resimulation | PrecheckResult) => void;
  reject: (e: unknown) => void;
}

interface Slot {
  worker: Worker;
  /** starting: importing the games; idle/busy: ready; dead: exited. */
  state: 'starting' | 'idle' | 'busy' | 'dead';
  job: Job | undefined;
  ready: Promise<void>;
}

/** Workers that fail to start this many times in a row make the pool give up (a broken games module). */
const MAX_START_FAILURES = 3;

/**
 * Re-simulates submissions off the event loop: a fixed set of worker threads and a bounded queue.
 * A worker that dies (an exception outside the verifier, out of memory) fails its job with 500 and is
 * replaced. {@link drain} waits for every queued and running job; {@link close} then stops the workers.
 *
 * Hand-written rather than a pool library because what is needed is small and specific: a hard
 * queue bound that refuses at once (503), jobs that transfer their bytes, and one worker script.
 */
export class VerifierPool {
  private readonly slots: Slot[] = [];
  private readonly queue: Job[] = [];
  private readonly maxQueue: number;
  private readonly limits: Partial<ReplayLimits>;
  private readonly modules: readonly string[];
  private readonly games: readonly AnyGameDefinition[];
  private nextId = 1;
  private closed = false;
  private startFailures = 0;
  private broken: string | undefined;
  private idleWaiters: (() => void)[] = [];
  /** Worker threads (0: inline). */
  readonly workers: number;

  constructor(private readonly options: VerifierPoolOptions = {}) {
    const workers = options.workers ?? Math.min(8, Math.max(1, availableParallelism() - 1));
    if (!Number.isInteger(workers) || workers < 0 || workers > 256) {
      throw new RangeError(
        `VerifierPool: workers must be an integer from 0 to 256, got ${String(workers)}`,
      );
    }
    const maxQueue = options.maxQueue ?? 32;
    if (!Number.isInteger(maxQueue) || maxQueue < 0) {
      throw new RangeError(
        `VerifierPool: maxQueue must be an integer ≥ 0, got ${String(maxQueue)}`,
      );
    }
    this.workers = workers;
    this.maxQueue = maxQueue;
    this.limits = options.limits ?? submissionLimits();
    this.modules = options.modules ?? [];
    this.games = options.games ?? [];
    if (workers > 0 && this.modules.length === 0) {
      throw new RangeError(
        'VerifierPool: workers need the games modules (modules: [url, …]) to import',
      );
    }
    for (let i = 0; i < workers; i++) this.slots.push(this.spawn());
  }

  /** Submissions waiting for a worker. */
  get queued(): number {
    return this.queue.length;
  }

  /** Submissions being re-simulated right now. */
  get running(): number {
    return this.slots.filter((s) => s.state === 'busy').length;
  }

  /** Resolves once every worker has imported the games (rejects naming the module that failed). */
  async ready(): Promise<void> {
    await Promise.all(this.slots.map((s) => s.ready));
  }

  /**
   * Re-simulates `bytes` and checks `claimedScore` (see {@link resimulate}). Throws a
   * {@link SubmissionError} 503 `BUSY` at once when the queue is full, 503 `DRAINING` after
   * {@link drain} or {@link close} began. The bytes are copied to the worker.
   */
  verify(bytes: Uint8Array, claimedScore: number): Promise<Resimulation> {
    return this.enqueue('verify', bytes, claimedScore) as Promise<Resimulation>;
  }

  /**
   * The pre-check of a submission (parse it, a known game, within the limits, its run id — see
   * `precheckSubmission`) in a worker too: its cost follows the ticks the file declares, not its
   * bytes (a small file can declare an hour of play), so it stays off the event loop. Queued and
   * refused like {@link verify}.
   */
  precheck(bytes: Uint8Array, claimedScore: number): Promise<PrecheckResult> {
    return this.enqueue('precheck', bytes, claimedScore) as Promise<PrecheckResult>;
  }

  private enqueue(
    kind: Job['kind'],
    bytes: Uint8Array,
    claimedScore: number,
  ): Promise<Resimulation | PrecheckResult> {
    if (this.closed) {
      return Promise.reject(new SubmissionError(503, 'DRAINING', 'the server is shutting down', 5));
    }
    if (this.workers === 0) {
      if (kind === 'precheck')
        return Promise.resolve(precheckPlain(bytes, claimedScore, this.games, this.limits));
      const started = performance.now();
      const result = resimulate(bytes, claimedScore, this.games, this.limits);
      this.options.onDone?.((performance.now() - started) / 1000, result.ok ? 'ok' : result.code);
      return Promise.resolve(result);
    }
    if (this.broken !== undefined) {
      return Promise.resolve({
        ok: false,
        status: 500,
        code: 'VERIFIER_UNAVAILABLE',
        message: this.broken,
      });
    }
    const idle = this.slots.find((s) => s.state === 'idle');
    if (idle === undefined && this.queue.length >= this.maxQueue) {
      return Promise.reject(
        new SubmissionError(
          503,
          'BUSY',
          `the verification queue is full (${this.maxQueue} waiting); try again shortly`,
          2,
        ),
      );
    }
    return new Promise<Resimulation | PrecheckResult>((resolve, reject) => {
      const job: Job = {
        id: this.nextId++,
        kind,
        bytes,
        claimedScore,
        started: performance.now(),
        resolve,
        reject,
      };
      if (idle) this.run(idle, job);
      else if (kind === 'verify') this.queue.push(job);
      else {
        // Pre-checks go before the re-simulations waiting: they are short, and an honest
        // submission should not queue twice behind the same backlog.
        const firstVerify = this.queue.findIndex((j) => j.kind === 'verify');
        this.queue.splice(firstVerify < 0 ? this.queue.length : firstVerify, 0, job);
      }
    });
  }

  /** Refuses new work and resolves once every queued and running verification has finished. */
  drain(): Promise<void> {
    this.closed = true;
    if (
      (this.queue.length === 0 && this.running === 0) ||
      this.slots.every((s) => s.state === 'dead')
    ) {
      return Promise.resolve();
    }
    return new Promise((resolve) => this.idleWaiters.push(resolve));
  }

  /** {@link drain}, then stop the workers. */
  async close(): Promise<void> {
    await this.drain();
    await Promise.all(this.slots.map((s) => s.worker.terminate()));
    this.slots.length = 0;
  }

  private spawn(): Slot {
    const { url, execArgv } = workerScript('./worker.js', import.meta.url);
    const worker = new Worker(url, {
      workerData: { modules: [...this.modules] },
      ...(execArgv ? { execArgv } : {}),
    });
    worker.unref();
    let settle: { resolve: () => void; reject: (e: Error) => void } | undefined;
    const slot: Slot = {
      worker,
      state: 'starting',
      job: undefined,
      ready: new Promise<void>((resolve, reject) => (settle = { resolve, reject })),
    };
    slot.ready.catch(() => undefined); // observed through ready()
    let failure: string | undefined;
    worker.on(
      'message',
      (m: {
        ready?: boolean;
        error?: string;
        id?: number;
        result?: Resimulation | PrecheckResult;
      }) => {
        if (m.ready !== undefined) {
          if (m.ready) {
            this.startFailures = 0;
            slot.state = 'idle';
            settle?.resolve();
            this.next(slot);
          } else {
            failure = m.error ?? 'a verification worker could not load the games';
            settle?.reject(new Error(failure));
            void worker.terminate();
          }
          return;
        }
        const job = slot.job;
        if (job === undefined || m.id !== job.id || m.result === undefined) return;
        slot.job = undefined;
        slot.state = 'idle';
        this.finish(job, m.result);
        this.next(slot);
      },
    );
    worker.on('error', (error) => {
      failure ??= error.message;
      settle?.reject(error);
    });
    worker.on('exit', () => {
      const started = slot.state !== 'starting';
      slot.state = 'dead';
      const job = slot.job;
      slot.job = undefined;
      if (job) {
        this.finish(job, {
          ok: false,
          status: 500,
          code: 'VERIFIER_CRASHED',
          message: `the verifier failed: ${failure ?? 'its thread exited'}`,
        });
      }
      const i = this.slots.indexOf(slot);
      if (i < 0 || this.closed) {
        this.wakeIdle();
        return;
      }
      if (!started && ++this.startFailures >= MAX_START_FAILURES) {
        // The games cannot be loaded: answer every waiting submission instead of retrying forever.
        this.broken = `the verification workers cannot start: ${failure ?? 'unknown error'}`;
        for (const waiting of this.queue.splice(0)) {
          this.finish(waiting, {
            ok: false,
            status: 500,
            code: 'VERIFIER_UNAVAILABLE',
            message: this.broken,
          });
        }
        this.wakeIdle();
        return;
      }
      this.slots[i] = this.spawn(); // replace it; the queue goes on when it is ready
    });
    return slot;
  }

  private run(slot: Slot, job: Job): void {
    slot.job = job;
    slot.state = 'busy';
    const copy = job.bytes.slice(); // the caller keeps its bytes; the copy is transferred
    slot.worker.postMessage(
      {
        id: job.id,
        kind: job.kind,
        bytes: copy,
        claimedScore: job.claimedScore,
        limits: this.limits,
      },
      copy.buffer instanceof ArrayBuffer ? [copy.buffer] : [],
    );
  }

  private next(slot: Slot): void {
    const job = slot.state === 'idle' ? this.queue.shift() : undefined;
    if (job) this.run(slot, job);
    else this.wakeIdle();
  }

  private wakeIdle(): void {
    if (this.running === 0 && this.queue.length === 0)
      for (const w of this.idleWaiters.splice(0)) w();
  }

  private finish(job: Job, result: Resimulation | PrecheckResult): void {
    if (job.kind === 'verify')
      this.options.onDone?.(
        (performance.now() - job.started) / 1000,
        result.ok ? 'ok' : result.code,
      );
    job.resolve(result);
  }
}
