import { mkdir, mkdtemp, rm, symlink, writeFile } from 'node:fs/promises';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import {
  DOCS_NOT_BUILT,
  mimeType,
  resolveRequestPath,
  startServer,
  type RunningServer,
} from '@fixedstep/cli';

/** A raw GET: the path goes on the wire exactly as given (fetch would normalise `..`). */
function get(
  port: number,
  rawPath: string,
  method = 'GET',
  headers: Record<string, string> = {},
): Promise<{ status: number; headers: http.IncomingHttpHeaders; body: string }> {
  return new Promise((resolve, reject) => {
    const req = http.request({ host: '127.0.0.1', port, path: rawPath, method, headers }, (res) => {
      const chunks: Buffer[] = [];
      res.on('data', (c: Buffer) => chunks.push(c));
      res.on('end', () => {
        resolve({
          status: res.statusCode ?? 0,
          headers: res.headers,
          body: Buffer.concat(chunks).toString('utf8'),
        });
      });
    });
    req.on('error', reject);
    req.end();
  });
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

  it('answers 404 for missing files and directories without a trailing slash', async () => {
    expect((await get(server.port, '/nope.js')).status).toBe(404);
    expect((await get(server.port, '/assets/nope.js')).status).toBe(404);
    expect((await get(server.port, '/docs')).status).toBe(404);
    expect((await get(server.port, '/assets')).status).toBe(404);
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
    expect([400, 404]).toContain(res.status);
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

describe('resolveRequestPath', () => {
  it('maps request paths inside the root and refuses the rest', () => {
    expect(resolveRequestPath('/srv', '/')).toBe('/srv/index.html');
    expect(resolveRequestPath('/srv', '/a/b.js')).toBe('/srv/a/b.js');
    expect(resolveRequestPath('/srv', '/a%20b.js')).toBe('/srv/a b.js');
    expect(resolveRequestPath('/srv', '/a//b.js')).toBe('/srv/a/b.js');
    expect(resolveRequestPath('/srv', '/../etc/passwd')).toBeUndefined();
    expect(resolveRequestPath('/srv', '/%2e%2e/etc/passwd')).toBeUndefined();
    expect(resolveRequestPath('/srv', '/a/..%2f..%2fetc')).toBeUndefined();
    expect(resolveRequestPath('/srv', 'relative')).toBeUndefined();
  });
});

describe('mimeType', () => {
  it.each([
    ['index.html', 'text/html; charset=utf-8'],
    ['a.JS', 'text/javascript; charset=utf-8'],
    ['a.css', 'text/css; charset=utf-8'],
    ['a.json', 'application/json; charset=utf-8'],
    ['a.png', 'image/png'],
    ['a.woff2', 'font/woff2'],
    ['no-extension', 'application/octet-stream'],
  ])('%s → %s', (name, type) => {
    expect(mimeType(name)).toBe(type);
  });
});
