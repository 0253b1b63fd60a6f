/**
 * One engine stepping `circlesInBoxScene(N, SEED)`, driven over stdin (see remote.ts):
 *
 *     node --conditions=source --expose-gc --import tsx peer-program.ts ENGINE N SEED
 */
import { createInterface } from 'node:readline';
import { circlesInBoxScene } from 'fixedstep';
import { sanity } from './checks.js';
import { buildEngine, ENGINES, isEngine } from './registry.js';

async function main(): Promise<void> {
  const out = (value: unknown) => process.stdout.write(`${JSON.stringify(value)}\n`);
  const [engine, n, seed] = process.argv.slice(2);
  if (engine === undefined || !isEngine(engine) || n === undefined || seed === undefined) {
    out({ ok: false, error: `usage: peer-program.ts ${ENGINES.join('|')} N SEED` });
    process.exit(2);
  }
  const scene = circlesInBoxScene(Number(n), Number(seed));
  const world = await buildEngine(engine, scene);
  out({ ok: true, info: { name: world.name, settings: world.settings, count: world.count } });
  createInterface({ input: process.stdin }).on('line', (line) => {
    const [verb, arg] = line.trim().split(' ');
    const steps = Number(arg);
    try {
      if (verb === 'settle') {
        for (let k = 0; k < steps; k++) world.step();
        out({ ok: true });
      } else if (verb === 'time') {
        const t0 = process.hrtime.bigint();
        for (let k = 0; k < steps; k++) world.step();
        out({ ok: true, ns: Number(process.hrtime.bigint() - t0) });
      } else if (verb === 'sanity') {
        out({ ok: true, sanity: sanity(world, scene) });
      } else if (verb === 'gc') {
        globalThis.gc?.();
        out({ ok: true });
      } else if (verb === 'quit') {
        world.dispose();
        process.exit(0);
      } else {
        out({ ok: false, error: `unknown command ${line}` });
      }
    } catch (e) {
      out({ ok: false, error: e instanceof Error ? e.message : String(e) });
    }
  });
}

await main();
