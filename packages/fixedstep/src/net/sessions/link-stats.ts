/**
 * What every networked session counts of its link to the server, whatever its kind (the relay
 * sessions' {@link NetSessionStats}, the state-sync session's {@link StateSyncSessionStats}).
 * @module
 */

/** A session's link to the server: the round trip, and the messages and bytes each way. */
export interface LinkStats {
  /** Round trip to the server, ms: the smallest and a high one of the window. */
  rtt: number;
  rttHigh: number;
  messagesSent: number;
  messagesReceived: number;
  bytesSent: number;
  bytesReceived: number;
}

/** A link's counters at the start: all zero. */
export function emptyLinkStats(): LinkStats {
  return {
    rtt: 0,
    rttHigh: 0,
    messagesSent: 0,
    messagesReceived: 0,
    bytesSent: 0,
    bytesReceived: 0,
  };
}
