import { readFileSync, writeFileSync, mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, it, vi } from 'vitest';

const root = join(import.meta.dirname, '..', '..', '..');

/** The README's loop example, extracted and run as it is written. */
describe('README example', () => {
  it('runs, and prints 60 ticks and the height it promises', async () => {
    const readme = readFileSync(join(root, 'README.md'), 'utf8');
    const marker = readme.indexOf('<!-- readme-example');
    expect(marker).toBeGreaterThan(0);
    const match = /```ts\n([\s\S]*?)```/.exec(readme.slice(marker));
    expect(match).not.toBeNull();
    const dir = join(root, 'artifacts', 'readme');
    mkdirSync(dir, { recursive: true });
    const file = join(dir, 'example.ts');
    writeFileSync(file, match![1]!);
    const log = vi.spyOn(console, 'log').mockImplementation(() => undefined);
    try {
      await import(/* @vite-ignore */ file);
      expect(log).toHaveBeenCalledTimes(1);
      const [ticks, y] = log.mock.calls[0] as [number, string];
      expect(ticks).toBe(60);
      // The comment in the README states the printed height: keep them in step.
      expect(match![1]).toContain(`// 60 ${y}`);
      // And it is the height 60 steps of 1/60 s give, whatever the display.
      let vy = 5;
      let h = 0;
      for (let i = 0; i < 60; i++) {
        vy -= 9.81 / 60;
        h += vy / 60;
      }
      expect(y).toBe(h.toFixed(6));
    } finally {
      log.mockRestore();
    }
  });
});
