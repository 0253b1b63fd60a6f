#!/usr/bin/env node
// The `fixedstep` command: runs the compiled CLI (packages/cli/dist, built by `npm run build`).
let cli;
try {
  cli = await import('../dist/cli.js');
} catch (error) {
  if (
    error &&
    error.code === 'ERR_MODULE_NOT_FOUND' &&
    String(error.message).includes('dist/cli.js')
  ) {
    process.stderr.write('fixedstep: the CLI is not built; run: npm run build\n');
    process.exit(1);
  }
  throw error;
}
process.exitCode = await cli.run(process.argv.slice(2));
