import { mkdtemp, readFile, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { afterAll, describe, expect, it } from 'vitest';
import type http from 'node:http';
import type { AddressInfo } from 'node:net';
import { connectNodeWebSocket } from '../src/relay/index.js';
import { recordRunner } from './replay-fixtures.js';

/**
 * The embedding examples of docs/server.md, run as written: each `server-example` block is written
 * to a module next to this file, started, sent a verified score, asked for the table, and connected
 * to its relay.
 */
const here = path.dirname(fileURLToPath(import.meta.url));
const written: string[] = [];
const dirs: string[] = [];
afterAll(async () => {
  for (const f of written) await rm(f, { force: true });
  for (const d of dirs) await rm(d, { recursive: true, force: true });
});

async function examples(): Promise<Map<string, string>> {
  const doc = await readFile(path.join(here, '../../../docs/server.md'), 'utf8');
  const found = new Map<string, string>();
  for (const m of doc.matchAll(/<!-- server-example: ([\w-]+)[^>]*-->\s*```ts\n([\s\S]*?)```/g)) {
    found.set(m[1]!, m[2]!.replace("from '@fixedstep/server'", "from '../src/index.js'"));
  }
  return found;
}

interface Started {
  server: http.Server;
  close(): Promise<void>;
}

describe('the embedding examples of docs/server.md', async () => {
  const blocks = await examples();
  it('documents node:http, express and fastify', () => {
    expect([...blocks.keys()]).toEqual(['node-http', 'express', 'fastify']);
  });

  it.each([...blocks.entries()])(
    '%s: serves verified highscores and the relay',
    async (name, code) => {
      const file = path.join(here, `.example-${name}.ts`);
      await writeFile(file, code);
      written.push(file);
      const dataDir = await mkdtemp(path.join(os.tmpdir(), `fixedstep-embed-${name}-`));
      dirs.push(dataDir);
      const mod = (await import(/* @vite-ignore */ file)) as {
        start(o: { port: number; dataDir: string }): Promise<Started>;
      };
      const started = await mod.start({ port: 0, dataDir });
      try {
        const port = (started.server.address() as AddressInfo).port;
        const base = `http://127.0.0.1:${port}`;
        const run = recordRunner(600, {}, name);
        const score = run.game.hud().score!;
        const res = await fetch(`${base}/api/highscores?score=${score}`, {
          method: 'POST',
          body: Buffer.from(run.bytes),
        });
        expect(res.status).toBe(201);
        expect(await res.json()).toMatchObject({ rank: 1, entry: { name, score } });
        const forged = await fetch(`${base}/api/highscores?score=${score + 1}`, {
          method: 'POST',
          body: Buffer.from(recordRunner(600, {}, 'eve').bytes),
        });
        expect(forged.status).toBe(409);
        const list = (await (await fetch(`${base}/api/highscores?game=runner`)).json()) as {
          entries: { name: string }[];
        };
        expect(list.entries.map((e) => e.name)).toEqual([name]);
        const transport = await connectNodeWebSocket(`ws://127.0.0.1:${port}/ws`);
        transport.close();
      } finally {
        await started.close();
      }
    },
    180_000,
  );
});
