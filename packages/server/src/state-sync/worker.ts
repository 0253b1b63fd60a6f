/**
 * A state-sync worker thread: many rooms (a `StateSyncServer`) on the thread's own clock, fed
 * the bytes of the WebSocket connections the main thread assigned to it. The main thread never
 * runs a game, so a busy room never holds up the HTTP server.
 * @internal
 */
import { parentPort, workerData } from 'node:worker_threads';
import {
  BaseTransport,
  StateSyncServer,
  performanceClock,
  type StateSyncGame,
  type StateSyncRoom,
} from 'fixedstep';
import {
  STATS_INTERVAL_MS,
  type FromWorker,
  type StateSyncWorkerStats,
  type ToWorker,
  type WorkerSetup,
} from './messages.js';

const port = parentPort;
if (port === null) throw new Error('state-sync worker: not started as a worker thread');
const setup = workerData as WorkerSetup;

function post(m: FromWorker, transfer: ArrayBuffer[] = []): void {
  port!.postMessage(m, transfer);
}

/** One connection, as the rooms see it: bytes from the main thread in, bytes back out. */
class PortTransport extends BaseTransport {
  /**
   * A WebSocket behind the port: in order, and the main thread closes it rather than drop a
   * message (its send buffer over the cap) — so each snapshot is coded against the one before.
   */
  readonly reliable = true;
  constructor(readonly id: number) {
    super();
  }
  send(bytes: Uint8Array): void {
    if (!this.isOpen) return;
    // The caller may reuse its bytes: send a copy, and move (not copy) that to the main thread.
    const copy = bytes.slice();
    post({ t: 'send', id: this.id, bytes: copy.buffer }, [copy.buffer]);
  }
  receive(bytes: Uint8Array): void {
    this.deliver(bytes);
  }
  remoteClose(reason: string): void {
    this.closedRemotely(reason);
  }
  protected doClose(reason: string): void {
    post({ t: 'close', id: this.id, reason });
  }
}

/** The games of the module: its `GAMES`, `games` or default export, checked. */
async function loadGames(specifier: string): Promise<StateSyncGame[]> {
  const mod = (await import(specifier)) as Record<string, unknown>;
  const list = mod.GAMES ?? mod.games ?? mod.default;
  if (!Array.isArray(list) || list.length === 0) {
    throw new Error(
      `${specifier} exports no games (GAMES, games or default: an array of game definitions)`,
    );
  }
  for (const g of list as unknown[]) {
    const d = g as Partial<StateSyncGame> | null;
    if (
      typeof d?.id !== 'string' ||
      typeof d.create !== 'function' ||
      typeof d.input !== 'object'
    ) {
      throw new Error(`${specifier}: ${JSON.stringify(d?.id ?? g)} is not a game definition`);
    }
  }
  return list as StateSyncGame[];
}

const connections = new Map<number, PortTransport>();
/** Open rooms by name (their counters are read at each report), and what ended rooms counted. */
const live = new Map<string, StateSyncRoom>();
const ended = { ticks: 0, snapshotBytes: 0, lateInputs: 0, filledInputs: 0 };

/** This worker's rooms and counters, for the main thread's `/metrics`. */
function stats(): StateSyncWorkerStats {
  const total = { rooms: live.size, players: 0, ...ended };
  for (const room of live.values()) {
    total.players += room.occupied().filter(Boolean).length;
    total.ticks += room.stats.ticks;
    total.snapshotBytes += room.stats.snapshotBytes;
    total.lateInputs += room.stats.lateInputs;
    total.filledInputs += room.stats.filledInputs;
  }
  return total;
}
let server: StateSyncServer | undefined;
let timer: ReturnType<typeof setInterval> | undefined;
let reporter: ReturnType<typeof setInterval> | undefined;
const early: ToWorker[] = [];

function handle(m: ToWorker): void {
  if (server === undefined) {
    early.push(m);
    return;
  }
  switch (m.t) {
    case 'open': {
      const c = new PortTransport(m.id);
      connections.set(m.id, c);
      c.onClose(() => connections.delete(m.id));
      server.accept(c, { room: m.room, address: m.address });
      break;
    }
    case 'data':
      connections.get(m.id)?.receive(new Uint8Array(m.bytes));
      break;
    case 'close':
      connections.get(m.id)?.remoteClose(m.reason);
      connections.delete(m.id);
      break;
    case 'beat':
      // The main thread reads the sockets: while it stalls, no member's silence is its own.
      server.heartbeat();
      break;
    case 'drain':
      void server.drain({ timeoutMs: m.timeoutMs }).then(() => {
        post({ t: 'drained' });
      });
      break;
    case 'stop':
      if (timer !== undefined) clearInterval(timer);
      if (reporter !== undefined) clearInterval(reporter);
      server.close();
      post({ t: 'stopped' });
      break;
  }
}

port.on('message', (m: ToWorker) => {
  try {
    handle(m);
  } catch (e) {
    // A bug in handling one message costs that connection, never the worker.
    if (m.t === 'open' || m.t === 'data') connections.get(m.id)?.close(`INTERNAL: ${String(e)}`);
  }
});

try {
  const byId = new Map<string, StateSyncGame>();
  for (const specifier of setup.games) {
    for (const game of await loadGames(specifier)) byId.set(game.id, game);
  }
  const games = [...byId.values()];
  server = new StateSyncServer({
    ...setup.host,
    clock: performanceClock(),
    games,
    room: setup.room,
    onEvent: (e) => {
      if (e.type === 'room-created') {
        const room = server?.room(e.room);
        if (room) live.set(e.room, room);
        post({ t: 'room-created', room: e.room, game: e.game, players: e.players });
      } else if (e.type === 'room-removed') {
        const room = live.get(e.room);
        if (room) {
          live.delete(e.room);
          ended.ticks += room.stats.ticks;
          ended.snapshotBytes += room.stats.snapshotBytes;
          ended.lateInputs += room.stats.lateInputs;
          ended.filledInputs += room.stats.filledInputs;
        }
        post({ t: 'room-removed', room: e.room });
      } else if (e.type === 'room-closed' && e.code === 'INTERNAL')
        post({ t: 'room-failed', room: e.room, message: e.message });
    },
  });
  const s = server;
  timer = setInterval(() => {
    s.update();
  }, setup.updateIntervalMs);
  reporter = setInterval(() => {
    post({ t: 'stats', stats: stats() });
  }, STATS_INTERVAL_MS);
  post({ t: 'ready', games: games.map((g) => g.id) });
  for (const m of early.splice(0)) handle(m);
} catch (e) {
  post({ t: 'fatal', message: e instanceof Error ? e.message : String(e) });
}
