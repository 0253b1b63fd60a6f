/**
 * The server's four WebSocket surfaces as the hostile suite (`hostile.test.ts`) sees them: how to
 * set one up alone, how a client makes and holds a room there with the least traffic that keeps
 * it, how an honest room starts, what its first and its everyday messages are.
 * @module
 */
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import {
  MATCH_PROTOCOL,
  RELAY_PROTOCOL,
  SIGNAL_PROTOCOL,
  STATE_SYNC_PROTOCOL,
  type MatchMessage,
  type NetMessage,
  type RoomHostOptions,
  type SignalMessage,
  type StateSyncMessage,
  type WireProtocol,
} from 'fixedstep';
import type { FixedstepServer, ServerOptions } from '../src/index.js';
import { GAMES, SLOW } from './hostile-games.js';
import { Peer, type AnyMessage } from './hostile-peer.js';

/**
 * A squatter's keep-alive: the least a client sends to keep its place (an ack, answers to the
 * server's pings), every this many ms — a fifth of the suite's silence timeout.
 */
export const KEEPALIVE_MS = 300;
/** An honest player's inputs (or signals), every this many ms. */
export const PLAY_MS = 100;

/** The suite's game, as every join names it. */
const GAME = { game: SLOW.id, gameVersion: SLOW.version, input: SLOW.input.id } as const;

/** The module state sync's workers load the suite's game from. */
export const GAMES_MODULE = pathToFileURL(path.join(import.meta.dirname, 'hostile-games.ts')).href;

/** createServer with no surface: each surface turns its own on. */
const NONE: ServerOptions = {
  port: 0,
  host: '127.0.0.1',
  games: GAMES,
  env: {},
  relay: false,
  stateSync: false,
  signalling: false,
  matchmaking: false,
};

/** Extras of a join (the relay's hello, state sync's join; signalling's join takes `token` as its invite). */
export interface JoinExtras {
  role?: 'player' | 'spectator';
  token?: Uint8Array;
  ticket?: Uint8Array;
  players?: number;
  seed?: number;
}

/** What the suite does with a surface whose clients meet in rooms. */
export interface RoomSurface {
  /** Whether a dropped player's seat is held for its reconnect token (signalling holds none). */
  holdsSeats: boolean;
  /** Whether it takes spectators (with the room's invite). */
  spectators: boolean;
  /** The message type that says a join is in. */
  joined: string;
  /** Rooms the surface holds now (state sync's: as the main thread knows them). */
  count(server: FixedstepServer): number;
  /** Whether the surface holds room `room` now. */
  has(server: FixedstepServer, room: string): boolean;
  /** Sends a player's join of `room` (signalling: a joiner's, `token` its invite). */
  join(peer: Peer, room: string, extras?: JoinExtras): void;
  /**
   * Makes `room` and keeps it with the least traffic that keeps it: the relay's and state sync's a
   * one-player match, acknowledged every {@link KEEPALIVE_MS} and never played; signalling's a
   * host answering pings. Resolves with `held`, or the refusal (an error code, `HTTP <status>`).
   */
  hold(peer: Peer, room: string): Promise<string>;
  /**
   * An honest room of two players (signalling: a host and its invited joiner) from `addresses`:
   * resolves once it has started, both kept alive — and, `playing`, playing. Rejects with
   * {@link Refused} when the room could not be made.
   */
  play(
    base: string,
    room: string,
    addresses: readonly [string, string],
    playing?: boolean,
  ): Promise<[Peer, Peer]>;
  /** A player's reconnect token, from its welcome. */
  token(peer: Peer): Uint8Array;
  /** The room's invite, as a player (signalling: the host) got it. */
  invite(peer: Peer): Uint8Array;
  /** A ping a member may send any time: the server answers with a pong of its `id`. */
  ping(id: number): AnyMessage;
  /** What a member sends to leave on purpose (signalling: none; closing is leaving). */
  leave(peer: Peer): AnyMessage | undefined;
}

/** One surface. */
export interface Surface {
  path: '/ws' | '/state' | '/signal' | '/match';
  protocol: WireProtocol<AnyMessage, object>;
  /** createServer options with this surface alone (quick match: with the relay its tickets are for). */
  options(host: RoomHostOptions, extra?: Partial<ServerOptions>): ServerOptions;
  /** Opens a client of `room` (quick match: of the queue) from `address`. */
  open(
    base: string,
    address: string,
    room?: string,
    headers?: Record<string, string>,
  ): Promise<Peer>;
  /** What a client sends first (its join, host or queue request). */
  hello(room: string): AnyMessage;
  /** What the server answers a good first message with. */
  welcome: string;
  /** What a client says after its first message, any number of times (flood material). */
  chatter(): AnyMessage;
  /** Rooms, for the surfaces that have them. */
  rooms?: RoomSurface;
}

const protocolOf = <M extends AnyMessage, L extends object>(p: WireProtocol<M, L>) =>
  p as unknown as WireProtocol<AnyMessage, object>;

/** Why an honest room was not made: the refusal of its first join (e.g. `SERVER_FULL`). */
export class Refused extends Error {
  constructor(readonly code: string) {
    super(`refused: ${code}`);
  }
}

/** Waits for the first join of an honest room to be `answer`ed; throws {@link Refused} if not. */
async function madeBy(peer: Peer, answer: string): Promise<void> {
  const outcome = await peer.outcome([answer]);
  if (outcome === answer) return;
  peer.close();
  throw new Refused(outcome);
}

/** The newest closed tick a relay client holds (what it acknowledges). */
function relayAck(peer: Peer): number {
  const c = peer.last('confirmed') as Extract<NetMessage, { type: 'confirmed' }> | undefined;
  return c ? c.tick + c.inputs.length / (c.players * c.words) : 0;
}

/** The newest snapshot tick a state-sync client holds (what it acknowledges). */
function stateAck(peer: Peer): number {
  const s = peer.last('snapshot') as Extract<StateSyncMessage, { type: 'snapshot' }> | undefined;
  return s ? s.tick : -1;
}

function welcomeOf(peer: Peer): {
  room: number;
  peer: number;
  slot: number;
  token: Uint8Array;
  invite: Uint8Array;
} {
  const w = peer.first('welcome') as
    | { room?: number; peer?: number; slot: number; token: Uint8Array; invite: Uint8Array }
    | undefined;
  if (w === undefined) throw new Error(`${peer.address} has no welcome`);
  return {
    room: w.room ?? 0,
    peer: w.peer ?? w.slot,
    slot: w.slot,
    token: w.token,
    invite: w.invite,
  };
}

function roomUrl(base: string, path: string, room: string | undefined): string {
  return room === undefined ? `${base}${path}` : `${base}${path}/${room}`;
}

// ------------------------------------------------------------------------------------------ /ws

/** How a game surface (the relay, state sync) differs, for {@link gameRooms}. */
interface GameRoomParts {
  open(base: string, address: string, room: string): Promise<Peer>;
  /** A player's join of `room`: the relay's hello, state sync's join. */
  join(room: string, extras?: JoinExtras): AnyMessage;
  /** The message that says the match is on: the relay's start, state sync's first snapshot. */
  started: string;
  keepAlive(peer: Peer, playing: boolean): void;
  count: (server: FixedstepServer) => number;
  has: (server: FixedstepServer, room: string) => boolean;
  ping: (id: number) => AnyMessage;
  leave: (peer: Peer) => AnyMessage;
}

/** The rooms of a game surface: seats held, spectators with the invite, joined by a welcome. */
function gameRooms(parts: GameRoomParts): RoomSurface {
  return {
    holdsSeats: true,
    spectators: true,
    joined: 'welcome',
    count: parts.count,
    has: parts.has,
    join: (peer, room, x) => {
      peer.send(parts.join(room, x));
    },
    async hold(peer, room) {
      peer.send(parts.join(room, { players: 1 }));
      const outcome = await peer.outcome([parts.started]);
      if (outcome !== parts.started) return outcome;
      parts.keepAlive(peer, false);
      return 'held';
    },
    async play(base, room, [a, b], playing = false) {
      const pa = await parts.open(base, a, room);
      pa.send(parts.join(room));
      await madeBy(pa, 'welcome');
      const pb = await parts.open(base, b, room);
      pb.send(parts.join(room));
      for (const p of [pa, pb]) {
        const outcome = await p.outcome([parts.started]);
        if (outcome !== parts.started) {
          throw new Error(`${p.address}: ${outcome}, not a ${parts.started}`);
        }
        parts.keepAlive(p, playing);
      }
      return [pa, pb];
    },
    token: (peer) => welcomeOf(peer).token,
    invite: (peer) => welcomeOf(peer).invite,
    ping: parts.ping,
    leave: parts.leave,
  };
}

/** What a join of `room` says on the relay (its hello) and on state sync (its join) alike. */
const joinFields = (room: string, x: JoinExtras) => ({
  room,
  role: x.role ?? 'player',
  ...GAME,
  players: x.players ?? 2,
  ...(x.seed !== undefined ? { seed: x.seed } : {}),
  ...(x.token ? { token: x.token } : {}),
  ...(x.ticket ? { ticket: x.ticket } : {}),
  name: 'p',
});

const relayHello = (room: string, x: JoinExtras = {}): NetMessage => ({
  type: 'hello',
  ...joinFields(room, x),
});

/** A relay member's keep-alive: answer pings, acknowledge the ticks; `playing`, send inputs too. */
function relayKeepAlive(peer: Peer, playing: boolean): void {
  peer.answerPings();
  const w = welcomeOf(peer);
  peer.every(KEEPALIVE_MS, () => {
    peer.send({ type: 'ack', room: w.room, ack: relayAck(peer) } satisfies NetMessage);
  });
  if (playing) {
    peer.every(PLAY_MS, () => {
      const tick = relayAck(peer);
      peer.send({
        type: 'input',
        room: w.room,
        player: w.slot,
        ack: tick,
        tick,
        words: 1,
        inputs: Uint32Array.of(1),
      } satisfies NetMessage);
    });
  }
}

const RELAY: Surface = {
  path: '/ws',
  protocol: protocolOf(RELAY_PROTOCOL),
  options: (host, extra = {}) => ({
    ...NONE,
    relay: { ...host, startDelayMs: 100, snapshotTimeoutMs: 100 },
    ...extra,
  }),
  open: (base, address, room, headers) =>
    Peer.open(roomUrl(base, '/ws', room), protocolOf(RELAY_PROTOCOL), address, headers),
  hello: (room) => relayHello(room),
  welcome: 'welcome',
  chatter: () => ({ type: 'ping', id: 1, time: 0 }) satisfies NetMessage,
  rooms: gameRooms({
    open: (base, address, room) => RELAY.open(base, address, room),
    join: relayHello,
    started: 'start',
    keepAlive: relayKeepAlive,
    count: (s) => s.relay!.relay.stats.rooms,
    has: (s, room) => s.relay!.relay.room(room) !== undefined,
    ping: (id) => ({ type: 'ping', id, time: 0 }) satisfies NetMessage,
    leave: (peer) => {
      const w = welcomeOf(peer);
      return { type: 'leave', room: w.room, peer: w.peer, reason: 'left' } satisfies NetMessage;
    },
  }),
};

// --------------------------------------------------------------------------------------- /state

const stateJoin = (room: string, x: JoinExtras = {}): StateSyncMessage => ({
  type: 'join',
  ...joinFields(room, x),
});

/** A state-sync member's keep-alive (the server sends no pings): acks; `playing`, inputs too. */
function stateKeepAlive(peer: Peer, playing: boolean): void {
  peer.every(KEEPALIVE_MS, () => {
    peer.send({ type: 'ack', ack: stateAck(peer) } satisfies StateSyncMessage);
  });
  if (playing) {
    const { slot } = welcomeOf(peer);
    peer.every(PLAY_MS, () => {
      const tick = stateAck(peer) + 1;
      peer.send({
        type: 'input',
        player: slot,
        ack: stateAck(peer),
        tick,
        words: 1,
        inputs: Uint32Array.of(1),
      } satisfies StateSyncMessage);
    });
  }
}

const STATE: Surface = {
  path: '/state',
  protocol: protocolOf(STATE_SYNC_PROTOCOL),
  options: (host, extra = {}) => ({
    ...NONE,
    stateSync: { games: GAMES_MODULE, workers: 1, host },
    ...extra,
  }),
  open: (base, address, room = 'lobby', headers) =>
    Peer.open(roomUrl(base, '/state', room), protocolOf(STATE_SYNC_PROTOCOL), address, headers),
  hello: (room) => stateJoin(room),
  welcome: 'welcome',
  chatter: () => ({ type: 'ping', id: 1, time: 0 }) satisfies StateSyncMessage,
  rooms: gameRooms({
    open: (base, address, room) => STATE.open(base, address, room),
    join: stateJoin,
    started: 'snapshot',
    keepAlive: stateKeepAlive,
    count: (s) => s.stateSync!.rooms().length,
    has: (s, room) => s.stateSync!.rooms().some((r) => r.room === room),
    ping: (id) => ({ type: 'ping', id, time: 0 }) satisfies StateSyncMessage,
    leave: () => ({ type: 'leave' }) satisfies StateSyncMessage,
  }),
};

// -------------------------------------------------------------------------------------- /signal

const SIGNAL: Surface = {
  path: '/signal',
  protocol: protocolOf(SIGNAL_PROTOCOL),
  options: (host, extra = {}) => ({ ...NONE, signalling: { ...host }, ...extra }),
  open: (base, address, room = 'lobby', headers) =>
    Peer.open(roomUrl(base, '/signal', room), protocolOf(SIGNAL_PROTOCOL), address, headers),
  hello: (room) => ({ type: 'host', room }) satisfies SignalMessage,
  welcome: 'joined',
  chatter: () => ({ type: 'ping', id: 1, time: 0 }) satisfies SignalMessage,
  rooms: {
    holdsSeats: false,
    spectators: false,
    joined: 'joined',
    count: (s) => s.signalling!.hub.stats.rooms,
    has: (s, room) => s.signalling!.hub.roomList().some((r) => r.room === room),
    join: (peer, room, x) => {
      peer.send({
        type: 'join',
        room,
        invite: x?.token ?? new Uint8Array(16),
      } satisfies SignalMessage);
    },
    async hold(peer, room) {
      peer.send({ type: 'host', room } satisfies SignalMessage);
      const outcome = await peer.outcome(['joined']);
      if (outcome !== 'joined') return outcome;
      peer.answerPings();
      return 'held';
    },
    async play(base, room, [a, b], playing = false) {
      const host = await SIGNAL.open(base, a, room);
      host.send({ type: 'host', room } satisfies SignalMessage);
      await madeBy(host, 'joined');
      const invite = SIGNAL.rooms!.invite(host);
      const joiner = await SIGNAL.open(base, b, room);
      joiner.send({ type: 'join', room, invite } satisfies SignalMessage);
      const outcome = await joiner.outcome(['joined']);
      if (outcome !== 'joined') throw new Error(`${b}: ${outcome}, not joined`);
      await host.until('its peer', () => host.first('peer'));
      for (const [p, to] of [
        [host, 1],
        [joiner, 0],
      ] as const) {
        p.answerPings();
        if (playing) {
          p.every(PLAY_MS, () => {
            p.send({
              type: 'signal',
              peer: to,
              kind: 'candidate',
              text: 'c',
            } satisfies SignalMessage);
          });
        }
      }
      return [host, joiner];
    },
    token: () => {
      throw new Error('signalling has no reconnect tokens');
    },
    invite: (peer) => (peer.first('joined') as unknown as { invite: Uint8Array }).invite,
    ping: (id) => ({ type: 'ping', id, time: 0 }) satisfies SignalMessage,
    leave: () => undefined,
  },
};

// --------------------------------------------------------------------------------------- /match

/** A quick-match request for the suite's game. */
export const queueRequest = (minPlayers = 2, maxPlayers = 2, timeoutMs = 60_000): MatchMessage => ({
  type: 'queue',
  ...GAME,
  minPlayers,
  maxPlayers,
  timeoutMs,
});

const MATCH: Surface = {
  path: '/match',
  protocol: protocolOf(MATCH_PROTOCOL),
  options: (host, extra = {}) => ({
    ...NONE,
    relay: { ...host, startDelayMs: 100 },
    matchmaking: {},
    ...extra,
  }),
  open: (base, address, _room, headers) =>
    Peer.open(`${base}/match`, protocolOf(MATCH_PROTOCOL), address, headers),
  hello: () => queueRequest(),
  welcome: 'queued',
  // Accepting with no match proposed does nothing: harmless, all day long.
  chatter: () => ({ type: 'accept' }) satisfies MatchMessage,
};

/** The four surfaces. */
export const SURFACES: readonly Surface[] = [RELAY, STATE, SIGNAL, MATCH];
/** The surfaces with rooms. */
export const ROOM_SURFACES = SURFACES.filter(
  (s): s is Surface & { rooms: RoomSurface } => s.rooms !== undefined,
);
export { RELAY, STATE, SIGNAL, MATCH };
