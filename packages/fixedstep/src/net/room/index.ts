/**
 * The room core: what every server-side room kind inherits — admission by address, token-bucket
 * rates, liveness on the server's responsive time, seats held for their players, invites, idle and
 * waiting rooms closed, drain. See `host.ts`.
 * @module
 */
export { RoomHost } from './host.js';
export { GameRoomHost } from './game-host.js';
export type { ConnectionInfo, HostStats, HostEvent, RoomContext, JoinPlan } from './host-types.js';
export { Room, Member, FIRST_SPECTATOR_PEER } from './room.js';
export type { Seat, SeatRequest, MemberState, MemberInit } from './room.js';
export { TokenBucket } from './bucket.js';
export type { RateLimits } from './bucket.js';
export { LivenessClock } from './liveness.js';
export { AddressTally } from './admission.js';
export * from './options.js';
