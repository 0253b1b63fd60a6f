// `npm run docs`: the API reference of every published package (TypeDoc, typedoc.json) in
// artifacts/api, which `fixedstep serve` serves at /docs/. TypeDoc is a development dependency:
// after `npm start`, which installs only what serving needs, this installs the rest first (the
// same `npm ci` as `npm test`). Extra arguments go to TypeDoc, e.g. `npm run docs -- --out x`.
import { join } from 'node:path';
import { ensureDependencies, root, run } from './setup.mjs';

if (
  ensureDependencies('all', (command) => {
    console.log(`The reference needs the development dependencies (TypeDoc): ${command}`);
  })
) {
  console.log('Installed.');
}
process.exit(
  run(process.execPath, [join(root, 'node_modules/typedoc/bin/typedoc'), ...process.argv.slice(2)]),
);
