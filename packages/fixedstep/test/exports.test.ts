/**
 * The public names: every entry point of the published packages (fixedstep's root and its
 * sub-paths, @fixedstep/games, @fixedstep/server) read by the TypeScript checker, types included.
 * A name may be exported from several entry points only when it is the same declaration (a
 * re-export); two different things under one name — two `CorrectionSmoother` classes once — fail.
 */
import { mkdtemp, readFile, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import ts from 'typescript';
import { describe, expect, it } from 'vitest';

const repo = fileURLToPath(new URL('../../..', import.meta.url));

/** Each entry point's exported names, the declaration behind each (aliases followed). */
type Exports = Map<string, Map<string, ts.Symbol>>;

/** The exports of `entries` (label → source file), read by one TypeScript program. */
function readExports(entries: Record<string, string>): Exports {
  const program = ts.createProgram(Object.values(entries), {
    target: ts.ScriptTarget.ES2022,
    module: ts.ModuleKind.NodeNext,
    moduleResolution: ts.ModuleResolutionKind.NodeNext,
    customConditions: ['source'],
    strict: true,
    noEmit: true,
    skipLibCheck: true,
    types: ['node'],
    lib: ['lib.es2022.d.ts', 'lib.dom.d.ts'],
  });
  const checker = program.getTypeChecker();
  const out: Exports = new Map();
  for (const [label, file] of Object.entries(entries)) {
    const source = program.getSourceFile(file);
    if (source === undefined) throw new Error(`${label}: ${file} is not in the program`);
    const module = checker.getSymbolAtLocation(source);
    if (module === undefined) throw new Error(`${label}: ${file} exports nothing`);
    const names = new Map<string, ts.Symbol>();
    for (const s of checker.getExportsOfModule(module)) {
      names.set(s.name, s.flags & ts.SymbolFlags.Alias ? checker.getAliasedSymbol(s) : s);
    }
    out.set(label, names);
  }
  return out;
}

/** Names exported by two entry points as different declarations: `name: entry, entry`. */
function collisions(exports: Exports): string[] {
  const seen = new Map<string, { entry: string; symbol: ts.Symbol }[]>();
  for (const [entry, names] of exports) {
    for (const [name, symbol] of names) {
      const list = seen.get(name) ?? [];
      if (!list.some((e) => e.symbol === symbol)) list.push({ entry, symbol });
      seen.set(name, list);
    }
  }
  return [...seen]
    .filter(([, list]) => list.length > 1)
    .map(([name, list]) => `${name}: ${list.map((e) => e.entry).join(', ')}`);
}

interface PackageJson {
  name: string;
  exports: Record<string, string | { source?: string; types?: string; default?: string }>;
}

/** A package's entry points as `name/sub-path` → source file, from its package.json. */
async function entryPoints(dir: string): Promise<Record<string, string>> {
  const pkg = JSON.parse(await readFile(path.join(dir, 'package.json'), 'utf8')) as PackageJson;
  const out: Record<string, string> = {};
  for (const [sub, target] of Object.entries(pkg.exports)) {
    if (typeof target === 'string') continue; // ./package.json
    out[sub === '.' ? pkg.name : `${pkg.name}/${sub.slice(2)}`] = path.join(dir, target.source!);
  }
  return out;
}

describe('exported names', () => {
  it('fixedstep has its sub-paths beside "."; built, each lands where its types say', async () => {
    const dir = path.join(repo, 'packages/fixedstep');
    const pkg = JSON.parse(await readFile(path.join(dir, 'package.json'), 'utf8')) as PackageJson;
    expect(Object.keys(pkg.exports)).toEqual([
      '.',
      './time',
      './sim',
      './input',
      './det',
      './physics',
      './replay',
      './net',
      './testing',
      './package.json',
    ]);
    for (const [sub, target] of Object.entries(pkg.exports)) {
      if (typeof target === 'string') continue;
      const base = sub === '.' ? './src/index.ts' : `./src/${sub.slice(2)}/index.ts`;
      expect(target).toEqual({
        source: base,
        types: base.replace('./src/', './dist/').replace(/\.ts$/, '.d.ts'),
        default: base.replace('./src/', './dist/').replace(/\.ts$/, '.js'),
      });
    }
  });

  it('no name means two things in fixedstep, its sub-paths, @fixedstep/games and @fixedstep/server; the root is the union of the sub-paths', async () => {
    const entries = {
      ...(await entryPoints(path.join(repo, 'packages/fixedstep'))),
      ...(await entryPoints(path.join(repo, 'packages/games'))),
      ...(await entryPoints(path.join(repo, 'packages/server'))),
    };
    const exports = readExports(entries);
    expect(collisions(exports)).toEqual([]);

    const root = exports.get('fixedstep')!;
    const union = new Map<string, ts.Symbol>();
    for (const [entry, names] of exports) {
      if (!entry.startsWith('fixedstep/')) continue;
      expect(names.size, `${entry} exports something`).toBeGreaterThan(0);
      for (const [name, symbol] of names) union.set(name, symbol);
    }
    expect([...root.keys()].sort()).toEqual([...union.keys()].sort());
    expect([...root].filter(([name, symbol]) => symbol !== union.get(name))).toEqual([]);
    console.log(
      `public names: ${root.size} in fixedstep (${exports.size - 3} sub-paths), ` +
        `${exports.get('@fixedstep/games')!.size} in @fixedstep/games, ` +
        `${exports.get('@fixedstep/server')!.size} in @fixedstep/server`,
    );
  });

  it('fails on two declarations under one name, not on one declaration re-exported', async () => {
    const dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-exports-'));
    try {
      await writeFile(path.join(dir, 'a.ts'), 'export class Smoother {}\nexport const same = 1;\n');
      await writeFile(
        path.join(dir, 'b.ts'),
        "export class Smoother {}\nexport { same } from './a.js';\n",
      );
      const exports = readExports({ a: path.join(dir, 'a.ts'), b: path.join(dir, 'b.ts') });
      expect(collisions(exports)).toEqual(['Smoother: a, b']);
    } finally {
      await rm(dir, { recursive: true, force: true });
    }
  });
});
