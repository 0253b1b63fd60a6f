/**
 * Quick match: a queue by game and player count with a ready check ({@link MatchQueue}, pure, clock
 * injected), the tickets that seat matched players in their relay room ({@link MatchTickets}), and
 * the WebSocket endpoint at `/match` ({@link attachMatchmaking}). The client is `quickMatch` in
 * fixedstep. See docs/network.md.
 * @module
 */
export {
  MatchQueue,
  DEFAULT_MATCHMAKING_LIMITS,
  ACCEPT_MS,
  FILL_WINDOW_MS,
  isLoopbackKey,
} from './queue.js';
export type {
  MatchmakingLimits,
  MatchQueueOptions,
  Match,
  MatchMember,
  JoinResult,
  Proposal,
  SweepResult,
} from './queue.js';
export { MatchTickets, TICKET_LIFETIME_MS } from './tickets.js';
export type { MatchTicketsOptions } from './tickets.js';
export {
  attachMatchmaking,
  MatchEndpoint,
  MATCH_SWEEP_MS,
  MATCH_REQUEST_TIMEOUT_MS,
} from './endpoint.js';
export type { MatchmakingEndpointOptions } from './endpoint.js';
