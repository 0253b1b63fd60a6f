import { defineConfig } from 'vitest/config';

export default defineConfig({
  resolve: { conditions: ['source'] },
  ssr: { resolve: { conditions: ['source'] } },
  test: {
    include: [
      'packages/*/test/**/*.test.ts',
      'apps/lab/test/**/*.test.ts',
      'bench/test/**/*.test.ts',
    ],
    environment: 'node',
    testTimeout: 60_000,
  },
});
