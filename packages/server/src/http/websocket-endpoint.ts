/**
 * A WebSocket surface of the server (`/ws`, `/state`, `/signal`, `/match`): the path it owns, the
 * room its URL names, and the shared {@link Admission} — so every surface parses, admits and
 * refuses the same way, and a new one inherits it.
 * @module
 */
import type http from 'node:http';
import type { Duplex } from 'node:stream';
import { WebSocketServer, type WebSocket } from 'ws';
import { NAME_PATTERN, type WireProtocol } from 'fixedstep';
import type { Admission } from './admission.js';
import { claimUpgradePaths, shouldRefuseUpgrade } from './upgrade-paths.js';

/** Whether a surface's URL names a room: `/path/<room>` (or `/path?room=<room>`). */
export type RoomInPath = 'required' | 'optional' | 'none';

/** How a surface is reached. */
export interface WebSocketEndpointSetup {
  /** Its URL path, e.g. `/ws`. */
  path: string;
  /** Whether the URL names a room. */
  rooms: RoomInPath;
  /** Largest message a client may send (`ws` refuses a larger frame before buffering it). */
  maxPayload: number;
  admission: Admission;
  /** The protocol its clients speak: a text frame is refused with its `error` message. */
  protocol: WireProtocol<{ type: string }, object>;
}

/** The close code of a connection that sent a text frame (RFC 6455: data it cannot accept). */
export const CLOSE_UNSUPPORTED_DATA = 1003;

/** Answers a text frame: the protocol's fatal `BAD_MESSAGE`, then close code 1003. */
function refuseText(ws: WebSocket, protocol: WireProtocol<{ type: string }, object>): void {
  if (ws.readyState !== ws.OPEN) return;
  const message = `${protocol.name} messages are binary frames, not text`;
  ws.send(protocol.encode({ type: 'error', code: 'BAD_MESSAGE', fatal: true, message } as never));
  ws.close(CLOSE_UNSUPPORTED_DATA, 'binary frames only');
}

/** Where an admitted connection comes from. */
export interface UpgradeInfo {
  /** The client's address (the per-address caps' key). */
  address: string;
  /** The room the URL names, if any. */
  room?: string;
}

/** Writes an HTTP refusal on an upgrade's socket and destroys it. */
export function refuseUpgrade(socket: Duplex, status: string, reason = ''): void {
  socket.write(
    `HTTP/1.1 ${status}\r\nConnection: close\r\nContent-Type: text/plain\r\n` +
      `Content-Length: ${Buffer.byteLength(reason)}\r\n\r\n${reason}`,
  );
  socket.destroy();
}

/**
 * One WebSocket surface on an `http.Server`. Upgrades to its path are admitted (origin, address,
 * the per-address share of sockets) and become {@link connected} calls; a bad room name in the URL
 * gets 400; other paths are left to other endpoints (404 when nobody owns them). Every protocol is
 * binary: a text frame is answered here, the same on every surface — the protocol's fatal
 * `BAD_MESSAGE` error, then close code 1003 — before the surface's own handlers see it.
 */
export abstract class WebSocketEndpoint {
  readonly path: string;
  protected readonly wss: WebSocketServer;
  protected readonly admission: Admission;
  private readonly releasePaths: () => void;
  private readonly onUpgrade: (req: http.IncomingMessage, socket: Duplex, head: Buffer) => void;
  private closed: Promise<void> | undefined;

  constructor(
    protected readonly server: http.Server,
    setup: WebSocketEndpointSetup,
  ) {
    const { path, rooms } = setup;
    if (!/^\/[A-Za-z0-9_./-]*$/.test(path) || path.endsWith('/')) {
      throw new RangeError(`a WebSocket path looks like /ws, got "${path}"`);
    }
    this.path = path;
    this.admission = setup.admission;
    this.wss = new WebSocketServer({
      noServer: true,
      maxPayload: setup.maxPayload,
      perMessageDeflate: false,
    });
    const owns = (pathname: string) =>
      (rooms !== 'required' && pathname === path) ||
      (rooms !== 'none' && pathname.startsWith(`${path}/`));
    this.releasePaths = claimUpgradePaths(server, owns, rooms === 'none' ? path : `${path}/room`);
    this.onUpgrade = (req, socket, head) => {
      let url: URL;
      try {
        url = new URL(req.url ?? '/', 'http://server');
      } catch {
        refuseUpgrade(socket, '400 Bad Request', 'bad URL');
        return;
      }
      if (!owns(url.pathname)) {
        // Another endpoint may own this path; answer only when none does.
        if (shouldRefuseUpgrade(server, owns, url.pathname)) refuseUpgrade(socket, '404 Not Found');
        return;
      }
      let room: string | undefined;
      if (url.pathname === path) room = url.searchParams.get('room') ?? undefined;
      else {
        try {
          room = decodeURIComponent(url.pathname.slice(path.length + 1));
        } catch {
          room = '';
        }
      }
      if (room !== undefined && !NAME_PATTERN.test(room)) {
        refuseUpgrade(socket, '400 Bad Request', 'a room name is 1-32 of A-Z a-z 0-9 _ - .');
        return;
      }
      const admitted = this.admission.admit(req);
      if ('status' in admitted) {
        refuseUpgrade(socket, admitted.status, admitted.reason);
        return;
      }
      const refusal = this.refuses();
      if (refusal !== undefined) {
        admitted.release();
        refuseUpgrade(socket, refusal, 'not taking connections');
        return;
      }
      // A handshake that fails never opens a socket: its place is released then too.
      socket.once('close', admitted.release);
      this.wss.handleUpgrade(req, socket, head, (ws) => {
        ws.once('close', admitted.release);
        // First of its listeners: the surface's own see a text frame only after it is refused.
        ws.on('message', (_data, isBinary) => {
          if (!isBinary) refuseText(ws, setup.protocol);
        });
        this.connected(ws, { address: admitted.address, ...(room !== undefined ? { room } : {}) });
      });
    };
    server.on('upgrade', this.onUpgrade);
  }

  /** An HTTP status to refuse new connections with (closing, full), or undefined. */
  protected refuses(): string | undefined {
    return undefined;
  }

  /** An admitted WebSocket is open. */
  protected abstract connected(ws: WebSocket, info: UpgradeInfo): void;

  /** The surface's own shutdown (tell its clients, stop its timers); before the sockets close. */
  protected abstract stop(): void | Promise<void>;

  /** Stop: the surface's own shutdown, then every connection closed and the path released. */
  close(): Promise<void> {
    return (this.closed ??= (async () => {
      this.server.off('upgrade', this.onUpgrade);
      this.releasePaths();
      await this.stop();
      await new Promise<void>((resolve) => {
        for (const ws of this.wss.clients) ws.terminate();
        this.wss.close(() => {
          resolve();
        });
      });
    })());
  }
}
