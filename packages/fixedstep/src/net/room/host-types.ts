/**
 * What a room host and its rooms exchange: where a connection comes from, the host's counters and
 * events, what a room may ask of its host, and the plan of a join.
 * @module
 */
import type { Clock } from '../../time/drivers.js';
import type { LeaveReason, NetErrorCode } from '../wire/common.js';
import type { RoomHostSettings } from './options.js';
import type { Member, Room, SeatRequest } from './room.js';

/** The creator address of an adopted room (not counted against any address). */
export const ADOPTED = '(adopted)';

/** Where a connection comes from, for {@link RoomHost.accept}. */
export interface ConnectionInfo {
  /**
   * The client's address (its IP, or any key: the per-address caps count connections and rooms by
   * it). Default: one shared key, `"unknown"` — give it whenever you know it.
   */
  address?: string;
  /**
   * The room the connection's URL names (`/ws/<room>`): its join must be for this room, else it is
   * dropped (`WRONG_ROOM`). Lets a load balancer route by room without reading the protocol.
   */
  room?: string;
  /**
   * Whether the transport delivers every message in order or closes (a WebSocket). Default: the
   * transport's own `reliable`.
   */
  reliable?: boolean;
}

/** Counters of a host. */
export interface HostStats {
  connections: number;
  rooms: number;
  /** Rooms waiting for players (refreshed every housekeeping round, 250 ms). */
  waitingRooms: number;
  /** Distinct client addresses connected. */
  addresses: number;
  /** Players and spectators in rooms (refreshed every housekeeping round). */
  members: number;
  messagesIn: number;
  messagesOut: number;
  bytesIn: number;
  bytesOut: number;
  /** Connections dropped for misbehaviour, silence or caps, by code. */
  dropped: Partial<Record<NetErrorCode, number>>;
  /** Liveness pings sent to silent members. */
  probes: number;
  /** Rooms closed to make way for a new one at capacity (idle or long-waiting ones). */
  evictions: number;
  /** Rooms closed because nobody played in them. */
  idleRooms: number;
  /** Time the server's updates stalled (not counted as its members' silence), ms. */
  stalledMs: number;
}

/** What every host reports. */
export type HostEvent =
  | { type: 'room-created'; room: string; game: string; players: number }
  | { type: 'room-removed'; room: string }
  | { type: 'room-closed'; room: string; code: NetErrorCode; message: string }
  | { type: 'join'; room: string; peer: number; slot: number; late: boolean }
  | { type: 'leave'; room: string; peer: number; reason: LeaveReason }
  | { type: 'drop'; connection: number; code: NetErrorCode; message: string }
  | { type: 'internal-error'; connection: number; error: unknown };

/** What a room may ask of its host (`Msg`: its protocol's messages). */
export interface RoomContext<M extends Member, Msg extends { type: string } = { type: string }> {
  readonly settings: Readonly<RoomHostSettings>;
  readonly clock: Clock;
  /** Encodes and sends a message of the host's protocol. */
  send(m: M, message: Msg): void;
  sendBytes(m: M, bytes: Uint8Array): void;
  /** A fatal error, then the connection is closed. */
  drop(m: M, code: NetErrorCode, message: string, reason?: LeaveReason): void;
  /** A violation: the first is told, more than `maxStrikes` drop the connection. */
  strike(m: M, code: NetErrorCode, message: string): void;
  /** The member leaves on its own (its seat is not held). */
  leave(m: M): void;
  /** How long `m` has been silent at server time `now`, on the responsive clock (ms). */
  silence(m: M, now: number): number;
  /** Reports an event of the room (joins, leaves) through the host. */
  emit(event: HostEvent): void;
  /** Closes a room: every connection in it is told `code` and closed, and the room removed. */
  closeRoom(room: Room<M>, code: NetErrorCode, message: string): void;
  /** A random u32 (seeds, request ids). */
  readonly randomU32: () => number;
}

/** The room a join names, and how to make it when it does not exist yet. */
export interface JoinPlan<R> extends SeatRequest {
  room: string;
  /** Makes the room (only called when admission allows a new one), or says why it cannot be. */
  create: (number: number, tokens: () => Uint8Array) => R | [NetErrorCode, string];
  /** Why an existing room does not take this join (another game), or undefined. */
  fits?: (room: R) => [NetErrorCode, string] | undefined;
  /** Why this join may not make the room (a `qm-` room is made by a match ticket only). */
  mayCreate?: [NetErrorCode, string] | undefined;
  /** Told when the join made the room (before it is seated in it). */
  created?: (room: R) => void;
}
