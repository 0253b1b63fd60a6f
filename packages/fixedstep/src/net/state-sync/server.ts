/**
 * Many state-sync rooms behind one entry point: a connection's join names the room, the first
 * join of a name creates it with the game it names.
 * @module
 */
import type { AnyGameDefinition } from '../../sim/game.js';
import type { Clock } from '../../time/drivers.js';
import type { Transport } from '../transport.js';
import { DEFAULT_STATE_SYNC_LIMITS, type JoinMessage, type StateSyncErrorCode } from './codec.js';
import {
  StateSyncRoom,
  refuse,
  waitForJoin,
  type StateSyncRoomEvent,
  type StateSyncRoomOptions,
  type StateSyncView,
} from './room.js';

/**
 * A game definition, optionally with its interest management: `stateView(sim, slot)` gives the
 * bytes member `slot` (-1: a spectator) may see (see {@link StateSyncView}).
 */
export type StateSyncGame = AnyGameDefinition & {
  // eslint-disable-next-line @typescript-eslint/no-explicit-any -- any: a registry holds games of every simulation type
  readonly stateView?: StateSyncView<any>;
};

/** Room options a server applies to every room it creates. */
export type StateSyncRoomDefaults = Partial<
  Omit<
    StateSyncRoomOptions,
    'game' | 'clock' | 'name' | 'players' | 'seed' | 'randomU32' | 'onEvent'
  >
>;

/** Options of a {@link StateSyncServer}. */
export interface StateSyncServerOptions {
  /** The server clock (ms). */
  clock: Clock;
  /** The games rooms may play (found by id; the version and input schema must match). */
  games: readonly StateSyncGame[];
  /** Options of every room (snapshot interval, limits …). */
  room?: StateSyncRoomDefaults;
  /** Rooms at once. Default 500. */
  maxRooms?: number;
  /** Connections at once (joined or not). Default 4000. */
  maxConnections?: number;
  /** A connection must join within this time. Default 5000 ms. */
  joinTimeoutMs?: number;
  /** A room without members is removed after this long. Default 30 000 ms. */
  emptyRoomTtlMs?: number;
  /** Random u32s for seeds and reconnect tokens. Default `crypto.getRandomValues`. */
  randomU32?: () => number;
  /** Room events, and rooms created and removed. */
  onEvent?: (event: StateSyncServerEvent) => void;
}

/** What a {@link StateSyncServer} reports. */
export type StateSyncServerEvent =
  | StateSyncRoomEvent
  | { type: 'room-created'; room: string; game: string; players: number }
  | { type: 'room-removed'; room: string }
  /** A room's game threw (in `step`, `save` or a view): the room was closed with `INTERNAL`. */
  | { type: 'room-failed'; room: string; error: unknown }
  | { type: 'refused'; code: StateSyncErrorCode; message: string };

interface Pending {
  transport: Transport;
  since: number;
  room: string | undefined;
  done: boolean;
}

/**
 * State-sync rooms by name. {@link accept} takes a connection; its join creates the room (with the
 * game, player count and seed it names) or enters an existing one. A connection may be pinned to
 * a room name (the WebSocket path `/state/<room>`): a join for another room is then refused
 * (`WRONG_ROOM`). Drive it with {@link update}.
 */
export class StateSyncServer {
  private readonly clock: Clock;
  private readonly options: StateSyncServerOptions;
  private readonly roomsByName = new Map<string, StateSyncRoom>();
  private pending: Pending[] = [];
  private closed = false;

  constructor(options: StateSyncServerOptions) {
    this.clock = options.clock;
    this.options = options;
  }

  /** The room of that name, if any. */
  room(name: string): StateSyncRoom | undefined {
    return this.roomsByName.get(name);
  }

  /** Every room, in creation order. */
  rooms(): StateSyncRoom[] {
    return [...this.roomsByName.values()];
  }

  /** Connections: waiting for their join, or members of a room. */
  get connectionCount(): number {
    let n = 0;
    for (const p of this.pending) if (!p.done) n++;
    for (const room of this.roomsByName.values()) n += room.memberCount;
    return n;
  }

  /** Take a connection; its first message must be a join (for `options.room`, if given). */
  accept(transport: Transport, options: { room?: string } = {}): void {
    if (this.closed) {
      refuse(transport, 'SHUTDOWN', 'the server is shutting down');
      return;
    }
    const max = this.options.maxConnections ?? 4000;
    if (this.connectionCount >= max) {
      this.refused(transport, 'SERVER_FULL', `${max} connections already`);
      return;
    }
    const p: Pending = { transport, since: this.clock.now(), room: options.room, done: false };
    this.pending.push(p);
    // Until it joins; a room takes the handlers over.
    transport.onClose(() => {
      p.done = true;
    });
    const limits = { ...DEFAULT_STATE_SYNC_LIMITS, ...this.options.room?.limits };
    waitForJoin(transport, limits, this.clock, (join) => {
      p.done = true;
      this.onJoin(p, join);
    });
  }

  /** Advance every room to `now`; drop connections that did not join in time; remove empty rooms. */
  update(now = this.clock.now()): void {
    const timeout = this.options.joinTimeoutMs ?? 5000;
    if (this.pending.length > 0) {
      const keep: Pending[] = [];
      for (const p of this.pending) {
        if (p.done) continue;
        if (now - p.since > timeout) {
          p.done = true;
          this.refused(p.transport, 'TIMEOUT', 'no join in time');
        } else keep.push(p);
      }
      this.pending = keep;
    }
    const ttl = this.options.emptyRoomTtlMs ?? 30_000;
    for (const [name, room] of this.roomsByName) {
      try {
        room.update(now);
      } catch (e) {
        // A bug in one game (a step that throws) costs that room, never the others.
        this.options.onEvent?.({ type: 'room-failed', room: name, error: e });
        room.close('INTERNAL', `the room stopped: ${e instanceof Error ? e.message : String(e)}`);
        this.roomsByName.delete(name);
        this.options.onEvent?.({ type: 'room-removed', room: name });
        continue;
      }
      const empty = room.emptySinceMs;
      if (empty !== undefined && now - empty >= ttl) {
        room.close();
        this.roomsByName.delete(name);
        this.options.onEvent?.({ type: 'room-removed', room: name });
      }
    }
  }

  /** Close every room and connection (`SHUTDOWN`). */
  close(): void {
    this.closed = true;
    for (const room of this.roomsByName.values()) room.close();
    this.roomsByName.clear();
    for (const p of this.pending)
      if (!p.done) refuse(p.transport, 'SHUTDOWN', 'the server is shutting down');
    this.pending = [];
  }

  private onJoin(p: Pending, join: JoinMessage): void {
    if (p.room !== undefined && join.room !== p.room) {
      this.refused(
        p.transport,
        'WRONG_ROOM',
        `this connection is for room ${p.room}, not ${join.room}`,
      );
      return;
    }
    let room = this.roomsByName.get(join.room);
    if (room === undefined) {
      const game = this.options.games.find((g) => g.id === join.game);
      if (game === undefined) {
        this.refused(p.transport, 'UNKNOWN_GAME', `no game "${join.game}" on this server`);
        return;
      }
      if (game.version !== join.gameVersion || game.input.id !== join.input) {
        this.refused(
          p.transport,
          'GAME_MISMATCH',
          `this server plays ${game.id} version ${game.version} (input schema ${game.input.id}), not version ${join.gameVersion} (${join.input})`,
        );
        return;
      }
      const max = this.options.maxRooms ?? 500;
      if (this.roomsByName.size >= max) {
        this.refused(p.transport, 'SERVER_FULL', `${max} rooms already`);
        return;
      }
      const players = join.players === 0 ? game.minPlayers : join.players;
      if (players < game.minPlayers || players > game.maxPlayers) {
        this.refused(
          p.transport,
          'BAD_JOIN',
          `${game.id} takes ${game.minPlayers} to ${game.maxPlayers} players, not ${players}`,
        );
        return;
      }
      const view = this.options.room?.view ?? game.stateView;
      const options: StateSyncRoomOptions = {
        ...this.options.room,
        game,
        name: join.room,
        clock: this.clock,
        players,
        onEvent: (e) => this.options.onEvent?.(e),
      };
      if (view) options.view = view;
      if (join.seed !== undefined) options.seed = join.seed;
      if (this.options.randomU32) options.randomU32 = this.options.randomU32;
      try {
        room = new StateSyncRoom(options);
      } catch (e) {
        // The game could not be built for this setup: refuse the join, keep serving the rest.
        this.refused(
          p.transport,
          'BAD_JOIN',
          `${game.id}: ${e instanceof Error ? e.message : String(e)}`,
        );
        return;
      }
      this.roomsByName.set(join.room, room);
      this.options.onEvent?.({ type: 'room-created', room: join.room, game: game.id, players });
    }
    const wrong = room.accepts(join);
    if (wrong) {
      this.refused(p.transport, wrong.code, wrong.message);
      return;
    }
    try {
      room.join(p.transport, join);
    } catch (e) {
      this.refused(
        p.transport,
        'INTERNAL',
        `cannot seat: ${e instanceof Error ? e.message : String(e)}`,
      );
    }
  }

  private refused(transport: Transport, code: StateSyncErrorCode, message: string): void {
    this.options.onEvent?.({ type: 'refused', code, message });
    refuse(transport, code, message);
  }
}
