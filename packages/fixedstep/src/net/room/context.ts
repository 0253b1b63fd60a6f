/**
 * What a host hands its rooms (see {@link RoomContext}): a class whose methods live on its
 * prototype, each a call into the host.
 *
 * Why not an object of arrow functions: every message of every match goes through `send`, and
 * optimised code that calls a closure embeds that closure. When its host is collected (a test, a
 * benchmark round, a server that replaces its relay) that code is thrown away and every hot path
 * warms up again; a prototype method outlives any one host.
 * @module
 */
import type { Clock } from '../../time/drivers.js';
import type { LeaveReason, NetErrorCode } from '../wire/common.js';
import type { HostEvent, RoomContext } from './host-types.js';
import type { RoomHostSettings } from './options.js';
import type { LivenessClock } from './liveness.js';
import type { Member, Room } from './room.js';

/** The parts of a `RoomHost` its context calls (protected or private there). */
export interface HostInternals<M extends Member, Msg extends { type: string }> {
  readonly liveness: LivenessClock;
  readonly random: () => number;
  send(m: M, message: Msg): void;
  sendBytes(m: M, bytes: Uint8Array): void;
  drop(m: M, code: NetErrorCode, message: string, reason?: LeaveReason, count?: boolean): void;
  strike(m: M, code: NetErrorCode, message: string): void;
  removeMember(m: M, reason: LeaveReason): void;
  sendFrame(m: M): void;
  emit(event: HostEvent): void;
  closeRoom(room: Room<M>, code: NetErrorCode, message: string): void;
}

/** A host's {@link RoomContext}. */
export class HostRoomContext<M extends Member, Msg extends { type: string }> implements RoomContext<
  M,
  Msg
> {
  readonly randomU32: () => number;
  constructor(
    private readonly host: HostInternals<M, Msg>,
    readonly settings: Readonly<RoomHostSettings>,
    readonly clock: Clock,
  ) {
    this.randomU32 = () => host.random() >>> 0;
  }
  send(m: M, message: Msg): void {
    this.host.send(m, message);
  }
  sendBytes(m: M, bytes: Uint8Array): void {
    this.host.sendBytes(m, bytes);
  }
  drop(m: M, code: NetErrorCode, message: string, reason?: LeaveReason): void {
    // A connection replaced by its player's reconnect did nothing wrong: not counted.
    this.host.drop(m, code, message, reason, reason !== 'replaced');
  }
  strike(m: M, code: NetErrorCode, message: string): void {
    this.host.strike(m, code, message);
  }
  leave(m: M): void {
    this.host.removeMember(m, 'left');
    this.host.sendFrame(m);
    m.transport.close('left');
  }
  silence(m: M, now: number): number {
    return this.host.liveness.at(now) - m.heardAt;
  }
  emit(event: HostEvent): void {
    this.host.emit(event);
  }
  closeRoom(room: Room<M>, code: NetErrorCode, message: string): void {
    this.host.closeRoom(room, code, message);
  }
}
