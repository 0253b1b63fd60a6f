/**
 * Many state-sync rooms behind one entry point, on the room core: a connection's join names the
 * room, the first join of a name makes it with the game it names.
 * @module
 */
import type { AnyGameDefinition } from '../../sim/game.js';
import type { Clock } from '../../time/drivers.js';
import { gameCatalog, type GameCatalog, type TicketVerifier } from '../room/game-join.js';
import { GameRoomHost } from '../room/game-host.js';
import type { HostEvent } from '../room/host-types.js';
import type { RoomHostOptions } from '../room/options.js';
import type { MemberInit } from '../room/room.js';
import {
  DEFAULT_STATE_SYNC_LIMITS,
  STATE_SYNC_PROTOCOL,
  type StateSyncMessage,
} from './messages.js';
import {
  StateSyncMember,
  StateSyncRoom,
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

/** Room options a server applies to every room it makes (the room core's are the server's). */
export type StateSyncRoomDefaults = Partial<
  Omit<
    StateSyncRoomOptions,
    'game' | 'clock' | 'name' | 'players' | 'seed' | 'randomU32' | 'onEvent' | keyof RoomHostOptions
  >
>;

/** Options of a {@link StateSyncServer}: the room core's, and its games and room defaults. */
export interface StateSyncServerOptions extends RoomHostOptions {
  /** The server clock (ms). */
  clock: Clock;
  /** The games rooms may play (found by id; the version and input schema must match). */
  games: readonly StateSyncGame[];
  /** Options of every room (snapshot interval, limits …). */
  room?: StateSyncRoomDefaults;
  /** Checks quick-match tickets. Default: tickets are refused. */
  tickets?: TicketVerifier;
  /** Room events, and rooms made and removed. */
  onEvent?: (event: StateSyncServerEvent) => void;
}

/** What a {@link StateSyncServer} reports. */
export type StateSyncServerEvent = HostEvent;

/**
 * State-sync rooms by name. {@link accept} takes a connection; its join makes the room (with the
 * game, player count and seed it names) or enters an existing one. A connection may be pinned to
 * a room name (the WebSocket path `/state/<room>`): a join for another room is then refused
 * (`WRONG_ROOM`). Every protection is the room core's: caps per address and in total, rates,
 * liveness, seats held for their players, an invite for spectators. Drive it with {@link update}.
 */
export class StateSyncServer extends GameRoomHost<
  StateSyncMember,
  StateSyncRoom,
  StateSyncMessage,
  StateSyncServerEvent
> {
  private readonly catalog: GameCatalog;
  private readonly options: StateSyncServerOptions;

  constructor(options: StateSyncServerOptions) {
    super('StateSyncServer', options.clock, options, STATE_SYNC_PROTOCOL, options.onEvent);
    this.options = options;
    this.catalog = gameCatalog(options.games);
  }

  /** A server of one room that serves on its own (see {@link StateSyncRoom.accept}). */
  static serving(room: StateSyncRoom, options: StateSyncRoomOptions): StateSyncServer {
    const { game, onEvent, ...host } = options;
    const server = new StateSyncServer({
      ...host,
      games: [game],
      ...(onEvent ? { onEvent: onEvent as (e: HostEvent) => void } : {}),
    });
    server.adopt(room);
    room.attach(server.context);
    return server;
  }

  /** The room of that name, if any. */
  room(name: string): StateSyncRoom | undefined {
    return this.rooms.get(name);
  }

  /** Every room, in creation order. */
  roomList(): StateSyncRoom[] {
    return [...this.rooms.values()];
  }

  /** Connections: waiting for their join, or in a room. */
  get connectionCount(): number {
    return this.stats.connections;
  }

  protected override decodeLimits(): object {
    return { ...DEFAULT_STATE_SYNC_LIMITS, ...this.options.room?.limits };
  }

  protected createMember(init: MemberInit): StateSyncMember {
    return new StateSyncMember(init);
  }

  protected onJoinMessage(m: StateSyncMember, message: StateSyncMessage, now: number): boolean {
    if (message.type !== 'join') return false;
    return this.joinGame(
      m,
      message,
      {
        catalog: this.catalog,
        tickets: this.options.tickets,
        make: (setup, number, tokens) => {
          const game = setup.game as unknown as StateSyncGame;
          const view = this.options.room?.view ?? game.stateView;
          try {
            const room = new StateSyncRoom(
              {
                ...this.options.room,
                game,
                name: message.room,
                clock: this.clock,
                players: setup.players,
                seed: setup.seed,
                ...(view ? { view } : {}),
              },
              { number, creator: m.address, tokens, ticketed: setup.ticketed },
            );
            room.attach(this.context);
            return room;
          } catch (e) {
            // The game could not be built for this setup: refuse the join, keep serving the rest.
            return ['BAD_HELLO', `${game.id}: ${e instanceof Error ? e.message : String(e)}`];
          }
        },
      },
      now,
    );
  }
}
