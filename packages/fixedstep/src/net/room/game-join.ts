/**
 * Joining a game's room — the relay's hello and state sync's join alike: the game from the catalog,
 * the room's setup from the join or, for a quick match, from its ticket.
 * @module
 */
import type { AnyGameDefinition } from '../../sim/game.js';
import type { InputSchema } from '../../sim/input-schema.js';
import type { JoinFields, NetErrorCode } from '../wire/common.js';
import type { JoinPlan } from './host-types.js';

/** What a host needs to know of a game: a game definition fits. */
export interface HostedGame {
  readonly id: string;
  readonly version: number;
  readonly tickRate: number;
  readonly minPlayers: number;
  readonly maxPlayers: number;
  /** What a player's input is: the host refuses inputs outside it. */
  readonly input: InputSchema<unknown>;
  /** The canonical option bytes of a room (sent to every client). Default: none. */
  options?(players: number, seed: number): Uint8Array;
}

/** Finds a game by id and version; a refusal says why it cannot be played. */
export type GameCatalog<G extends HostedGame = HostedGame> = (
  id: string,
  version: number,
) => G | { code: 'UNKNOWN_GAME' | 'GAME_MISMATCH'; message: string };

/** A catalog of the given games: unknown ids and other versions are refused with a reason. */
export function gameCatalog<G extends HostedGame>(
  games: readonly (G | AnyGameDefinition)[],
): GameCatalog<G> {
  return (id, version) => {
    const game = games.find((g) => g.id === id);
    if (game === undefined) {
      return { code: 'UNKNOWN_GAME', message: `no game "${id}" on this server` };
    }
    if (game.version !== version) {
      return {
        code: 'GAME_MISMATCH',
        message: `this server plays ${id} version ${game.version}, not ${version}`,
      };
    }
    return game as G;
  };
}

/**
 * A quick-match ticket, checked: the room it seats its holder in, the room's setup as the
 * matchmaker fixed it, and the holder's seat.
 */
export interface MatchTicket {
  room: string;
  game: string;
  gameVersion: number;
  players: number;
  seed: number;
  slot: number;
}

/**
 * Checks a ticket's bytes (its signature, its expiry): the ticket, or why it is refused. The
 * server's matchmaker makes them (`@fixedstep/server`'s `MatchTickets`).
 */
export type TicketVerifier = (ticket: Uint8Array) => MatchTicket | string;

/** Rooms whose names start with this are made by quick match: only a ticket makes one. */
export const MATCH_ROOM_PREFIX = 'qm-';

/** A game room's setup, from a join or a ticket. */
export interface GameRoomSetup<G extends HostedGame> {
  game: G;
  players: number;
  seed: number;
  /** Made from a ticket: its players come with tickets (or their reconnect tokens) only. */
  ticketed: boolean;
}

/** What {@link gameJoinPlan} needs besides the join. */
export interface GameJoinContext<G extends HostedGame, R> {
  catalog: GameCatalog<G>;
  tickets: TicketVerifier | undefined;
  randomU32: () => number;
  /** Makes the room (see {@link JoinPlan.create}), or says why the game cannot be set up so. */
  make: (
    setup: GameRoomSetup<G>,
    number: number,
    tokens: () => Uint8Array,
  ) => R | [NetErrorCode, string];
}

/**
 * The plan of a join (`JoinFields`): the game and input schema from the catalog, the setup (a
 * player count within the game's, the join's seed or a random one) — or, with a ticket, the room,
 * setup and seat the ticket names, which no other join can change. Returns a refusal instead when
 * the join cannot be honoured.
 */
export function gameJoinPlan<
  G extends HostedGame,
  R extends { name: string; game: G; seed: number; players: number; ticketed: boolean },
>(join: JoinFields, c: GameJoinContext<G, R>): JoinPlan<R> | [NetErrorCode, string] {
  const found = c.catalog(join.game, join.gameVersion);
  if ('code' in found) return [found.code, found.message];
  const game = found;
  if (join.input !== game.input.id) {
    return [
      'GAME_MISMATCH',
      `${game.id} takes input schema ${game.input.id}, the client sends ${join.input}`,
    ];
  }
  const sameGame = (room: R): [NetErrorCode, string] | undefined =>
    room.game.id !== game.id || room.game.version !== game.version
      ? [
          'GAME_MISMATCH',
          `room ${room.name} plays ${room.game.id} v${room.game.version}, not ${game.id} v${game.version}`,
        ]
      : undefined;
  if (join.ticket !== undefined) {
    const ticket = c.tickets?.(join.ticket) ?? 'this server takes no match tickets';
    if (typeof ticket === 'string') return ['BAD_TOKEN', `match ticket refused: ${ticket}`];
    if (ticket.room !== join.room) {
      return ['BAD_TOKEN', `the ticket is for room ${ticket.room}, not ${join.room}`];
    }
    if (ticket.game !== game.id || ticket.gameVersion !== game.version) {
      return ['GAME_MISMATCH', `the ticket is for ${ticket.game} v${ticket.gameVersion}`];
    }
    if (join.role !== 'player') return ['BAD_HELLO', 'a match ticket seats a player'];
    const setup = { game, players: ticket.players, seed: ticket.seed, ticketed: true };
    return {
      room: join.room,
      role: 'player',
      slot: ticket.slot,
      ...(join.token !== undefined ? { token: join.token } : {}),
      create: (number, tokens) => c.make(setup, number, tokens),
      fits: (room) =>
        sameGame(room) ??
        (room.ticketed && room.seed === ticket.seed && room.players === ticket.players
          ? undefined
          : ['BAD_TOKEN', `room ${room.name} is not the room of this ticket`]),
    };
  }
  const players = join.players === 0 ? game.minPlayers : join.players;
  const plan: JoinPlan<R> = {
    room: join.room,
    role: join.role,
    ...(join.token !== undefined ? { token: join.token } : {}),
    create: (number, tokens) => {
      if (players < game.minPlayers || players > game.maxPlayers) {
        return [
          'BAD_HELLO',
          `${game.id} plays ${game.minPlayers} to ${game.maxPlayers} players, not ${players}`,
        ];
      }
      const seed = join.seed ?? c.randomU32() >>> 0;
      return c.make({ game, players, seed, ticketed: false }, number, tokens);
    },
    fits: sameGame,
  };
  if (join.room.startsWith(MATCH_ROOM_PREFIX)) {
    plan.mayCreate = [
      'BAD_TOKEN',
      `rooms named ${MATCH_ROOM_PREFIX}… are made by quick match: join with the match's ticket`,
    ];
  }
  return plan;
}
