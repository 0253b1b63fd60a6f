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
    // Three files at a time on two cores: most of an e2e file's time is waiting (on a browser's
    // frames, a server, an npm install), and each test waits on state, never on time, and holds its
    // own ports, folders and browser (scripts/busy-check.mjs runs the playing ones with every core
    // busy).
    maxWorkers: 3,
  },
});
