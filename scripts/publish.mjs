// Publishes every publishable workspace (each one whose package.json is not `private`), in
// dependency order, as built: run `npm run build` first (dist/ and the CLI's copy of the lab are
// what gets packed). A version already on the registry is skipped, so a rerun after a partial
// publish finishes the job. Used by the release workflow (.github/workflows/release.yml, with
// --provenance) and by e2e/registry.e2e.test.ts (with --registry, against a local Verdaccio).
//
//   node scripts/publish.mjs [--registry <url>] [--provenance] [--tag <dist-tag>] [--dry-run]
//
// Registry credentials come from npm's own configuration (.npmrc, NODE_AUTH_TOKEN in CI).
import { execFileSync, spawn } from 'node:child_process';
import { existsSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { parseArgs } from 'node:util';

const root = new URL('..', import.meta.url).pathname;

/** The publishable workspaces, dependencies before their dependents. */
export function publishable() {
  const { workspaces } = JSON.parse(readFileSync(join(root, 'package.json'), 'utf8'));
  const pkgs = workspaces
    .map((dir) => ({ dir, pkg: JSON.parse(readFileSync(join(root, dir, 'package.json'), 'utf8')) }))
    .filter(({ pkg }) => pkg.private !== true);
  const names = new Set(pkgs.map(({ pkg }) => pkg.name));
  const ordered = [];
  const placed = new Set();
  while (ordered.length < pkgs.length) {
    const next = pkgs.find(
      ({ pkg }) =>
        !placed.has(pkg.name) &&
        Object.keys(pkg.dependencies ?? {}).every((d) => !names.has(d) || placed.has(d)),
    );
    if (next === undefined) throw new Error('the workspaces depend on one another in a cycle');
    ordered.push(next);
    placed.add(next.pkg.name);
  }
  return ordered;
}

/**
 * Whether the registry has `name@version`: its packument, read once per package (one npm process
 * per `npm view` costs seconds on a busy machine). A package the registry does not know is a 404.
 */
async function isPublished(registryUrl, name, version) {
  const base = registryUrl.endsWith('/') ? registryUrl : `${registryUrl}/`;
  const res = await fetch(new URL(name.replace('/', '%2f'), base), {
    headers: { accept: 'application/vnd.npm.install-v1+json' },
  });
  if (res.status === 404) return false;
  if (!res.ok) throw new Error(`${registryUrl}: ${res.status} for ${name}`);
  const doc = await res.json();
  return Object.hasOwn(doc.versions ?? {}, version);
}

async function main() {
  const { values } = parseArgs({
    options: {
      registry: { type: 'string' },
      provenance: { type: 'boolean', default: false },
      tag: { type: 'string' },
      'dry-run': { type: 'boolean', default: false },
    },
  });
  const registry = values.registry === undefined ? [] : ['--registry', values.registry];
  const registryUrl =
    values.registry ??
    execFileSync('npm', ['config', 'get', 'registry'], { cwd: root, encoding: 'utf8' }).trim();
  for (const { dir, pkg } of publishable()) {
    const id = `${pkg.name}@${pkg.version}`;
    // Every folder the package ships (dist/, the CLI's lab/) is made by the build.
    for (const f of pkg.files ?? []) {
      if (!existsSync(join(root, dir, f))) {
        throw new Error(`${dir}/${f} is missing: run \`npm run build\` first`);
      }
    }
    if (await isPublished(registryUrl, pkg.name, pkg.version)) {
      console.log(`${id}: already published, skipped`);
      continue;
    }
    const args = ['publish', '-w', dir, '--access', 'public', ...registry];
    if (values.provenance) args.push('--provenance');
    if (values.tag !== undefined) args.push('--tag', values.tag);
    if (values['dry-run']) args.push('--dry-run');
    console.log(`${id}: npm ${args.join(' ')}`);
    // Not execFileSync: a blocked event loop never sees the registry close the idle keep-alive
    // socket of the last isPublished, and the next fetch then fails on it ("other side closed").
    await new Promise((resolve, reject) => {
      const child = spawn('npm', args, { cwd: root, stdio: 'inherit' });
      child.on('error', reject);
      child.on('exit', (code, signal) => {
        if (code === 0) resolve();
        else reject(new Error(`${id}: npm publish ended with ${code ?? signal}`));
      });
    });
  }
}

if (process.argv[1] === new URL(import.meta.url).pathname) await main();
