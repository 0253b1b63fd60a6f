// The test files `npm test` runs with every core kept busy (scripts/busy-check.mjs) — and only
// there: its unit and e2e stages exclude them, so each runs once, under the harder conditions.

/** The browser tests that play: games by keyboard and bot, replays, recording, network play. */
export const BUSY_BROWSER_TESTS = [
  'e2e/games.e2e.test.ts',
  'e2e/replays.e2e.test.ts',
  'e2e/debugging.e2e.test.ts',
  'e2e/network.e2e.test.ts',
];

/** The unit tests that start servers and talk to them over real sockets. */
export const BUSY_UNIT_TESTS = [
  'packages/server/test/net-balancer.test.ts',
  'packages/server/test/serve.test.ts',
  'packages/server/test/state-sync-server.test.ts',
  'packages/server/test/net-endpoint.test.ts',
  'packages/server/test/net-websocket.test.ts',
  'packages/server/test/store-opening.test.ts',
  'packages/server/test/submit-retry.test.ts',
  'packages/cli/test/cli.test.ts',
];
