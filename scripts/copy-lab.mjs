// The last step of `npm run build`: the built lab (apps/lab/dist) copied into the CLI package
// (packages/cli/lab), so that `fixedstep serve` installed from the registry serves it with nothing
// to build. Source maps stay behind: they are most of the lab's size and only a developer of the
// lab, who has the repository, reads them.
import { cpSync, existsSync, rmSync } from 'node:fs';
import { join } from 'node:path';

const root = new URL('..', import.meta.url).pathname;
const from = join(root, 'apps/lab/dist');
const to = join(root, 'packages/cli/lab');
if (!existsSync(join(from, 'index.html'))) {
  console.error('copy-lab: apps/lab/dist has no index.html; build the lab first');
  process.exit(1);
}
rmSync(to, { recursive: true, force: true });
cpSync(from, to, { recursive: true, filter: (src) => !src.endsWith('.map') });
console.log(`copy-lab: ${from} → ${to}`);
