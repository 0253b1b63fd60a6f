/**
 * Quick match: a queue by game and player count ({@link MatchQueue}, pure, clock injected) and
 * its WebSocket endpoint at `/match` ({@link attachMatchmaking}), which hands matched players a
 * fresh relay room. The client is `quickMatch` in fixedstep. See docs/network.md.
 * @module
 */
export { MatchQueue, DEFAULT_MATCHMAKING_LIMITS } from './queue.js';
export type {
  MatchmakingLimits,
  MatchQueueOptions,
  Match,
  MatchMember,
  JoinResult,
} from './queue.js';
export { attachMatchmaking } from './endpoint.js';
export type { MatchmakingEndpoint, MatchmakingEndpointOptions } from './endpoint.js';
