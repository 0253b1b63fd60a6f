import { mkdir, mkdtemp, rm, symlink, writeFile } from 'node:fs/promises';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { DOCS_NOT_BUILT, startServer, type RunningServer } from '@fixedstep/server';
import { createServer } from '../src/app.js';
import { SECURITY_HEADERS } from '../src/http/security.js';
import { closed, connect, memoryStore, request } from './helpers.js';

/** A raw GET: the path goes on the wire exactly as given (fetch would normalise `..`). */
async function get(
  port: number,
  rawPath: string,
  method = 'GET',
  headers: Record<string, string> = {},
): Promise<{ status: number; headers: http.IncomingHttpHeaders; body: string }> {
  const res = await request(port, rawPath, { method, headers });
  return { ...res, body: res.body.toString('utf8') };
}

let dir: string;
let root: string;
let server: RunningServer;

beforeAll(async () => {
  dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-serve-'));
  root = path.join(dir, 'dist');
  await mkdir(path.join(root, 'assets'), { recursive: true });
  await mkdir(path.join(root, 'docs'), { recursive: true });
  await writeFile(path.join(root, 'index.html'), '<!doctype html><title>lab</title>');
  await writeFile(path.join(root, 'assets', 'index-abc123.js'), 'console.log(1);');
  await writeFile(path.join(root, 'assets', 'index-abc123.css'), 'body{}');
  await writeFile(path.join(root, 'docs', 'index.html'), 'docs');
  await writeFile(path.join(root, 'favicon.svg'), '<svg/>');
  await writeFile(path.join(root, 'data.wasm'), 'x');
  await writeFile(path.join(root, '.env'), 'SECRET=1');
  await writeFile(path.join(dir, 'secret.txt'), 'outside the root');
  await symlink(path.join(dir, 'secret.txt'), path.join(root, 'link.txt'));
  server = await startServer({ port: 0, host: '127.0.0.1', root });
});

afterAll(async () => {
  await server.close();
  await rm(dir, { recursive: true, force: true });
});

describe('startServer', () => {
  it('binds the port it was given (0 = any) and reports the URL', () => {
    expect(server.port).toBeGreaterThan(0);
    expect(server.url).toBe(`http://localhost:${server.port}/`);
    expect(server.server.listening).toBe(true);
  });

  it('serves index.html for / and for a directory ending in /', async () => {
    const res = await get(server.port, '/');
    expect(res.status).toBe(200);
    expect(res.headers['content-type']).toBe('text/html; charset=utf-8');
    expect(res.headers['cache-control']).toBe('no-cache');
    expect(res.body).toBe('<!doctype html><title>lab</title>');
    expect((await get(server.port, '/docs/')).body).toBe('docs');
    expect((await get(server.port, '/?x=1#y')).status).toBe(200);
  });

  it('serves assets with their MIME type and long caching for hashed assets', async () => {
    const js = await get(server.port, '/assets/index-abc123.js');
    expect(js.status).toBe(200);
    expect(js.headers['content-type']).toBe('text/javascript; charset=utf-8');
    expect(js.headers['cache-control']).toBe('public, max-age=31536000, immutable');
    expect(js.headers['content-length']).toBe('15');
    expect(js.headers['x-content-type-options']).toBe('nosniff');
    expect(js.body).toBe('console.log(1);');
    const css = await get(server.port, '/assets/index-abc123.css');
    expect(css.headers['content-type']).toBe('text/css; charset=utf-8');
    const svg = await get(server.port, '/favicon.svg');
    expect(svg.headers['content-type']).toBe('image/svg+xml');
    expect(svg.headers['cache-control']).toBe('no-cache');
    expect((await get(server.port, '/data.wasm')).headers['content-type']).toBe('application/wasm');
  });

  it('answers HEAD without a body and revalidates with ETag', async () => {
    const head = await get(server.port, '/index.html', 'HEAD');
    expect(head.status).toBe(200);
    expect(head.body).toBe('');
    const etag = head.headers.etag;
    expect(etag).toMatch(/^W\/"/);
    const again = await get(server.port, '/index.html', 'GET', { 'If-None-Match': etag! });
    expect(again.status).toBe(304);
    expect(again.body).toBe('');
  });

  it('answers 404 for missing files, and redirects a directory to its slash', async () => {
    expect((await get(server.port, '/nope.js')).status).toBe(404);
    expect((await get(server.port, '/assets/nope.js')).status).toBe(404);
    const docs = await get(server.port, '/docs');
    expect(docs.status).toBe(301);
    expect(docs.headers.location).toBe('/docs/');
    expect((await get(server.port, '/assets/')).status).toBe(404);
  });

  it('refuses other methods with 405', async () => {
    const res = await get(server.port, '/', 'POST');
    expect(res.status).toBe(405);
    expect(res.headers.allow).toBe('GET, HEAD');
  });

  it.each([
    '/../secret.txt',
    '/assets/../../secret.txt',
    '/%2e%2e/secret.txt',
    '/%2E%2E/secret.txt',
    '/..%2fsecret.txt',
    '/assets/..%2F..%2Fsecret.txt',
    '/..%5csecret.txt',
    '/.env',
    '/%2eenv',
    '/index.html%00.js',
    '/%E0%A4%A',
    '/link.txt',
  ])('never serves a file outside the root or a dot-file: %s', async (rawPath) => {
    const res = await get(server.port, rawPath);
    expect([400, 403, 404]).toContain(res.status);
    expect(res.body).not.toContain('outside the root');
    expect(res.body).not.toContain('SECRET');
  });

  it('rejects a port that is already in use with a clear message', async () => {
    await expect(startServer({ port: server.port, host: '127.0.0.1', root })).rejects.toThrow(
      `port ${server.port} on 127.0.0.1 is already in use`,
    );
  });

  it('rejects a root that does not exist', async () => {
    await expect(startServer({ port: 0, root: path.join(dir, 'missing') })).rejects.toThrow(
      /no such directory/,
    );
  });
});

describe('startServer with the API reference at /docs/', () => {
  let api: string;
  let docsServer: RunningServer;

  beforeAll(async () => {
    api = path.join(dir, 'api');
    docsServer = await startServer({ port: 0, host: '127.0.0.1', root, docs: api });
  });

  afterAll(async () => {
    await docsServer.close();
  });

  it('says how to build the reference while it is not built, then serves it once it is', async () => {
    const missing = await get(docsServer.port, '/docs/');
    expect(missing.status).toBe(404);
    expect(missing.body).toBe(`404 ${DOCS_NOT_BUILT}\n`);
    expect(missing.body).toContain('npm run docs');
    // The lab's own docs/ folder is not what /docs/ serves when a reference directory is given.
    expect(missing.body).not.toBe('docs');

    // Built while the server runs: the next request finds it.
    await mkdir(path.join(api, 'assets'), { recursive: true });
    await writeFile(path.join(api, 'index.html'), '<title>api</title>');
    await writeFile(path.join(api, 'assets', 'main.js'), 'let a;');
    const index = await get(docsServer.port, '/docs/');
    expect(index.status).toBe(200);
    expect(index.body).toBe('<title>api</title>');
    expect(index.headers['content-type']).toBe('text/html; charset=utf-8');
    const js = await get(docsServer.port, '/docs/assets/main.js');
    expect(js.status).toBe(200);
    expect(js.body).toBe('let a;');
    // TypeDoc's asset names carry no content hash: revalidate, never cache for a year.
    expect(js.headers['cache-control']).toBe('no-cache');
    expect((await get(docsServer.port, '/docs/nothing.html')).status).toBe(404);
  });

  it('redirects /docs to /docs/ and keeps the lab everywhere else', async () => {
    const res = await get(docsServer.port, '/docs');
    expect(res.status).toBe(301);
    expect(res.headers.location).toBe('/docs/');
    expect((await get(docsServer.port, '/')).body).toBe('<!doctype html><title>lab</title>');
    expect((await get(docsServer.port, '/docsy')).status).toBe(404);
  });

  it.each([
    '/docs/../secret.txt',
    '/docs/%2e%2e/secret.txt',
    '/docs/..%2fsecret.txt',
    '/docs/.env',
  ])('never serves a file outside the reference: %s', async (rawPath) => {
    const res = await get(docsServer.port, rawPath);
    expect([400, 404]).toContain(res.status);
    expect(res.body).not.toContain('outside the root');
  });
});

describe('hardening', () => {
  it('answers GET // and other odd paths with 404, never 500', async () => {
    for (const p of ['//', '///x', '//..//', '/%', '/%00', '/assets//index-abc123.js/']) {
      const res = await get(server.port, p);
      expect([400, 404]).toContain(res.status);
    }
  });

  it('sends the security headers on every answer, a CSP included', async () => {
    for (const p of ['/', '/nope', '/healthz']) {
      const res = await get(server.port, p);
      for (const [k, v] of Object.entries(SECURITY_HEADERS))
        expect(res.headers[k.toLowerCase()]).toBe(v);
    }
    expect(SECURITY_HEADERS['Content-Security-Policy']).toContain("frame-ancestors 'none'");
    expect(SECURITY_HEADERS['X-Frame-Options']).toBe('DENY');
  });

  it('takes a game’s own CSP; the API reference allows its inline theme script, the lab does not', async () => {
    const own = "default-src 'self' https://cdn.example";
    const s = await createServer({
      port: 0,
      root,
      docs: root,
      relay: false,
      stateSync: false,
      signalling: false,
      contentSecurityPolicy: own,
    });
    try {
      expect((await get(s.port, '/')).headers['content-security-policy']).toBe(own);
      const docsCsp = (await get(s.port, '/docs/')).headers['content-security-policy'];
      expect(docsCsp).toContain("script-src 'self' 'unsafe-inline'");
      expect(docsCsp).toContain("frame-ancestors 'none'");
    } finally {
      await s.close();
    }
    expect(SECURITY_HEADERS['Content-Security-Policy']).toMatch(
      /script-src 'self' 'wasm-unsafe-eval';/,
    );
  });

  it('says it is alive and ready, and serves Prometheus metrics', async () => {
    expect((await get(server.port, '/healthz')).status).toBe(200);
    const ready = await get(server.port, '/readyz');
    expect(ready.status).toBe(200);
    expect(JSON.parse(ready.body)).toEqual({ ready: true, reasons: [] });
    const metrics = await get(server.port, '/metrics');
    expect(metrics.headers['content-type']).toContain('text/plain');
    expect(metrics.body).toMatch(
      /fixedstep_http_requests_total\{method="GET",route="\/healthz",status="200"\} [1-9]/,
    );
  });

  it('caps connections: idle sockets beyond the cap are closed, and the server still answers', async () => {
    const capped = await createServer({
      port: 0,
      root,
      relay: false,
      limits: { maxConnections: 5 },
    });
    const sockets = await Promise.all(Array.from({ length: 5 }, () => connect(capped.port)));
    const extra = await connect(capped.port);
    expect(await closed(extra)).toBe(''); // closed by the server at once
    for (const s of sockets) s.destroy();
    await expect
      .poll(async () => (await get(capped.port, '/healthz').catch(() => ({ status: 0 }))).status)
      .toBe(200);
    await capped.close();
  });

  it('drains on close: not ready, the store closed, the port released', async () => {
    const store = await memoryStore();
    const s = await createServer({ port: 0, root, relay: true, store });
    await s.storeReady;
    expect((await get(s.port, '/readyz')).status).toBe(200);
    const closing = s.close();
    expect(s.draining).toBe(true);
    await closing;
    await expect(get(s.port, '/healthz')).rejects.toThrow();
    await expect(store.top('runner')).rejects.toThrow();
  });

  it('is not ready while the store is opening or failed to open', async () => {
    let open: (() => void) | undefined;
    const gate = new Promise<void>((resolve) => (open = resolve));
    const s = await createServer({
      port: 0,
      root,
      relay: false,
      store: gate.then(() => memoryStore()),
    });
    const early = await get(s.port, '/readyz');
    expect(early.status).toBe(503);
    expect(early.body).toContain('the store is opening');
    const starting = await get(s.port, '/api/highscores?game=runner');
    expect(starting.status).toBe(503);
    expect(starting.headers['retry-after']).toBe('5');
    open!();
    await s.storeReady;
    expect((await get(s.port, '/readyz')).status).toBe(200);
    await s.close();
    const failed = await createServer({
      port: 0,
      root,
      relay: false,
      store: Promise.reject(new Error('no database here')),
      log: () => undefined,
    });
    await expect(failed.storeReady).rejects.toThrow('no database here');
    const res = await get(failed.port, '/readyz');
    expect(res.status).toBe(503);
    expect(res.body).toContain('no database here');
    await failed.close();
  });
});
