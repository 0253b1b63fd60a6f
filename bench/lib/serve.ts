/**
 * `fixedstep serve` as a process of its own, the way an operator runs it: the built CLI when there
 * is one (`npm run build`), else the sources under tsx (which holds more memory: its transpiler
 * and the sources' maps — the tables say which it was).
 * @module
 */
import { existsSync, readFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const ROOT = fileURLToPath(new URL('../../', import.meta.url));

/** The node arguments that run `fixedstep`, and how (for a table's note). */
export function fixedstepCommand(): { args: string[]; how: string } {
  const built = path.join(ROOT, 'packages/cli/dist/cli.js');
  return existsSync(built)
    ? { args: [built], how: 'built CLI' }
    : {
        args: [
          '--conditions=source',
          '--import',
          'tsx',
          path.join(ROOT, 'packages/cli/src/cli.ts'),
        ],
        how: 'sources under tsx',
      };
}

/** Resident memory of process `pid` now and at its peak, MB (Linux /proc; NaN elsewhere). */
export function residentMb(pid: number): { now: number; peak: number } {
  try {
    const status = readFileSync(`/proc/${pid}/status`, 'utf8');
    const kb = (field: string) => Number(new RegExp(`${field}:\\s+(\\d+)`).exec(status)?.[1]);
    return { now: kb('VmRSS') / 1024, peak: kb('VmHWM') / 1024 };
  } catch {
    return { now: Number.NaN, peak: Number.NaN };
  }
}
