/**
 * The C side of the `physics-springs` suite: encode a 2D spring scene for `springs.c`, compile it
 * with gcc at bench time, and drive the resulting program over a line protocol (see the comment
 * at the top of springs.c). The encoding and the parsing are pure; everything else does I/O.
 */
import { spawn, spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import { Fnv1a64, type SpringModel } from 'fixedstep';
import { LineProcess } from '../lib/line-process.js';

/** Path of the C source. */
export const SPRINGS_C = fileURLToPath(new URL('./springs.c', import.meta.url));
/** Path of the JavaScript program (springs-js.ts), which speaks the same protocol. */
export const SPRINGS_JS = fileURLToPath(new URL('./springs-js.ts', import.meta.url));

/** The contestants springs-js.ts hosts, by index. */
export const JS_CONTESTANTS: readonly string[] = [
  'fixedstep SpringSystem.step',
  'fixedstep Integrator.step, plain arrays',
  'hand-written JS (same loop as the C)',
];

/** "FSSP" read as a little-endian u32. */
export const SCENE_MAGIC = 0x50535346;
export const SCENE_VERSION = 1;

/** The methods springs.c implements, by their id in the scene file. */
export const C_METHODS = ['semi-implicit-euler', 'velocity-verlet'] as const;
export type CMethod = (typeof C_METHODS)[number];

/** A 2D spring scene as springs.c reads it. */
export interface SpringSceneData {
  readonly method: CMethod;
  /** The fixed step, s. */
  readonly dt: number;
  /** Gravity (x, y), m/s². */
  readonly gravity: readonly [number, number];
  /** Start positions, m, 2 per particle. */
  readonly x: Float64Array;
  /** Start velocities, m/s, 2 per particle. */
  readonly v: Float64Array;
  /** 1/mass per particle, 1/kg (0 = fixed). */
  readonly inverseMass: Float64Array;
  readonly springA: Int32Array;
  readonly springB: Int32Array;
  readonly restLength: Float64Array;
  readonly stiffness: Float64Array;
  readonly damping: Float64Array;
}

const HEADER_BYTES = 6 * 4 + 3 * 8;

/** The scene of a library {@link SpringModel} (2D) started from its start state. */
export function sceneOfModel(model: SpringModel, method: CMethod, dt: number): SpringSceneData {
  if (model.dim !== 2) throw new RangeError(`springs.c is 2D only, the model is ${model.dim}D`);
  return {
    method,
    dt,
    gravity: [model.gravity[0]!, model.gravity[1]!],
    x: model.startPosition,
    v: model.startVelocity,
    inverseMass: model.inverseMass,
    springA: model.springA,
    springB: model.springB,
    restLength: model.restLength,
    stiffness: model.stiffness,
    damping: model.damping,
  };
}

/** The scene file springs.c reads (layout in its header comment). */
export function encodeSpringScene(s: SpringSceneData): Uint8Array {
  const n = s.inverseMass.length;
  const m = s.springA.length;
  if (s.x.length !== 2 * n || s.v.length !== 2 * n) {
    throw new RangeError(`encodeSpringScene: x and v need ${2 * n} numbers`);
  }
  for (const arr of [s.springB, s.restLength, s.stiffness, s.damping]) {
    if (arr.length !== m) throw new RangeError(`encodeSpringScene: every spring array needs ${m}`);
  }
  const bytes = new Uint8Array(HEADER_BYTES + 8 * 5 * n + m * (4 + 4 + 8 + 8 + 8));
  const view = new DataView(bytes.buffer);
  let o = 0;
  const u32 = (value: number) => {
    view.setUint32(o, value, true);
    o += 4;
  };
  const f64s = (values: ArrayLike<number>) => {
    for (let i = 0; i < values.length; i++, o += 8) view.setFloat64(o, values[i]!, true);
  };
  const i32s = (values: ArrayLike<number>) => {
    for (let i = 0; i < values.length; i++, o += 4) view.setInt32(o, values[i]!, true);
  };
  u32(SCENE_MAGIC);
  u32(SCENE_VERSION);
  u32(C_METHODS.indexOf(s.method));
  u32(2);
  u32(n);
  u32(m);
  f64s([s.dt, s.gravity[0], s.gravity[1]]);
  f64s(s.x);
  f64s(s.v);
  f64s(s.inverseMass);
  i32s(s.springA);
  i32s(s.springB);
  f64s(s.restLength);
  f64s(s.stiffness);
  f64s(s.damping);
  if (o !== bytes.length) throw new Error(`encodeSpringScene: wrote ${o} of ${bytes.length} bytes`);
  return bytes;
}

/** Reads back {@link encodeSpringScene}'s bytes (for tests). Throws on a malformed file. */
export function decodeSpringScene(bytes: Uint8Array): SpringSceneData {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let o = 0;
  const u32 = () => {
    const value = view.getUint32(o, true);
    o += 4;
    return value;
  };
  const f64s = (count: number) => {
    const out = new Float64Array(count);
    for (let i = 0; i < count; i++, o += 8) out[i] = view.getFloat64(o, true);
    return out;
  };
  const i32s = (count: number) => {
    const out = new Int32Array(count);
    for (let i = 0; i < count; i++, o += 4) out[i] = view.getInt32(o, true);
    return out;
  };
  if (bytes.length < HEADER_BYTES) throw new RangeError('decodeSpringScene: too short');
  if (u32() !== SCENE_MAGIC || u32() !== SCENE_VERSION) {
    throw new RangeError('decodeSpringScene: not a version 1 scene file');
  }
  const method = C_METHODS[u32()];
  const dim = u32();
  if (method === undefined || dim !== 2) {
    throw new RangeError('decodeSpringScene: unknown method or dim');
  }
  const n = u32();
  const m = u32();
  if (bytes.length !== HEADER_BYTES + 8 * 5 * n + m * 32) {
    throw new RangeError('decodeSpringScene: wrong length');
  }
  const [dt, gx, gy] = f64s(3);
  return {
    method,
    dt: dt!,
    gravity: [gx!, gy!],
    x: f64s(2 * n),
    v: f64s(2 * n),
    inverseMass: f64s(n),
    springA: i32s(m),
    springB: i32s(m),
    restLength: f64s(m),
    stiffness: f64s(m),
    damping: f64s(m),
  };
}

/** A reply line of springs.c. */
export type Reply =
  | { readonly kind: 'ready'; readonly particles: number; readonly springs: number }
  | { readonly kind: 'time'; readonly ns: number }
  | { readonly kind: 'hash'; readonly hex: string }
  | { readonly kind: 'ok' }
  | { readonly kind: 'error'; readonly message: string };

/** Parses one reply line of springs.c; throws on anything else. */
export function parseReply(line: string): Reply {
  const text = line.trim();
  let m: RegExpExecArray | null;
  if ((m = /^ready (\d+) (\d+)$/.exec(text))) {
    return { kind: 'ready', particles: Number(m[1]), springs: Number(m[2]) };
  }
  if ((m = /^time (\d+)$/.exec(text))) return { kind: 'time', ns: Number(m[1]) };
  if ((m = /^hash ([0-9a-f]{16})$/.exec(text))) return { kind: 'hash', hex: m[1]! };
  if (text === 'ok') return { kind: 'ok' };
  if ((m = /^error (.*)$/.exec(text))) return { kind: 'error', message: m[1]! };
  throw new Error(`springs.c: unexpected output ${JSON.stringify(line)}`);
}

/** FNV-1a 64 (hex) of the bytes of `x` then `v`: what springs.c's `hash` prints. */
export function stateHash(x: Float64Array, v: Float64Array): string {
  const bytes = (a: Float64Array) => new Uint8Array(a.buffer, a.byteOffset, a.byteLength);
  return new Fnv1a64().update(bytes(x)).update(bytes(v)).hex();
}

/** gcc's flags: `-O2`, and no fused multiply-add (JavaScript rounds every operation). */
export const GCC_FLAGS: readonly string[] = ['-O2', '-ffp-contract=off', '-std=c11'];

/** The compiler command for `source` into `output`. */
export function compileArgs(source: string, output: string): string[] {
  return [...GCC_FLAGS, '-o', output, source, '-lm'];
}

/** `gcc --version`'s first line, or undefined when there is no gcc on the PATH. */
export function gccVersion(): string | undefined {
  const r = spawnSync('gcc', ['--version'], { encoding: 'utf8' });
  if (r.error !== undefined || r.status !== 0) return undefined;
  return r.stdout.split('\n')[0]?.trim();
}

/** Compiles springs.c into `output`; throws with gcc's message when it fails. */
export function compileSprings(output: string): void {
  const r = spawnSync('gcc', compileArgs(SPRINGS_C, output), { encoding: 'utf8' });
  if (r.error !== undefined) throw r.error;
  if (r.status !== 0) throw new Error(`gcc failed:\n${r.stderr}`);
}

/**
 * The CPUs of a `taskset -p PID` answer ("pid 42's current affinity mask: 3"), lowest first;
 * undefined if the line is not one.
 */
export function parseAffinity(line: string): number[] | undefined {
  const m = /affinity mask:\s*([0-9a-f]+)\s*$/i.exec(line.trim());
  if (m === null) return undefined;
  const mask = BigInt(`0x${m[1]!}`);
  const cpus: number[] = [];
  for (let cpu = 0; mask >> BigInt(cpu) > 0n; cpu++) {
    if (((mask >> BigInt(cpu)) & 1n) === 1n) cpus.push(cpu);
  }
  return cpus;
}

/**
 * The last CPU this process may run on (Linux, from `taskset -p`), to pin the programs a suite
 * measures side by side (`taskset -c`): on a busy machine with few cores, two unpinned programs
 * can land one on a free core and the other on a shared one. Undefined without `taskset`.
 */
export function lastAllowedCpu(): number | undefined {
  if (process.platform !== 'linux') return undefined;
  const query = spawnSync('taskset', ['-p', String(process.pid)], { encoding: 'utf8' });
  if (query.error !== undefined || query.status !== 0) return undefined;
  return parseAffinity(query.stdout)?.at(-1);
}

/**
 * Node's arguments for springs-js.ts on `sceneJson`: TypeScript sources through tsx (resolved from
 * here, so it works from any directory), `source` exports, `--expose-gc` for gc between rounds.
 */
export function jsProgramArgs(sceneJson: string, tsx: string): string[] {
  return ['--conditions=source', '--expose-gc', '--import', tsx, SPRINGS_JS, sceneJson];
}

/**
 * A running springs.c or springs-js.ts: one command at a time, each answered by one line. The
 * methods take the contestant's index for springs-js.ts and none for springs.c.
 */
export class SpringsProcess {
  private constructor(private readonly proc: LineProcess<Reply>) {}

  /** Starts `command args…` (on CPU `cpu` if given) and waits for it to be ready. */
  static async start(command: string, args: string[], cpu?: number): Promise<SpringsProcess> {
    const child =
      cpu === undefined
        ? spawn(command, args, { stdio: 'pipe' })
        : spawn('taskset', ['-c', String(cpu), command, ...args], { stdio: 'pipe' });
    const p = new SpringsProcess(
      new LineProcess<Reply>(child, 'springs.c', (line) => {
        const reply = parseReply(line);
        if (reply.kind === 'error') throw new Error(`springs.c: ${reply.message}`);
        return reply;
      }),
    );
    const ready = await p.proc.next();
    if (ready.kind !== 'ready') throw new Error(`springs.c: expected ready, got ${ready.kind}`);
    return p;
  }

  private async expect<K extends Reply['kind']>(
    text: string,
    kind: K,
  ): Promise<Extract<Reply, { kind: K }>> {
    const reply = await this.proc.command(text);
    if (reply.kind !== kind) throw new Error(`springs.c: ${text} answered ${reply.kind}`);
    return reply as Extract<Reply, { kind: K }>;
  }

  /** Runs `steps` steps, timed by the program itself; resolves to the time in ns. */
  async time(steps: number, who?: number): Promise<number> {
    return (await this.expect(`time ${steps}${arg(who)}`, 'time')).ns;
  }

  /** Runs `steps` steps, untimed. */
  async step(steps: number, who?: number): Promise<void> {
    await this.expect(`step ${steps}${arg(who)}`, 'ok');
  }

  /** {@link stateHash} of its current state. */
  async hash(who?: number): Promise<string> {
    return (await this.expect(`hash${arg(who)}`, 'hash')).hex;
  }

  /** Writes x then v (raw doubles) to `path`. */
  async dump(path: string, who?: number): Promise<void> {
    if (/[\r\n]/.test(path)) throw new RangeError('dump: a path on one line, please');
    await this.expect(`dump${arg(who)} ${path}`, 'ok');
  }

  /** A full gc in the program, if it has one (springs.c has nothing to collect). */
  async gc(): Promise<void> {
    await this.expect('gc', 'ok');
  }

  /** Back to the start state. */
  async reset(): Promise<void> {
    await this.expect('reset', 'ok');
  }

  /** Asks it to quit and waits for it to exit. */
  async close(): Promise<void> {
    if (this.proc.running) this.proc.child.stdin.end('quit\n');
    await this.proc.exited;
  }
}

function arg(who: number | undefined): string {
  return who === undefined ? '' : ` ${who}`;
}
