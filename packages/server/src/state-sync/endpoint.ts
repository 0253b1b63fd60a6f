/**
 * State-sync rooms on the HTTP server: WebSocket upgrades on `/state/<room>` become connections to
 * rooms that run in a pool of worker threads, many rooms per worker. The main thread only moves
 * bytes between sockets and workers; the games run in the workers, so no room ever blocks the
 * HTTP server (or another worker's rooms).
 * @module
 */
import { availableParallelism } from 'node:os';
import type http from 'node:http';
import { Worker } from 'node:worker_threads';
import type { WebSocket } from 'ws';
import { STATE_SYNC_PROTOCOL, type RoomHostOptions, type StateSyncRoomDefaults } from 'fixedstep';
import type { FromWorker, StateSyncWorkerStats, ToWorker, WorkerSetup } from './messages.js';
import { endpointAdmission, roomCapsFromEnv, type SurfaceOptions } from '../http/admission.js';
import { WebSocketEndpoint, type UpgradeInfo } from '../http/websocket-endpoint.js';

/** How often each worker advances its rooms, ms: a 60 Hz tick is stepped within 4 ms of its time. */
export const STATE_SYNC_UPDATE_MS = 4;
/**
 * How often the main thread tells each worker it is responsive, ms: while it stalls (and its
 * sockets go unread), the workers' liveness stops — a member's silence then is not its own. Well
 * within the room core's stall tolerance (1 s by default).
 */
export const STATE_SYNC_HEARTBEAT_MS = 100;
/** A peer that does not read is dropped when this much is waiting to be sent to it. */
const MAX_BUFFERED = 4 << 20;

/** Options of {@link attachStateSync}. */
export interface StateSyncEndpointOptions extends SurfaceOptions {
  /** URL path prefix: a room is at `<path>/<room>`. Default `/state`. */
  path?: string;
  /**
   * The module (or modules) the workers load their games from (package names, or `file:` URLs):
   * each one's `GAMES`, `games` or default export, an array of game definitions (a `stateView` on
   * one is its interest management); a later module's game replaces an earlier one's of the same
   * id. Default `@fixedstep/games` — the talk's games.
   */
  games?: string | readonly string[];
  /** Worker threads. Default: the cores but one, from 1 to 4. */
  workers?: number;
  /** How often each worker advances its rooms, in ms. Default {@link STATE_SYNC_UPDATE_MS}. */
  updateIntervalMs?: number;
  /** Options of every room (snapshot interval, limits …); plain data, no functions. */
  room?: Omit<StateSyncRoomDefaults, 'view'>;
  /**
   * The room core's options in each worker (caps per address and in total, liveness, seat holds …);
   * plain data. Default: the core's defaults, and the caps of `FIXEDSTEP_*` variables.
   */
  host?: Omit<RoomHostOptions, 'randomU32'>;
  /** Where problems are reported (a worker that failed, a room whose game threw). Default: console.error. */
  log?: (message: string) => void;
}

interface Slot {
  worker: Worker;
  ready: Promise<void>;
  /** What the worker last reported. */
  stats?: StateSyncWorkerStats;
}

interface Conn {
  ws: WebSocket;
  room: string;
  worker: number;
}

/** The worker script: compiled next to this file, or (from the sources, under tsx) the TypeScript. */
function startWorker(setup: WorkerSetup): Worker {
  const here = import.meta.url;
  if (here.endsWith('.ts')) {
    // Running from the sources (tests, `npm run bench`): register tsx in the worker first, then
    // load the worker's TypeScript. The published package runs the compiled worker.js.
    const tsx = import.meta.resolve('tsx/esm/api');
    const entry = new URL('./worker.ts', here).href;
    const code = `import(${JSON.stringify(tsx)}).then((m) => { m.register(); return import(${JSON.stringify(entry)}); });`;
    return new Worker(code, { eval: true, workerData: setup, execArgv: ['--conditions=source'] });
  }
  return new Worker(new URL('./worker.js', here), { workerData: setup });
}

/** State-sync rooms attached to an HTTP server (see {@link attachStateSync}). */
export class StateSyncEndpoint extends WebSocketEndpoint {
  /** Worker threads running rooms. */
  readonly workers: number;
  /** Resolves once every worker has loaded its games (rejects if one could not). */
  readonly ready: Promise<void>;
  private readonly setup: WorkerSetup;
  private readonly log: (message: string) => void;
  private readonly conns = new Map<number, Conn>();
  /** Room name → the worker it runs on, while it may exist there. */
  private readonly roomWorker = new Map<string, number>();
  // Who made each room (the first connection's address): an address's rooms share a worker.
  private readonly roomAddress = new Map<string, string>();
  private readonly slots: Slot[];
  private nextId = 1;
  private closing = false;
  private readonly heartbeat: ReturnType<typeof setInterval>;

  constructor(server: http.Server, options: StateSyncEndpointOptions = {}) {
    const count = options.workers ?? Math.max(1, Math.min(4, availableParallelism() - 1));
    if (!(Number.isInteger(count) && count >= 1 && count <= 64)) {
      throw new RangeError(
        `attachStateSync: workers must be an integer from 1 to 64, got ${String(count)}`,
      );
    }
    super(server, {
      path: (options.path ?? '/state').replace(/\/+$/, ''),
      rooms: 'required',
      // Clients send only inputs, acks and pings.
      maxPayload: STATE_SYNC_PROTOCOL.largest('client', {
        ...STATE_SYNC_PROTOCOL.limits,
        ...options.room?.limits,
      }),
      protocol: STATE_SYNC_PROTOCOL,
      admission: endpointAdmission(options, options.env ?? process.env),
    });
    this.workers = count;
    this.log =
      options.log ??
      ((m: string) => {
        console.error(`fixedstep state sync: ${m}`);
      });
    this.setup = {
      games:
        options.games === undefined
          ? ['@fixedstep/games']
          : typeof options.games === 'string'
            ? [options.games]
            : options.games,
      room: options.room ?? {},
      host: { ...roomCapsFromEnv(options.env ?? process.env), ...options.host },
      updateIntervalMs: options.updateIntervalMs ?? STATE_SYNC_UPDATE_MS,
    };
    this.slots = Array.from({ length: count }, (_, i) => this.spawn(i));
    this.ready = Promise.all(this.slots.map((s) => s.ready)).then(() => undefined);
    this.heartbeat = setInterval(() => {
      for (let i = 0; i < this.slots.length; i++) this.post(i, { t: 'beat' });
    }, STATE_SYNC_HEARTBEAT_MS);
    this.heartbeat.unref();
  }

  /**
   * Rooms, players and counters over every worker, as the workers last reported them (each does
   * every second); a worker that was replaced counts from its start.
   */
  get stats(): StateSyncWorkerStats {
    const total: StateSyncWorkerStats = {
      rooms: 0,
      players: 0,
      ticks: 0,
      snapshotBytes: 0,
      lateInputs: 0,
      filledInputs: 0,
    };
    for (const slot of this.slots) {
      for (const key of Object.keys(total) as (keyof StateSyncWorkerStats)[]) {
        total[key] += slot.stats?.[key] ?? 0;
      }
    }
    return total;
  }

  /** Room names now, with the worker each runs on. */
  rooms(): { room: string; worker: number }[] {
    return [...this.roomWorker].map(([room, worker]) => ({ room, worker }));
  }

  protected override refuses(): string | undefined {
    return this.closing ? '503 Service Unavailable' : undefined;
  }

  protected connected(ws: WebSocket, info: UpgradeInfo): void {
    const room = info.room!;
    let index = this.roomWorker.get(room);
    if (index === undefined) {
      index = this.placeRoom(info.address);
      this.roomWorker.set(room, index);
      this.roomAddress.set(room, info.address);
    }
    const id = this.nextId++;
    const w = index;
    this.conns.set(id, { ws, room, worker: w });
    this.post(w, { t: 'open', id, room, address: info.address });
    ws.on('message', (data, isBinary) => {
      // A text frame was refused by the endpoint (the base class).
      if (!isBinary) return;
      const chunks = Array.isArray(data)
        ? data
        : [data instanceof ArrayBuffer ? Buffer.from(data) : data];
      const size = chunks.reduce((n, c) => n + c.length, 0);
      const bytes = new Uint8Array(size);
      let at = 0;
      for (const c of chunks) {
        bytes.set(c, at);
        at += c.length;
      }
      this.post(w, { t: 'data', id, bytes: bytes.buffer }, [bytes.buffer]);
    });
    ws.on('close', () => {
      if (!this.conns.delete(id)) return;
      this.post(w, { t: 'close', id, reason: 'closed' });
    });
    ws.on('error', () => {
      ws.terminate();
    });
  }

  /**
   * Drain before a shutdown: every worker makes no new rooms, closes waiting ones, and lets running
   * rooms play on until their players have left or `timeoutMs` has passed (then `SHUTDOWN`).
   * Resolves when no worker has a room left. Call {@link close} after.
   */
  drain(timeoutMs = 25_000): Promise<void> {
    return Promise.all(
      this.slots.map(
        (s) =>
          new Promise<void>((resolve) => {
            const done = (m: FromWorker) => {
              if (m.t !== 'drained') return;
              s.worker.off('message', done);
              resolve();
            };
            s.worker.on('message', done);
            s.worker.once('exit', () => {
              resolve();
            });
            s.worker.postMessage({ t: 'drain', timeoutMs } satisfies ToWorker);
          }),
      ),
    ).then(() => undefined);
  }

  /** Each worker says `SHUTDOWN` to its rooms' members, then ends. */
  protected async stop(): Promise<void> {
    this.closing = true;
    clearInterval(this.heartbeat);
    await Promise.all(
      this.slots.map(
        (s) =>
          new Promise<void>((resolve) => {
            const done = () => {
              resolve();
            };
            const timer = setTimeout(done, 1000);
            s.worker.on('message', (m: FromWorker) => {
              if (m.t === 'stopped') {
                clearTimeout(timer);
                // Let the last sends reach the main thread's sockets.
                setImmediate(done);
              }
            });
            s.worker.on('exit', done);
            s.worker.postMessage({ t: 'stop' } satisfies ToWorker);
          }),
      ),
    );
    for (const c of this.conns.values()) c.ws.close(1001, 'the server is shutting down');
    this.conns.clear();
    await Promise.all(this.slots.map((s) => s.worker.terminate()));
  }

  /**
   * The worker for a new room from `address`: the one its other rooms run on, so that worker's
   * per-address caps count all of them (they would count per worker otherwise); else the worker
   * with the fewest rooms.
   */
  private placeRoom(address: string): number {
    for (const [room, from] of this.roomAddress) {
      const w = this.roomWorker.get(room);
      if (from === address && w !== undefined) return w;
    }
    const load = this.slots.map(() => 0);
    for (const w of this.roomWorker.values()) load[w] = load[w]! + 1;
    return load.indexOf(Math.min(...load));
  }

  private post(index: number, m: ToWorker, transfer: ArrayBuffer[] = []): void {
    this.slots[index]!.worker.postMessage(m, transfer);
  }

  private spawn(index: number): Slot {
    const worker = startWorker(this.setup);
    let settle: { ok: () => void; fail: (e: Error) => void } | undefined;
    const ready = new Promise<void>((ok, fail) => {
      settle = { ok, fail };
    });
    // Nothing waits on it but `ready`: an unhandled rejection must not take the process down.
    ready.catch(() => undefined);
    worker.on('message', (m: FromWorker) => {
      if (m.t === 'ready') settle?.ok();
      if (m.t === 'fatal') settle?.fail(new Error(m.message));
      this.onWorkerMessage(index, m);
    });
    worker.on('error', (e) => {
      this.log(`worker ${index} failed: ${e.message}`);
      settle?.fail(e);
    });
    worker.on('exit', () => {
      // Its rooms are gone: close their connections; a new worker takes its place.
      for (const [id, c] of this.conns) {
        if (c.worker !== index) continue;
        this.conns.delete(id);
        c.ws.close(1011, 'the room’s worker stopped');
      }
      for (const [room, w] of this.roomWorker) {
        if (w !== index) continue;
        this.roomWorker.delete(room);
        this.roomAddress.delete(room);
      }
      if (!this.closing) this.slots[index] = this.spawn(index);
    });
    return { worker, ready };
  }

  private onWorkerMessage(index: number, m: FromWorker): void {
    switch (m.t) {
      case 'send': {
        const c = this.conns.get(m.id);
        if (!c || c.ws.readyState !== c.ws.OPEN) return;
        if (c.ws.bufferedAmount > MAX_BUFFERED) {
          c.ws.terminate();
          return;
        }
        c.ws.send(new Uint8Array(m.bytes), { binary: true });
        break;
      }
      case 'close': {
        const c = this.conns.get(m.id);
        if (!c) return;
        this.conns.delete(m.id);
        c.ws.close(1000, m.reason.slice(0, 120));
        break;
      }
      case 'room-removed': {
        // Forget where it ran — unless a connection to that name is open (it went to this worker
        // and may have made the room again there).
        const open = [...this.conns.values()].some((c) => c.room === m.room);
        if (!open && this.roomWorker.get(m.room) === index) {
          this.roomWorker.delete(m.room);
          this.roomAddress.delete(m.room);
        }
        break;
      }
      case 'room-failed':
        this.log(`room ${m.room} stopped: ${m.message}`);
        break;
      case 'stats':
        this.slots[index]!.stats = m.stats;
        break;
      case 'fatal':
        this.log(`worker ${index} could not start: ${m.message}`);
        break;
      default:
        break;
    }
  }
}

/**
 * Attaches state-sync rooms to `server` at `path` (default `/state`): a WebSocket upgrade on
 * `/state/<room>` (a room name: 1–32 of `A–Z a–z 0–9 _ - .`) joins — or, with its first join,
 * makes — that room, admitted as every surface is. Rooms run in `workers` worker threads on the
 * room core (caps, rates, liveness, held seats, invites); a new room goes to the worker with the
 * fewest rooms, and every connection to it follows. A bad room name gets 400.
 */
export function attachStateSync(
  server: http.Server,
  options: StateSyncEndpointOptions = {},
): StateSyncEndpoint {
  return new StateSyncEndpoint(server, options);
}
