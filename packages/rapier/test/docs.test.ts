import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, it, vi } from 'vitest';

const root = join(import.meta.dirname, '..', '..', '..');

/** docs/rapier.md's example, extracted and run as it is written. */
describe('docs/rapier.md example', () => {
  it('runs, and prints what its comment promises: 60 ticks, the box in the air and turned', async () => {
    const doc = readFileSync(join(root, 'docs', 'rapier.md'), 'utf8');
    const marker = doc.indexOf('<!-- rapier-example');
    expect(marker).toBeGreaterThan(0);
    const match = /```ts\n([\s\S]*?)```/.exec(doc.slice(marker));
    expect(match).not.toBeNull();
    const code = match![1]!;
    const dir = join(root, 'artifacts', 'rapier-doc');
    mkdirSync(dir, { recursive: true });
    const file = join(dir, 'example.ts');
    writeFileSync(file, code);
    const log = vi.spyOn(console, 'log').mockImplementation(() => undefined);
    try {
      await import(/* @vite-ignore */ file);
      expect(log).toHaveBeenCalledTimes(1);
      const printed = (log.mock.calls[0] as unknown[]).map(String).join(' ');
      // The comment in the doc states the output: keep them in step.
      expect(code).toContain(`// ${printed}`);
      const [ticks, y, angle] = printed.split(' ').map(Number);
      expect(ticks).toBe(60);
      // A second after the start, 0.75 s after the jump: the box has risen and turned.
      expect(y).toBeGreaterThan(0.6);
      expect(Math.abs(angle!)).toBeGreaterThan(1);
    } finally {
      log.mockRestore();
    }
  });
});
