/**
 * One frame a socket a flush: while a host updates its rooms, or handles one client message, the
 * messages it sends are held per member, then each member's go as one WebSocket frame (a batch
 * frame when several: see `WireProtocol.frame`). A write per message costs a system call and a
 * TCP segment each; this is most of a relay's cost on real sockets.
 * @module
 */
import type { WireProtocol } from '../wire/protocol.js';
import type { Member } from './room.js';

/** The messages held for members during a flush. */
export class FrameHold<M extends Member> {
  // How deep in flushes (an update may handle messages …), and the members holding messages.
  // (`held` is never shrunk: setting an array's length is a slow call on every message's path.)
  private depth = 0;
  private readonly held: (M | undefined)[] = [];
  private count = 0;

  constructor(private readonly protocol: WireProtocol<{ type: string }, object>) {}

  /** A flush begins. A protocol without batch frames holds nothing. */
  hold(): void {
    if (this.protocol.batch !== undefined) this.depth++;
  }

  /**
   * Whether `bytes` for `m` were held (else send them now). Only over a stream (a WebSocket):
   * over a lossy transport, one lost frame would lose every message in it.
   */
  add(m: M, bytes: Uint8Array): boolean {
    if (this.depth === 0 || m.transport.reliable !== true) return false;
    if (m.outgoing.length === 0) this.held[this.count++] = m;
    m.outgoing.push(bytes);
    return true;
  }

  /** A flush ends: the outermost sends each member's messages as one frame. */
  release(): void {
    if (this.protocol.batch === undefined || --this.depth > 0) return;
    // By index: a send may deliver at once (an in-memory transport) and a reply be held here.
    for (let i = 0; i < this.count; i++) {
      this.send(this.held[i]!);
      this.held[i] = undefined;
    }
    this.count = 0;
  }

  /** Sends what is held for `m` now (before its connection closes, too). */
  send(m: M): void {
    const list = m.outgoing;
    if (list.length === 0) return;
    let frame: Uint8Array;
    if (list.length === 1) {
      frame = list.pop()!;
    } else {
      frame = this.protocol.frame(list);
      list.length = 0;
    }
    if (m.transport.isOpen) m.transport.send(frame);
  }
}
