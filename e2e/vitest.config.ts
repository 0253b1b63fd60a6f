import { fileURLToPath } from 'node:url';
import { defineConfig } from 'vitest/config';

// Browser tests: they need a built lab (`npm run build`) and Chromium (CHROMIUM_PATH, or
// /usr/bin/chromium). Run with `npm run test:e2e`.
export default defineConfig({
  resolve: { conditions: ['source'] },
  ssr: { resolve: { conditions: ['source'] } },
  test: {
    root: fileURLToPath(new URL('..', import.meta.url)),
    include: ['e2e/**/*.e2e.test.ts'],
    environment: 'node',
    testTimeout: 120_000,
    hookTimeout: 120_000,
    fileParallelism: false,
  },
});
