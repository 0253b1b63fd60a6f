// Before `tsc -b`: a package's dist holds only what its sources compile to. `tsc -b` never
// deletes an output whose source was moved or removed, and it trusts its .tsbuildinfo even when
// dist was deleted by hand; either way the packed tarball would ship a stale build. This removes
// outputs without a source and forgets the build info of a package whose dist is gone.
import { existsSync, readdirSync, rmSync } from 'node:fs';
import { join, relative } from 'node:path';

const root = new URL('..', import.meta.url).pathname;
const OUTPUT = /\.(d\.ts\.map|d\.ts|js\.map|js)$/;

function* files(dir) {
  for (const entry of readdirSync(dir, { withFileTypes: true })) {
    const p = join(dir, entry.name);
    if (entry.isDirectory()) yield* files(p);
    else yield p;
  }
}

let removed = 0;
for (const name of readdirSync(join(root, 'packages'))) {
  const pkg = join(root, 'packages', name);
  const dist = join(pkg, 'dist');
  const info = join(pkg, 'tsconfig.build.tsbuildinfo');
  if (!existsSync(join(dist, 'index.js'))) {
    rmSync(info, { force: true });
    continue;
  }
  for (const out of files(dist)) {
    const base = relative(dist, out).replace(OUTPUT, '');
    if (base === relative(dist, out)) continue;
    if (['.ts', '.tsx', '.mts'].some((ext) => existsSync(join(pkg, 'src', base + ext)))) continue;
    rmSync(out);
    removed++;
  }
}
if (removed > 0) console.log(`clean-dist: removed ${removed} outputs whose sources are gone`);
