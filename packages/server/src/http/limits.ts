import { readFileSync } from 'node:fs';

/** The HTTP server's limits; every field has a default (see {@link DEFAULT_HTTP_LIMITS}). */
export interface HttpLimits {
  /**
   * Most open connections (HTTP and WebSocket together); further ones are closed at once. Default:
   * the process's open-file limit less 256 (kept for the database, the workers and the files
   * served), at most 10 000 — so a flood of idle sockets cannot exhaust file descriptors (EMFILE).
   */
  maxConnections: number;
  /**
   * Most open connections from one client address (HTTP and WebSocket together, counted from the
   * moment they connect, before a byte of the request is read); further ones are closed at once —
   * so one address's half-sent requests cannot fill {@link maxConnections}. A trusted proxy's
   * connections are not counted (every client behind it shares its address). Default 96: an
   * address's share of WebSockets (`MAX_SOCKETS_PER_ADDRESS`) and a few browsers' HTTP connections.
   */
  maxConnectionsPerAddress: number;
  /** The request line and headers must arrive within this many ms. Default 10 000. */
  headersTimeoutMs: number;
  /**
   * The whole request, body included, must arrive within this many ms; a slower one is answered
   * 408 and its connection closed. Default 15 000 (a 1 MiB replay at 1 Mbit/s takes 8.4 s).
   */
  requestTimeoutMs: number;
  /** An idle keep-alive connection is closed after this many ms. Default 5 000. */
  keepAliveTimeoutMs: number;
  /** A connection with no traffic at all for this many ms is closed. Default 30 000. */
  idleTimeoutMs: number;
  /** Largest request body, in bytes. Default 1 MiB (the largest replay). */
  maxBodyBytes: number;
}

/** The process's soft limit of open files, from /proc (Linux), or undefined. */
export function openFileLimit(): number | undefined {
  try {
    const line = /^Max open files\s+(\d+|unlimited)/m.exec(
      readFileSync('/proc/self/limits', 'utf8'),
    );
    if (line?.[1] === undefined || line[1] === 'unlimited') return undefined;
    return Number(line[1]);
  } catch {
    return undefined;
  }
}

function defaultMaxConnections(): number {
  const files = openFileLimit();
  return files === undefined ? 4096 : Math.max(64, Math.min(10_000, files - 256));
}

/** The defaults of {@link HttpLimits}. */
export const DEFAULT_HTTP_LIMITS: Readonly<HttpLimits> = Object.freeze({
  maxConnections: defaultMaxConnections(),
  maxConnectionsPerAddress: 96,
  headersTimeoutMs: 10_000,
  requestTimeoutMs: 15_000,
  keepAliveTimeoutMs: 5_000,
  idleTimeoutMs: 30_000,
  maxBodyBytes: 1024 * 1024,
});
