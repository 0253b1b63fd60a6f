#!/usr/bin/env node
// `npm create fixedstep <dir> -- --template canvas`: a new game on fixedstep, copied from
// templates/<template>, with fixedstep and @fixedstep/cli at this package's own version (they
// are released together).
import { cpSync, existsSync, readdirSync, readFileSync, renameSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';

const here = path.dirname(fileURLToPath(import.meta.url));
const templates = readdirSync(path.join(here, 'templates'));
const HELP = `create-fixedstep — a new game on fixedstep

Usage:
  npm create fixedstep@latest <dir> -- [--template <name>]
  npx create-fixedstep <dir> [--template <name>]

Templates: ${templates.join(', ')} (default: canvas)
`;

function fail(message) {
  process.stderr.write(`create-fixedstep: ${message}\n`);
  process.exit(2);
}

let parsed;
try {
  parsed = parseArgs({
    allowPositionals: true,
    options: {
      template: { type: 'string', short: 't', default: 'canvas' },
      help: { type: 'boolean', short: 'h', default: false },
    },
  });
} catch (error) {
  fail(`${error.message}\n\n${HELP}`);
}
const { values, positionals } = parsed;
if (values.help) {
  process.stdout.write(HELP);
  process.exit(0);
}
const dir = positionals[0];
if (dir === undefined || positionals.length > 1) fail(`name one folder to create\n\n${HELP}`);
if (!templates.includes(values.template)) {
  fail(`no template "${values.template}"; there are: ${templates.join(', ')}`);
}
const target = path.resolve(dir);
if (existsSync(target) && readdirSync(target).length > 0) fail(`${target} is not empty`);

cpSync(path.join(here, 'templates', values.template), target, { recursive: true });
// npm never packs a file named .gitignore: the template keeps it as _gitignore.
renameSync(path.join(target, '_gitignore'), path.join(target, '.gitignore'));
const own = JSON.parse(readFileSync(path.join(here, 'package.json'), 'utf8'));
const pkgFile = path.join(target, 'package.json');
const pkg = JSON.parse(readFileSync(pkgFile, 'utf8'));
pkg.name =
  path
    .basename(target)
    .toLowerCase()
    .replace(/[^a-z0-9._-]+/g, '-')
    .replace(/^[._-]+/, '') || 'my-game';
pkg.dependencies.fixedstep = `^${own.version}`;
pkg.devDependencies['@fixedstep/cli'] = `^${own.version}`;
writeFileSync(pkgFile, `${JSON.stringify(pkg, null, 2)}\n`);

process.stdout.write(`Created ${target} from the ${values.template} template.

Next:
  cd ${path.relative(process.cwd(), target) || '.'}
  npm install
  npm run dev      # play it: http://localhost:5173/
  npm run build    # dist/ (the page) and dist-game/game.js (the game, for the server)
  npm run serve    # highscores and online play: fixedstep serve with your game
`);
