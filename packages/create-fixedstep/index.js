#!/usr/bin/env node
// `npm create fixedstep <dir> -- --template <name>`: a new game on fixedstep. A game is
// templates/_shared (the game itself — src/game.ts — and src/play.ts, its loop, input, replay,
// highscores and online play) with templates/<name> over it (src/main.ts, which draws it, and the
// package.json and tsconfig.json that go with the renderer). fixedstep and @fixedstep/cli are
// set to this package's own version (they are released together).
import { cpSync, existsSync, readdirSync, readFileSync, renameSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { createInterface } from 'node:readline/promises';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';

const here = path.dirname(fileURLToPath(import.meta.url));
const SHARED = '_shared';
/** Each template folder and what draws it; a folder without a line here is an error. */
const DESCRIPTIONS = {
  canvas: 'plain <canvas> 2D, no engine',
  phaser: 'Phaser 4: a scene of game objects',
  pixi: 'PixiJS 8: Graphics on the stage',
  three: 'three.js: meshes under an orthographic camera',
};
const DEFAULT_TEMPLATE = 'canvas';
const templates = readdirSync(path.join(here, 'templates'))
  .filter((name) => name !== SHARED)
  .sort((a, b) => a.localeCompare(b));
for (const name of templates) {
  if (!(name in DESCRIPTIONS)) throw new Error(`templates/${name} has no description`);
}
const LIST = templates.map((name) => `  ${name.padEnd(8)}${DESCRIPTIONS[name]}`).join('\n');
const HELP = `create-fixedstep — a new game on fixedstep

Usage:
  npm create fixedstep@latest <dir> -- [--template <name>]
  npx create-fixedstep <dir> [--template <name>]

Templates (default: ${DEFAULT_TEMPLATE}):
${LIST}

Every template is the same game, wired the same way: an input schema, the fixed-step loop, a
replay (download it; npm run verify), a highscore table and online play (npm run serve).
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
      template: { type: 'string', short: 't' },
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
if (positionals.length > 1) fail(`name one folder to create\n\n${HELP}`);
let dir = positionals[0];
let template = values.template;
if (dir === undefined) {
  // Without a folder: ask, on a terminal; elsewhere (a script, CI) say how to call it.
  if (!process.stdin.isTTY || !process.stdout.isTTY) fail(`name a folder to create\n\n${HELP}`);
  const rl = createInterface({ input: process.stdin, output: process.stdout });
  dir = (await rl.question('Folder for the new game (my-game): ')).trim() || 'my-game';
  if (template === undefined) {
    process.stdout.write(`Templates:\n${LIST}\n`);
    const answer = await rl.question(`Template (${DEFAULT_TEMPLATE}): `);
    template = answer.trim() || DEFAULT_TEMPLATE;
  }
  rl.close();
}
template ??= DEFAULT_TEMPLATE;
if (!templates.includes(template)) {
  fail(`no template "${template}"; there are:\n${LIST}`);
}
const target = path.resolve(dir);
if (existsSync(target) && readdirSync(target).length > 0) fail(`${target} is not empty`);

cpSync(path.join(here, 'templates', SHARED), target, { recursive: true });
cpSync(path.join(here, 'templates', template), target, { recursive: true });
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

process.stdout.write(`Created ${target} from the ${template} template (${DESCRIPTIONS[template]}).

Next:
  cd ${path.relative(process.cwd(), target) || '.'}
  npm install
  npm run dev      # play it: http://localhost:5173/
  npm run build    # dist/ (the page) and dist-game/game.js (the game, for the server)
  npm run serve    # highscores and online play: fixedstep serve with your game
`);
