/**
 * One engine in a process of its own (peer-program.ts), driven over a line protocol: commands in,
 * one JSON line out per command. Each engine then runs in a fresh V8 isolate: no shared heap, no
 * JIT state and no process-wide V8 state from the others. (Rapier's WASM memory growth detaches an
 * ArrayBuffer, which turns off a V8 fast path for every typed-array access in the process:
 * in-process, fixedstep's world ran ~25 % slower next to Rapier.)
 *
 * Commands: `settle K` (K steps), `time K` (K steps, timed with hrtime), `sanity`, `gc`, `quit`.
 */
import { spawn, spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import { LineProcess } from '../lib/line-process.js';
import type { Sanity } from './checks.js';
import type { Engine } from './registry.js';

/** Path of the peer program. */
export const PEER_PROGRAM = fileURLToPath(new URL('./peer-program.ts', import.meta.url));

/** What a peer program says when it is ready. */
export interface PeerInfo {
  readonly name: string;
  readonly settings: string;
  readonly count: number;
}

/** A reply line of the peer program. */
export type PeerReply =
  | { readonly ok: true; readonly info?: PeerInfo; readonly ns?: number; readonly sanity?: Sanity }
  | { readonly ok: false; readonly error: string };

/** Parses one reply line; throws on anything that is not one. */
export function parsePeerReply(line: string): PeerReply {
  let value: unknown;
  try {
    value = JSON.parse(line);
  } catch {
    throw new Error(`peer program: unexpected output ${JSON.stringify(line)}`);
  }
  if (
    typeof value !== 'object' ||
    value === null ||
    typeof (value as { ok?: unknown }).ok !== 'boolean'
  ) {
    throw new Error(`peer program: unexpected output ${JSON.stringify(line)}`);
  }
  return value as PeerReply;
}

/** Node's arguments for the peer program: the bench's flags, then engine, N and seed. */
export function peerProgramArgs(engine: Engine, n: number, seed: number, tsx: string): string[] {
  return [
    '--conditions=source',
    '--expose-gc',
    '--import',
    tsx,
    PEER_PROGRAM,
    engine,
    String(n),
    String(seed),
  ];
}

export class PeerProcess {
  /** Set once ready. */
  info: PeerInfo = { name: '?', settings: '', count: 0 };

  private constructor(private readonly proc: LineProcess<PeerReply & { ok: true }>) {}

  /** Starts one engine on `circlesInBoxScene(n, seed)` and waits until it is built. */
  static async start(engine: Engine, n: number, seed: number, tsx: string): Promise<PeerProcess> {
    const child = spawn(process.execPath, peerProgramArgs(engine, n, seed, tsx), { stdio: 'pipe' });
    const p = new PeerProcess(
      new LineProcess(child, 'peer program', (line) => {
        const reply = parsePeerReply(line);
        if (!reply.ok) throw new Error(`peer program: ${reply.error}`);
        return reply;
      }),
    );
    const ready = await p.proc.next();
    if (ready.info === undefined) throw new Error('peer program: no info when ready');
    p.info = ready.info;
    return p;
  }

  private command(text: string): Promise<PeerReply & { ok: true }> {
    return this.proc.command(text);
  }

  /** Runs `steps` steps, untimed. */
  async settle(steps: number): Promise<void> {
    await this.command(`settle ${steps}`);
  }

  /** Runs `steps` steps; resolves to their duration in ns, measured in the program. */
  async time(steps: number): Promise<number> {
    const reply = await this.command(`time ${steps}`);
    if (reply.ns === undefined) throw new Error('peer program: no time');
    return reply.ns;
  }

  /** The world's {@link Sanity} now (this steps it once). */
  async sanity(): Promise<Sanity> {
    const reply = await this.command('sanity');
    if (reply.sanity === undefined) throw new Error('peer program: no sanity');
    return reply.sanity;
  }

  /** A full gc in the program. */
  async gc(): Promise<void> {
    await this.command('gc');
  }

  /** Pins the program's main thread to `cpu` (Linux, taskset); false if that failed. */
  pin(cpu: number): boolean {
    const pid = this.proc.child.pid;
    if (pid === undefined) return false;
    const r = spawnSync('taskset', ['-p', '-c', String(cpu), String(pid)]);
    return r.error === undefined && r.status === 0;
  }

  /** Ends the program (its world is disposable) and waits for it to exit. */
  async close(): Promise<void> {
    if (this.proc.running) this.proc.child.kill();
    await this.proc.exited;
  }
}
