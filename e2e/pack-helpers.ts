/**
 * What the package tests share: running a program to its end, and packing workspaces with
 * `npm pack` the way a publish would (the tarballs a user installs).
 */
import { execFile } from 'node:child_process';
import { existsSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import ts from 'typescript';

/** The repository's root directory. */
export const repo = fileURLToPath(new URL('..', import.meta.url));

/** What a program run by {@link run} left. */
export interface Ran {
  code: number;
  stdout: string;
  stderr: string;
}

/** Runs a program to its end (never through a shell); resolves with its exit code and output. */
export function run(
  file: string,
  args: readonly string[],
  cwd: string,
  env: NodeJS.ProcessEnv = {},
): Promise<Ran> {
  return new Promise((resolve) => {
    execFile(
      file,
      args,
      { cwd, maxBuffer: 64 << 20, env: { ...process.env, NO_COLOR: '1', ...env } },
      (error, stdout, stderr) => {
        const code = error === null ? 0 : typeof error.code === 'number' ? error.code : 1;
        resolve({ code, stdout, stderr });
      },
    );
  });
}

/** One file of a packed tarball, as `npm pack --json` lists it. */
export interface PackedFile {
  path: string;
  size: number;
}

/** One packed tarball, as `npm pack --json` describes it, and where it was written. */
export interface Packed {
  name: string;
  filename: string;
  size: number;
  unpackedSize: number;
  files: PackedFile[];
  tarball: string;
}

/**
 * Packs `workspaces` (paths such as `packages/fixedstep`) into `destination` with `npm pack`, as
 * built: dist/ must be there (`npm run build`), and `--ignore-scripts` keeps the pack from
 * rebuilding it. Returns the tarballs by package name.
 */
export async function packWorkspaces(
  workspaces: readonly string[],
  destination: string,
): Promise<Map<string, Packed>> {
  if (!existsSync(path.join(repo, 'packages/fixedstep/dist/index.d.ts'))) {
    throw new Error('packages/fixedstep/dist is not built: run `npm run build` first.');
  }
  const pack = await run(
    'npm',
    ['pack', '--json', '--ignore-scripts', '--pack-destination', destination].concat(
      workspaces.flatMap((w) => ['-w', w]),
    ),
    repo,
  );
  if (pack.code !== 0) throw new Error(`npm pack failed:\n${pack.stderr}`);
  const packed = new Map<string, Packed>();
  for (const p of JSON.parse(pack.stdout) as Omit<Packed, 'tarball'>[]) {
    packed.set(p.name, { ...p, tarball: path.join(destination, p.filename) });
  }
  return packed;
}

/** The first ```ts block after the `<!-- readme-example` marker of a README. */
export function readmeExample(readme: string): string {
  const marker = readme.indexOf('<!-- readme-example');
  if (marker < 0) throw new Error('README has no <!-- readme-example --> marker');
  const match = /```ts\n([\s\S]*?)```/.exec(readme.slice(marker));
  if (!match?.[1]) throw new Error('README has no ```ts block after its readme-example marker');
  return match[1];
}

/** TypeScript → JavaScript with the workspace's own compiler (Node 20 runs no TypeScript). */
export function toJs(source: string): string {
  return ts.transpileModule(source, {
    compilerOptions: { module: ts.ModuleKind.ESNext, target: ts.ScriptTarget.ES2022 },
  }).outputText;
}
