/**
 * State-sync rooms on the HTTP server: WebSocket upgrades on `/state/<room>` become connections to
 * rooms that run in a pool of worker threads, many rooms per worker. The main thread only moves
 * bytes between sockets and workers; the games run in the workers, so no room ever blocks the
 * HTTP server (or another worker's rooms).
 */
import { availableParallelism } from 'node:os';
import type http from 'node:http';
import type { Duplex } from 'node:stream';
import { Worker } from 'node:worker_threads';
import { WebSocketServer, type WebSocket } from 'ws';
import { NAME_PATTERN, type StateSyncRoomDefaults } from 'fixedstep';
import type { FromWorker, ToWorker, WorkerSetup } from './messages.js';
import { claimUpgradePaths, shouldRefuseUpgrade } from '../http/upgrade-paths.js';
import { originAllowed } from '../relay/endpoint.js';

/** Options of {@link attachStateSync}. */
export interface StateSyncEndpointOptions {
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
  /** How often each worker advances its rooms, in ms. Default 4 (a 60 Hz tick is stepped within 4 ms of its time). */
  updateIntervalMs?: number;
  /** Options of every room (snapshot interval, limits …); plain data, no functions. */
  room?: Omit<StateSyncRoomDefaults, 'view'>;
  /** Rooms per worker at once. Default 500. */
  maxRoomsPerWorker?: number;
  /** Connections at once, all workers together. Default 4000. */
  maxConnections?: number;
  /** A connection must join within this time. Default 5000 ms. */
  joinTimeoutMs?: number;
  /** A room without members is removed after this long. Default 30 000 ms. */
  emptyRoomTtlMs?: number;
  /** Largest WebSocket message from a client (`ws` `maxPayload`). Default 64 KiB: clients send only inputs. */
  maxMessageBytes?: number;
  /** Browser origins allowed to connect (the `Origin` header). Default: any. */
  allowedOrigins?: readonly string[];
  /** Where problems are reported (a worker that failed, a room whose game threw). Default: console.error. */
  log?: (message: string) => void;
}

/** State-sync rooms attached to an HTTP server, from {@link attachStateSync}. */
export interface StateSyncEndpoint {
  readonly path: string;
  /** Worker threads running rooms. */
  readonly workers: number;
  /** Resolves once every worker has loaded its games (rejects if one could not). */
  readonly ready: Promise<void>;
  /** Room names now, with the worker each runs on. */
  rooms(): { room: string; worker: number }[];
  /** Stop: close every connection (`SHUTDOWN`), detach from the server, end the workers. */
  close(): Promise<void>;
}

/** A peer that does not read is dropped when this much is waiting to be sent to it. */
const MAX_BUFFERED = 4 << 20;

interface Slot {
  worker: Worker;
  ready: Promise<void>;
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

/**
 * Attaches state-sync rooms to `server` at `path` (default `/state`): a WebSocket upgrade on
 * `/state/<room>` (a room name: 1–32 of `A–Z a–z 0–9 _ - .`) joins — or, with its first join,
 * creates — that room. Rooms run in `workers` worker threads; a new room goes to the worker with
 * the fewest rooms, and every connection to it follows. Other upgrade paths are left to other
 * handlers (404 when there is none); a bad room name gets 400.
 */
export function attachStateSync(
  server: http.Server,
  options: StateSyncEndpointOptions = {},
): StateSyncEndpoint {
  const path = (options.path ?? '/state').replace(/\/+$/, '');
  const count = options.workers ?? Math.max(1, Math.min(4, availableParallelism() - 1));
  if (!(Number.isInteger(count) && count >= 1 && count <= 64)) {
    throw new RangeError(
      `attachStateSync: workers must be an integer from 1 to 64, got ${String(count)}`,
    );
  }
  const log =
    options.log ??
    ((m: string) => {
      console.error(`fixedstep state sync: ${m}`);
    });
  const maxConnections = options.maxConnections ?? 4000;
  const setup: WorkerSetup = {
    games:
      options.games === undefined
        ? ['@fixedstep/games']
        : typeof options.games === 'string'
          ? [options.games]
          : options.games,
    room: options.room ?? {},
    updateIntervalMs: options.updateIntervalMs ?? 4,
    maxRooms: options.maxRoomsPerWorker ?? 500,
    maxConnections,
    joinTimeoutMs: options.joinTimeoutMs ?? 5000,
    emptyRoomTtlMs: options.emptyRoomTtlMs ?? 30_000,
  };
  const wss = new WebSocketServer({
    noServer: true,
    maxPayload: options.maxMessageBytes ?? 64 * 1024,
    perMessageDeflate: false,
  });
  const conns = new Map<number, Conn>();
  /** Room name → the worker it runs on, while it may exist there. */
  const roomWorker = new Map<string, number>();
  let nextId = 1;
  let closing = false;

  const onWorkerMessage = (index: number, m: FromWorker) => {
    switch (m.t) {
      case 'send': {
        const c = conns.get(m.id);
        if (!c || c.ws.readyState !== c.ws.OPEN) return;
        if (c.ws.bufferedAmount > MAX_BUFFERED) {
          c.ws.terminate();
          return;
        }
        c.ws.send(new Uint8Array(m.bytes), { binary: true });
        break;
      }
      case 'close': {
        const c = conns.get(m.id);
        if (!c) return;
        conns.delete(m.id);
        c.ws.close(1000, m.reason.slice(0, 120));
        break;
      }
      case 'room-removed': {
        // Forget where it ran — unless a connection to that name is open (it went to this worker
        // and may have made the room again there).
        const open = [...conns.values()].some((c) => c.room === m.room);
        if (!open && roomWorker.get(m.room) === index) roomWorker.delete(m.room);
        break;
      }
      case 'room-failed':
        log(`room ${m.room} stopped: ${m.message}`);
        break;
      case 'fatal':
        log(`worker ${index} could not start: ${m.message}`);
        break;
      default:
        break;
    }
  };

  const spawn = (index: number): Slot => {
    const worker = startWorker(setup);
    let settle: { ok: () => void; fail: (e: Error) => void } | undefined;
    const ready = new Promise<void>((ok, fail) => {
      settle = { ok, fail };
    });
    // Nothing waits on it but `ready`: an unhandled rejection must not take the process down.
    ready.catch(() => undefined);
    worker.on('message', (m: FromWorker) => {
      if (m.t === 'ready') settle?.ok();
      if (m.t === 'fatal') settle?.fail(new Error(m.message));
      onWorkerMessage(index, m);
    });
    worker.on('error', (e) => {
      log(`worker ${index} failed: ${e.message}`);
      settle?.fail(e);
    });
    worker.on('exit', () => {
      // Its rooms are gone: close their connections; a new worker takes its place.
      for (const [id, c] of conns) {
        if (c.worker !== index) continue;
        conns.delete(id);
        c.ws.close(1011, 'the room’s worker stopped');
      }
      for (const [room, w] of roomWorker) if (w === index) roomWorker.delete(room);
      if (!closing) slots[index] = spawn(index);
    });
    return { worker, ready };
  };
  const slots: Slot[] = Array.from({ length: count }, (_, i) => spawn(i));

  const post = (index: number, m: ToWorker, transfer: ArrayBuffer[] = []) => {
    slots[index]!.worker.postMessage(m, transfer);
  };

  const refuse = (socket: Duplex, status: string) => {
    socket.write(`HTTP/1.1 ${status}\r\nConnection: close\r\nContent-Length: 0\r\n\r\n`);
    socket.destroy();
  };

  const ownsPath = (pathname: string) => pathname.startsWith(`${path}/`);
  const releasePaths = claimUpgradePaths(server, ownsPath, `${path}/room`);
  const onUpgrade = (req: http.IncomingMessage, socket: Duplex, head: Buffer) => {
    const pathname = (req.url ?? '/').split('?')[0] ?? '/';
    if (!ownsPath(pathname)) {
      // Another endpoint may own this path; answer only when none does.
      if (shouldRefuseUpgrade(server, ownsPath, pathname)) refuse(socket, '404 Not Found');
      return;
    }
    let room: string;
    try {
      room = decodeURIComponent(pathname.slice(path.length + 1));
    } catch {
      room = '';
    }
    if (!NAME_PATTERN.test(room)) {
      refuse(socket, '400 Bad Request');
      return;
    }
    if (!originAllowed(req, options.allowedOrigins ?? 'any')) {
      refuse(socket, '403 Forbidden');
      return;
    }
    if (closing || conns.size >= maxConnections) {
      refuse(socket, '503 Service Unavailable');
      return;
    }
    wss.handleUpgrade(req, socket, head, (ws) => {
      let index = roomWorker.get(room);
      if (index === undefined) {
        // A new room: to the worker with the fewest.
        const load = slots.map(() => 0);
        for (const w of roomWorker.values()) load[w] = load[w]! + 1;
        index = load.indexOf(Math.min(...load));
        roomWorker.set(room, index);
      }
      const id = nextId++;
      const w = index;
      conns.set(id, { ws, room, worker: w });
      post(w, { t: 'open', id, room });
      ws.on('message', (data, isBinary) => {
        if (!isBinary) {
          ws.close(1003, 'binary messages only');
          return;
        }
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
        post(w, { t: 'data', id, bytes: bytes.buffer }, [bytes.buffer]);
      });
      ws.on('close', () => {
        if (!conns.delete(id)) return;
        post(w, { t: 'close', id, reason: 'closed' });
      });
      ws.on('error', () => {
        ws.terminate();
      });
    });
  };
  server.on('upgrade', onUpgrade);

  let closed: Promise<void> | undefined;
  return {
    path,
    workers: count,
    ready: Promise.all(slots.map((s) => s.ready)).then(() => undefined),
    rooms: () => [...roomWorker].map(([room, worker]) => ({ room, worker })),
    close: () =>
      (closed ??= (async () => {
        closing = true;
        server.off('upgrade', onUpgrade);
        releasePaths();
        // Each worker says SHUTDOWN to its rooms' members, then ends.
        await Promise.all(
          slots.map(
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
        for (const c of conns.values()) c.ws.close(1001, 'the server is shutting down');
        conns.clear();
        await Promise.all(slots.map((s) => s.worker.terminate()));
        await new Promise<void>((resolve) => {
          for (const ws of wss.clients) ws.terminate();
          wss.close(() => {
            resolve();
          });
        });
      })()),
  };
}
