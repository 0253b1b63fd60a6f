import { existsSync } from 'node:fs';
import { mkdir, readFile, rename, writeFile } from 'node:fs/promises';
import http from 'node:http';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';
import { PGlite } from '@electric-sql/pglite';
import { openStore, type HighscoreStore } from '../src/store/store.js';

/**
 * A fresh embedded database in memory for a test, started from a data folder dumped once (PGlite's
 * `initdb` takes seconds; loading its dump, a second). The dump is cached in the temp folder.
 */
export async function memoryStore(): Promise<HighscoreStore> {
  return openStore({ template: await template() });
}

let cached: Promise<Blob> | undefined;
/** PGlite's freshly initialised data folder, dumped (cached across test files in the temp folder). */
export function template(): Promise<Blob> {
  return (cached ??= (async () => {
    const version = JSON.parse(
      await readFile(
        new URL('../../../node_modules/@electric-sql/pglite/package.json', import.meta.url),
        'utf8',
      ),
    ) as { version: string };
    const file = path.join(os.tmpdir(), `fixedstep-pglite-template-${version.version}.tar`);
    if (!existsSync(file)) {
      const db = await PGlite.create();
      const dump = await db.dumpDataDir('none');
      await db.close();
      await mkdir(path.dirname(file), { recursive: true });
      const tmp = `${file}.${process.pid}`;
      await writeFile(tmp, Buffer.from(await dump.arrayBuffer()));
      await rename(tmp, file);
    }
    return new Blob([await readFile(file)]);
  })());
}

/** A raw HTTP request (the path goes on the wire as given); resolves with status, headers, body. */
export function request(
  port: number,
  rawPath: string,
  options: { method?: string; headers?: Record<string, string>; body?: Uint8Array } = {},
): Promise<{ status: number; headers: http.IncomingHttpHeaders; body: Buffer }> {
  return new Promise((resolve, reject) => {
    const req = http.request(
      {
        host: '127.0.0.1',
        port,
        path: rawPath,
        method: options.method ?? 'GET',
        headers: options.headers,
        agent: false,
      },
      (res) => {
        const chunks: Buffer[] = [];
        res.on('data', (c: Buffer) => chunks.push(c));
        res.on('end', () => {
          resolve({
            status: res.statusCode ?? 0,
            headers: res.headers,
            body: Buffer.concat(chunks),
          });
        });
      },
    );
    req.on('error', reject);
    req.end(options.body === undefined ? undefined : Buffer.from(options.body));
  });
}

/** Opens a raw TCP connection; resolves once connected. */
export function connect(port: number): Promise<net.Socket> {
  return new Promise((resolve, reject) => {
    const socket = net.connect(port, '127.0.0.1', () => {
      resolve(socket);
    });
    socket.on('error', reject);
  });
}

/** Resolves when `socket` closes (the peer hung up), with what it received meanwhile. */
export function closed(socket: net.Socket): Promise<string> {
  return new Promise((resolve) => {
    let received = '';
    socket.on('data', (d: Buffer) => (received += d.toString('latin1')));
    socket.on('error', () => undefined);
    socket.on('close', () => {
      resolve(received);
    });
  });
}
