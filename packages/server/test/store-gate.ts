/**
 * Imported by the embedded database's thread before it opens the database (the store's `preload`):
 * blocks that thread — synchronously, as a slow `initdb` would — until the file named by
 * `FIXEDSTEP_TEST_STORE_GATE` exists. On the main thread it would freeze the whole server, which
 * is what the store-opening test shows does not happen.
 */
import { existsSync } from 'node:fs';
import { isMainThread } from 'node:worker_threads';

if (isMainThread) throw new Error('store-gate.ts is for the embedded database’s thread');
const file = process.env.FIXEDSTEP_TEST_STORE_GATE;
if (file === undefined) throw new Error('FIXEDSTEP_TEST_STORE_GATE is not set');
const pause = new Int32Array(new SharedArrayBuffer(4));
while (!existsSync(file)) Atomics.wait(pause, 0, 0, 5);
