/**
 * The room core's tuning: every number named, with its reason (as Box2D's `constants.h` does).
 * @module
 */
import type { RateLimits } from './bucket.js';

/** A connection must send its join (hello) within this: clients send it at once. */
export const HELLO_TIMEOUT_MS = 5000;
/**
 * A member silent this long is pinged (a live client answers even from a background tab). A token
 * naming a seat whose connection was heard within two of these pings that connection first: if it
 * answers within one of these, it keeps its seat (a stolen token is no use while its owner plays);
 * if not, the token's bearer takes the seat (its owner, back from another network).
 */
export const PROBE_AFTER_MS = 1000;
/** A member silent this long — ten unanswered probes — is dropped and its seat held for it. */
export const SILENCE_TIMEOUT_MS = 10_000;
/**
 * A gap between two of the host's updates longer than this is the server's own stall (a long
 * collection, a blocking call): only this much of it counts as its members' silence.
 */
export const STALL_TOLERANCE_MS = 1000;
/** How often liveness, time-outs and the room counts are checked. */
export const HOUSEKEEPING_MS = 250;
/** A room whose seats are not all filled this long after it was made is closed (`TIMEOUT`). */
export const WAITING_ROOM_TTL_MS = 120_000;
/**
 * A running room where no player has played (sent an input or a signal) for this long is closed
 * (`IDLE`): keep-alives alone do not hold a room.
 */
export const IDLE_ROOM_TTL_MS = 120_000;
/**
 * At capacity, a room nobody has played in for this long makes way for a new one — the idlest,
 * of the address holding the most, first — before a new room is refused: a new honest room starts
 * within 5 s however many addresses squat the rest.
 */
export const IDLE_GRACE_MS = 5000;
/**
 * At capacity, a room still waiting for players this long after it was made makes way too — as
 * soon as an idle one does (the 5 s goal holds for rooms squatted while waiting, too).
 */
export const WAITING_GRACE_MS = 5000;
/** An empty running room is kept this long, so its players can come back with their tokens. */
export const EMPTY_ROOM_TTL_MS = 30_000;
/** A dropped player's seat is held for it this long: no stranger takes it meanwhile. */
export const SEAT_HOLD_MS = 60_000;
/** Messages a connection may send before its join (pings, inputs that overtook it). */
export const MAX_EARLY_MESSAGES = 32;

/** Rooms at once: each costs its history and a timer's share. */
export const MAX_ROOMS = 500;
/** Connections at once. */
export const MAX_CONNECTIONS = 4000;
/** Connections at once from one address: a household or a LAN party fits, a flood does not. */
export const MAX_CONNECTIONS_PER_ADDRESS = 32;
/** Rooms one address has made that still exist. */
export const MAX_ROOMS_PER_ADDRESS = 8;
/** Spectators per room. */
export const MAX_SPECTATORS = 16;
/** Violations (a tick out of its window, a bad hash tick …) a connection may commit. */
export const MAX_STRIKES = 8;

/** The default rates of every connection: a client at 144 Hz sends ~150 messages a second. */
export const DEFAULT_RATE_LIMITS: Readonly<RateLimits> = Object.freeze({
  messagesPerSecond: 240,
  messageBurst: 480,
  bytesPerSecond: 128 * 1024,
  // One full snapshot (a late joiner's, forensics) must fit.
  byteBurst: 2 << 20,
});

/** Options every room host takes (the relay's, state sync's, signalling's). */
export interface RoomHostOptions {
  /** Rooms at once. Default {@link MAX_ROOMS}. */
  maxRooms?: number;
  /** Connections at once. Default {@link MAX_CONNECTIONS}. */
  maxConnections?: number;
  /**
   * Connections at once from one client address (see `accept`'s `address`). Default
   * {@link MAX_CONNECTIONS_PER_ADDRESS}.
   */
  maxConnectionsPerAddress?: number;
  /** Rooms that connections from one address made and that still exist. Default {@link MAX_ROOMS_PER_ADDRESS}. */
  maxRoomsPerAddress?: number;
  /** Spectators per room. Default {@link MAX_SPECTATORS}. */
  maxSpectators?: number;
  /** Violations a connection may commit before it is dropped. Default {@link MAX_STRIKES}. */
  maxStrikes?: number;
  /** A connection must join within this time. Default {@link HELLO_TIMEOUT_MS}. */
  helloTimeoutMs?: number;
  /**
   * A member (or a connection joining a room) that has sent nothing for this long is dropped
   * (`TIMEOUT`) and its seat held for it. Measured on the server's responsive time: a stall of the
   * server does not count. Default {@link SILENCE_TIMEOUT_MS}.
   */
  silenceTimeoutMs?: number;
  /** A member silent this long is pinged (at most once per this interval). Default {@link PROBE_AFTER_MS}. */
  probeAfterMs?: number;
  /** A gap between updates longer than this is the server's stall. Default {@link STALL_TOLERANCE_MS}. */
  stallToleranceMs?: number;
  /** A room not full within this time after it was made is closed. Default {@link WAITING_ROOM_TTL_MS}. */
  waitingRoomTtlMs?: number;
  /** A running room nobody plays in is closed after this long. Default {@link IDLE_ROOM_TTL_MS}. */
  idleRoomTtlMs?: number;
  /** At capacity, rooms idle this long make way for a new one. Default {@link IDLE_GRACE_MS}. */
  idleGraceMs?: number;
  /** At capacity, rooms waiting this long make way for a new one. Default {@link WAITING_GRACE_MS}. */
  waitingGraceMs?: number;
  /** An empty room is removed after this long. Default {@link EMPTY_ROOM_TTL_MS}. */
  emptyRoomTtlMs?: number;
  /** A dropped player's seat is held for its token this long. Default {@link SEAT_HOLD_MS}. */
  seatHoldMs?: number;
  /** Per-connection rates (token buckets). Default {@link DEFAULT_RATE_LIMITS}. */
  rate?: Partial<RateLimits>;
  /**
   * A source of random u32s for seeds, reconnect and invite tokens. Default: the platform's
   * cryptographic source. Inject a seeded one in tests (tokens then become guessable).
   */
  randomU32?: () => number;
}

/** {@link RoomHostOptions} with every default filled in. */
export type RoomHostSettings = Required<Omit<RoomHostOptions, 'rate' | 'randomU32'>> & {
  rate: RateLimits;
};

/** The settings of `options`, checked (a RangeError names a bad one). */
export function roomHostSettings(who: string, options: RoomHostOptions): RoomHostSettings {
  const s: RoomHostSettings = {
    maxRooms: options.maxRooms ?? MAX_ROOMS,
    maxConnections: options.maxConnections ?? MAX_CONNECTIONS,
    maxConnectionsPerAddress: options.maxConnectionsPerAddress ?? MAX_CONNECTIONS_PER_ADDRESS,
    maxRoomsPerAddress: options.maxRoomsPerAddress ?? MAX_ROOMS_PER_ADDRESS,
    maxSpectators: options.maxSpectators ?? MAX_SPECTATORS,
    maxStrikes: options.maxStrikes ?? MAX_STRIKES,
    helloTimeoutMs: options.helloTimeoutMs ?? HELLO_TIMEOUT_MS,
    silenceTimeoutMs: options.silenceTimeoutMs ?? SILENCE_TIMEOUT_MS,
    probeAfterMs: options.probeAfterMs ?? PROBE_AFTER_MS,
    stallToleranceMs: options.stallToleranceMs ?? STALL_TOLERANCE_MS,
    waitingRoomTtlMs: options.waitingRoomTtlMs ?? WAITING_ROOM_TTL_MS,
    idleRoomTtlMs: options.idleRoomTtlMs ?? IDLE_ROOM_TTL_MS,
    idleGraceMs: options.idleGraceMs ?? IDLE_GRACE_MS,
    waitingGraceMs: options.waitingGraceMs ?? WAITING_GRACE_MS,
    emptyRoomTtlMs: options.emptyRoomTtlMs ?? EMPTY_ROOM_TTL_MS,
    seatHoldMs: options.seatHoldMs ?? SEAT_HOLD_MS,
    rate: { ...DEFAULT_RATE_LIMITS, ...options.rate },
  };
  const numbers: [string, number][] = [
    ...Object.entries(s).filter((e): e is [string, number] => typeof e[1] === 'number'),
    ...Object.entries(s.rate as unknown as Record<string, number>).map(
      ([k, v]): [string, number] => [`rate.${k}`, v],
    ),
  ];
  for (const [k, v] of numbers) {
    if (!(typeof v === 'number' && v >= 0 && !Number.isNaN(v))) {
      throw new RangeError(`${who}: ${k} must be a number >= 0, got ${String(v)}`);
    }
  }
  return s;
}
