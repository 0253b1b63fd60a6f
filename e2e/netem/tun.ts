/**
 * The kernel's TCP over a lossy link, in a network namespace of the run's own: `runOverTun` makes
 * the namespace, runs tun-child.ts in it (the rooms, both players, and tun-link.py's TUN link) and
 * deletes the namespace when it ends, whatever happened. Needs root, `ip`, python3 and
 * /dev/net/tun; `findTunSupport` says why not otherwise.
 */
import { spawn, spawnSync } from 'node:child_process';
import { existsSync } from 'node:fs';
import { createInterface } from 'node:readline';
import { fileURLToPath } from 'node:url';
import type { Impairment } from './impair.js';
import type { Model, ModelRow } from './model-match.js';

const child = fileURLToPath(new URL('./tun-child.ts', import.meta.url));

/** Whether this machine can run the TUN link, or why not. */
export function findTunSupport(): { ok: true } | { ok: false; reason: string } {
  if (process.getuid?.() !== 0) return { ok: false, reason: 'network namespaces need root' };
  if (!existsSync('/dev/net/tun')) return { ok: false, reason: 'no /dev/net/tun' };
  for (const [cmd, arg] of [
    ['ip', '-V'],
    ['python3', '--version'],
  ] as const) {
    if (spawnSync(cmd, [arg]).status !== 0) return { ok: false, reason: `no ${cmd}` };
  }
  return { ok: true };
}

let made = 0;

/** Plays each model over the TUN link with `link`'s conditions; rows in `models`' order. */
export async function runOverTun(o: {
  models: readonly Model[];
  seconds: number;
  link: Impairment;
  seed: number;
}): Promise<ModelRow[]> {
  const ns = `fixedstep-${process.pid}-${made++}`;
  const ip = (...args: string[]) => {
    const r = spawnSync('ip', args, { encoding: 'utf8' });
    if (r.status !== 0) throw new Error(`ip ${args.join(' ')}: ${r.stderr.trim()}`);
  };
  ip('netns', 'add', ns);
  try {
    ip('netns', 'exec', ns, 'ip', 'link', 'set', 'lo', 'up');
    const proc = spawn(
      'ip',
      [
        'netns',
        'exec',
        ns,
        process.execPath,
        '--conditions=source',
        '--import',
        'tsx',
        child,
        JSON.stringify(o),
      ],
      { stdio: ['ignore', 'pipe', 'pipe'] },
    );
    const rows: ModelRow[] = [];
    let errors = '';
    proc.stderr.on('data', (d: Buffer) => {
      errors = (errors + d.toString()).slice(-4000);
    });
    createInterface({ input: proc.stdout }).on('line', (line) => {
      if (line.startsWith('row ')) rows.push(JSON.parse(line.slice(4)) as ModelRow);
    });
    const code = await new Promise<number | null>((resolve) => {
      const limit = setTimeout(
        () => proc.kill('SIGKILL'),
        (o.seconds + 60) * 1000 * o.models.length,
      );
      proc.once('exit', (c) => {
        clearTimeout(limit);
        resolve(c);
      });
    });
    proc.stdout.destroy();
    proc.stderr.destroy();
    if (code !== 0 || rows.length !== o.models.length) {
      throw new Error(`the TUN match ended with ${String(code)}:\n${errors}`);
    }
    return rows;
  } finally {
    // Deleting the namespace also removes its TUN device and anything left bound in it.
    spawnSync('ip', ['netns', 'del', ns]);
  }
}
