// `npm start`: install what is needed, build, and serve the lab (and its server) on one port.
// Extra arguments go to `fixedstep serve`, e.g. `npm start -- --port 9000`.
import { build, ensureDependencies, run } from './setup.mjs';

ensureDependencies();
build();
process.exit(run('node', ['packages/cli/bin/fixedstep.js', 'serve', ...process.argv.slice(2)]));
