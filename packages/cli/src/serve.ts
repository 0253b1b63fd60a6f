import { createReadStream } from 'node:fs';
import { realpath, stat } from 'node:fs/promises';
import http from 'node:http';
import type { AddressInfo } from 'node:net';
import path from 'node:path';

/** Options of {@link startServer}. */
export interface ServeOptions {
  /** TCP port; 0 picks a free one. Default 8080. */
  port?: number;
  /** Interface to listen on. Default `127.0.0.1` (this machine only); `0.0.0.0` for the network. */
  host?: string;
  /** Directory to serve (the built lab, `apps/lab/dist`). */
  root: string;
  /** Answers API requests first (e.g. the highscore API); resolves true when it answered. */
  api?: (req: http.IncomingMessage, res: http.ServerResponse) => Promise<boolean>;
  /**
   * Directory of the built API reference (`npm run docs` writes `artifacts/api`), served at
   * `/docs/` in place of `root`'s own `docs/`. It is looked up on every request, so a reference
   * built while the server runs shows on the next reload; until then `/docs/` answers 404 with
   * the command that builds it. Not set: `/docs/` is served from `root` like any other path.
   */
  docs?: string;
}

/** A running server, from {@link startServer}. */
export interface RunningServer {
  /** Where to open it, e.g. `http://localhost:8080/`. */
  readonly url: string;
  /** The port actually bound (useful with port 0). */
  readonly port: number;
  /** The underlying HTTP server, so later endpoints (WebSocket upgrades) can share the port. */
  readonly server: http.Server;
  /** Stop listening and close open connections. */
  close(): Promise<void>;
}

const MIME: Readonly<Record<string, string>> = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json; charset=utf-8',
  '.map': 'application/json; charset=utf-8',
  '.webmanifest': 'application/manifest+json; charset=utf-8',
  '.txt': 'text/plain; charset=utf-8',
  '.md': 'text/markdown; charset=utf-8',
  '.svg': 'image/svg+xml',
  '.png': 'image/png',
  '.jpg': 'image/jpeg',
  '.jpeg': 'image/jpeg',
  '.gif': 'image/gif',
  '.webp': 'image/webp',
  '.avif': 'image/avif',
  '.ico': 'image/x-icon',
  '.wasm': 'application/wasm',
  '.woff': 'font/woff',
  '.woff2': 'font/woff2',
  '.bin': 'application/octet-stream',
};

/** The MIME type served for a file name (by extension; unknown ones are binary). */
export function mimeType(fileName: string): string {
  return MIME[path.extname(fileName).toLowerCase()] ?? 'application/octet-stream';
}

/**
 * Maps a request path to a file path under `root`, or `undefined` when it must not be served:
 * malformed escapes, NUL bytes, `..`, dot-files and encoded separators are all refused, and the
 * result is checked to lie inside `root`. A path ending in `/` means its `index.html`.
 */
export function resolveRequestPath(root: string, pathname: string): string | undefined {
  if (!pathname.startsWith('/')) return undefined;
  const parts: string[] = [];
  for (const raw of pathname.split('/')) {
    if (raw === '') continue;
    let segment: string;
    try {
      segment = decodeURIComponent(raw);
    } catch {
      return undefined;
    }
    if (segment.startsWith('.') || /[/\\\0:]/.test(segment)) return undefined;
    parts.push(segment);
  }
  if (pathname.endsWith('/')) parts.push('index.html');
  const file = path.resolve(root, ...parts);
  return isInside(root, file) ? file : undefined;
}

function isInside(root: string, file: string): boolean {
  const rel = path.relative(root, file);
  return rel !== '' && !rel.startsWith('..') && !path.isAbsolute(rel);
}

/**
 * Vite puts content-hashed files under `assets/`: they never change, so they may be cached for a
 * year. Everything else (index.html above all) is revalidated on every load.
 */
function cacheControl(rel: string): string {
  return rel.startsWith('assets/') ? 'public, max-age=31536000, immutable' : 'no-cache';
}

const SECURITY_HEADERS = {
  'X-Content-Type-Options': 'nosniff',
  'Referrer-Policy': 'no-referrer',
} as const;

/**
 * Starts a small static file server for the built lab on `node:http`: GET and HEAD only, correct
 * MIME types, `/` → `index.html`, no path traversal (nor through symlinks), 404 for anything
 * missing, ETag revalidation. Rejects with a clear message when the port is taken.
 */
export async function startServer(options: ServeOptions): Promise<RunningServer> {
  const port = options.port ?? 8080;
  const host = options.host ?? '127.0.0.1';
  if (!Number.isInteger(port) || port < 0 || port > 65535) {
    throw new RangeError(`port must be an integer from 0 to 65535, got ${String(port)}`);
  }
  let root: string;
  try {
    root = await realpath(path.resolve(options.root));
  } catch {
    throw new Error(`cannot serve ${options.root}: no such directory`);
  }
  if (!(await stat(root)).isDirectory()) {
    throw new Error(`cannot serve ${options.root}: not a directory`);
  }

  const docs = options.docs === undefined ? undefined : path.resolve(options.docs);
  const server = http.createServer((req, res) => {
    const api = options.api;
    (api ? api(req, res) : Promise.resolve(false))
      .then((answered) => (answered ? undefined : route(root, docs, req, res)))
      .catch((error: unknown) => {
        if (!res.headersSent) send(res, 500, 'Internal Server Error');
        else res.destroy();
        console.error('fixedstep serve: error while answering', req.url, error);
      });
  });

  await new Promise<void>((resolve, reject) => {
    const onError = (error: NodeJS.ErrnoException) => {
      server.off('listening', onListening);
      if (error.code === 'EADDRINUSE') {
        reject(new Error(`port ${port} on ${host} is already in use (choose another with --port)`));
      } else if (error.code === 'EACCES') {
        reject(
          new Error(`no permission to listen on port ${port} on ${host} (try a port above 1023)`),
        );
      } else if (error.code === 'EADDRNOTAVAIL' || error.code === 'ENOTFOUND') {
        reject(new Error(`cannot listen on host ${host}: no such local address`));
      } else {
        reject(error);
      }
    };
    const onListening = () => {
      server.off('error', onError);
      resolve();
    };
    server.once('error', onError);
    server.once('listening', onListening);
    server.listen(port, host);
  });

  const bound = (server.address() as AddressInfo).port;
  return {
    url: `http://${displayHost(host)}:${bound}/`,
    port: bound,
    server,
    close: () =>
      new Promise<void>((resolve, reject) => {
        server.close((error) => {
          if (error) reject(error);
          else resolve();
        });
        server.closeAllConnections();
      }),
  };
}

/** The host to print in a URL: loopback and wildcard addresses are best opened as `localhost`. */
export function displayHost(host: string): string {
  if (['127.0.0.1', '::1', '0.0.0.0', '::', 'localhost', ''].includes(host)) return 'localhost';
  return host.includes(':') ? `[${host}]` : host;
}

/** What `/docs/` answers while the API reference is not built. */
export const DOCS_NOT_BUILT =
  'The API reference is not built yet. Build it with `npm run docs` (in the fixedstep repository), then reload this page.';

/** Sends `/docs/…` to the API reference when `docs` is set, everything else to the lab. */
async function route(
  root: string,
  docs: string | undefined,
  req: http.IncomingMessage,
  res: http.ServerResponse,
): Promise<void> {
  if (req.method !== 'GET' && req.method !== 'HEAD') {
    res.setHeader('Allow', 'GET, HEAD');
    send(res, 405, 'Method Not Allowed');
    return;
  }
  const rawPath = (req.url ?? '/').split('?')[0]!.split('#')[0]!;
  if (docs === undefined || (rawPath !== '/docs' && !rawPath.startsWith('/docs/'))) {
    await handle(root, rawPath, req, res, true);
    return;
  }
  if (rawPath === '/docs') {
    res.setHeader('Location', '/docs/');
    send(res, 301, 'Moved Permanently');
    return;
  }
  let docsRoot: string;
  try {
    docsRoot = await realpath(docs);
    await stat(path.join(docsRoot, 'index.html'));
  } catch {
    send(res, 404, DOCS_NOT_BUILT);
    return;
  }
  // TypeDoc's assets/ are not content-hashed: everything under /docs/ is revalidated.
  await handle(docsRoot, rawPath.slice('/docs'.length), req, res, false);
}

async function handle(
  root: string,
  rawPath: string,
  req: http.IncomingMessage,
  res: http.ServerResponse,
  hashedAssets: boolean,
): Promise<void> {
  const file = resolveRequestPath(root, rawPath);
  if (file === undefined) {
    send(
      res,
      rawPath.startsWith('/') ? 404 : 400,
      rawPath.startsWith('/') ? 'Not Found' : 'Bad Request',
    );
    return;
  }
  let real: string;
  try {
    real = await realpath(file);
  } catch {
    send(res, 404, 'Not Found');
    return;
  }
  // A symlink inside the root must not lead outside it.
  if (!isInside(root, real)) {
    send(res, 404, 'Not Found');
    return;
  }
  const info = await stat(real);
  if (!info.isFile()) {
    send(res, 404, 'Not Found');
    return;
  }
  const etag = `W/"${info.size.toString(16)}-${Math.floor(info.mtimeMs).toString(16)}"`;
  const rel = path.relative(root, real).split(path.sep).join('/');
  res.setHeader('Content-Type', mimeType(real));
  res.setHeader('Cache-Control', hashedAssets ? cacheControl(rel) : 'no-cache');
  res.setHeader('ETag', etag);
  res.setHeader('Last-Modified', info.mtime.toUTCString());
  for (const [k, v] of Object.entries(SECURITY_HEADERS)) res.setHeader(k, v);
  if (req.headers['if-none-match'] === etag) {
    res.statusCode = 304;
    res.end();
    return;
  }
  res.setHeader('Content-Length', info.size);
  res.statusCode = 200;
  if (req.method === 'HEAD') {
    res.end();
    return;
  }
  const stream = createReadStream(real);
  stream.on('error', () => res.destroy());
  stream.pipe(res);
}

function send(res: http.ServerResponse, status: number, text: string): void {
  const body = `${status} ${text}\n`;
  res.statusCode = status;
  for (const [k, v] of Object.entries(SECURITY_HEADERS)) res.setHeader(k, v);
  res.setHeader('Content-Type', 'text/plain; charset=utf-8');
  res.setHeader('Cache-Control', 'no-store');
  res.setHeader('Content-Length', Buffer.byteLength(body));
  res.end(body);
}
