/**
 * `create-fixedstep` (index.js) on this machine, nothing installed: each template makes a game
 * of the shared files (templates/_shared: the game, its loop and wiring) and its own drawing; an
 * unknown template, a missing folder and a folder in use get a message and exit code 2. That each
 * game installs, builds and plays is e2e/registry.e2e.test.ts's part.
 */
import { execFile } from 'node:child_process';
import { existsSync, readdirSync, readFileSync } from 'node:fs';
import { mkdir, mkdtemp, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';

const here = fileURLToPath(new URL('..', import.meta.url));
const index = path.join(here, 'index.js');
const templates = path.join(here, 'templates');
const own = JSON.parse(readFileSync(path.join(here, 'package.json'), 'utf8')) as {
  version: string;
};

interface Pkg {
  name: string;
  description: string;
  scripts: Record<string, string>;
  dependencies: Record<string, string>;
  devDependencies: Record<string, string>;
}

/** Runs index.js in `cwd` with its stdin a closed pipe (not a terminal: it never asks). */
function create(args: string[], cwd: string): Promise<{ code: number; out: string; err: string }> {
  return new Promise((resolve) => {
    const child = execFile(process.execPath, [index, ...args], { cwd }, (error, out, err) => {
      resolve({ code: error === null ? 0 : Number(error.code), out, err });
    });
    child.stdin?.end();
  });
}

/** Every file under `dir`, relative, sorted. */
function files(dir: string): string[] {
  return readdirSync(dir, { recursive: true, withFileTypes: true })
    .filter((e) => e.isFile())
    .map((e) => path.relative(dir, path.join(e.parentPath, e.name)))
    .sort();
}

let scratch: string;
beforeAll(async () => {
  scratch = await mkdtemp(path.join(os.tmpdir(), 'create-fixedstep-'));
});
afterAll(async () => {
  await rm(scratch, { recursive: true, force: true });
});

/** What each template draws with: its folder, and the engine package it adds. */
const ENGINES = { canvas: undefined, phaser: 'phaser', pixi: 'pixi.js', three: 'three' } as const;

describe('create-fixedstep', () => {
  it('has a folder for each template and one for the shared files, nothing else', () => {
    expect(readdirSync(templates).sort()).toEqual(['_shared', ...Object.keys(ENGINES)].sort());
  });

  it.each(Object.entries(ENGINES))(
    '--template %s: the shared game and wiring, the template’s drawing, versions set',
    async (template, engine) => {
      const made = await create([`My ${template} Game`, '--template', template], scratch);
      expect({ code: made.code, err: made.err }).toEqual({ code: 0, err: '' });
      expect(made.out).toContain(`from the ${template} template`);
      const dir = path.join(scratch, `My ${template} Game`);
      const mine = files(path.join(templates, template));
      const shared = files(path.join(templates, '_shared'));
      const expected = [...new Set([...mine, ...shared])]
        .map((f) => (f === '_gitignore' ? '.gitignore' : f))
        .sort();
      expect(files(dir)).toEqual(expected);
      // The game and its wiring are the shared files, byte for byte; the drawing is the template's.
      for (const f of ['src/game.ts', 'src/play.ts', 'index.html', 'tsconfig.game.json']) {
        expect(readFileSync(path.join(dir, f), 'utf8')).toBe(
          readFileSync(path.join(templates, '_shared', f), 'utf8'),
        );
      }
      expect(readFileSync(path.join(dir, 'src/main.ts'), 'utf8')).toBe(
        readFileSync(path.join(templates, template, 'src/main.ts'), 'utf8'),
      );
      const pkg = JSON.parse(readFileSync(path.join(dir, 'package.json'), 'utf8')) as Pkg;
      expect(pkg.name).toBe(`my-${template}-game`);
      expect(pkg.dependencies.fixedstep).toBe(`^${own.version}`);
      expect(pkg.devDependencies['@fixedstep/cli']).toBe(`^${own.version}`);
      const deps = Object.keys(pkg.dependencies).sort();
      expect(deps).toEqual(engine === undefined ? ['fixedstep'] : ['fixedstep', engine].sort());
    },
  );

  it('gives every template the canvas template’s scripts, TypeScript and Vite', () => {
    const read = (t: string) =>
      JSON.parse(readFileSync(path.join(templates, t, 'package.json'), 'utf8')) as Pkg;
    const canvas = read('canvas');
    expect(canvas.scripts).toEqual({
      dev: 'vite',
      build: 'tsc -p tsconfig.json && vite build && tsc -p tsconfig.game.json',
      serve: 'fixedstep serve --root dist --games ./dist-game/game.js',
      verify: 'fixedstep replay verify --games ./dist-game/game.js',
    });
    for (const t of Object.keys(ENGINES)) {
      const pkg = read(t);
      expect({ t, scripts: pkg.scripts }).toEqual({ t, scripts: canvas.scripts });
      expect(pkg.devDependencies).toMatchObject({
        typescript: canvas.devDependencies.typescript,
        vite: canvas.devDependencies.vite,
      });
    }
  });

  it('refuses an unknown template, listing the templates, with exit code 2', async () => {
    const made = await create(['nope-game', '--template', 'unity'], scratch);
    expect(made.code).toBe(2);
    expect(made.err).toContain('no template "unity"; there are:');
    for (const t of Object.keys(ENGINES)) expect(made.err).toMatch(new RegExp(`^  ${t} +\\S`, 'm'));
    expect(existsSync(path.join(scratch, 'nope-game'))).toBe(false);
  });

  it('without a folder, off a terminal: the usage, exit code 2; --help: the usage, exit 0', async () => {
    const bare = await create([], scratch);
    expect(bare.code).toBe(2);
    expect(bare.err).toContain('create-fixedstep: name a folder to create');
    expect(bare.err).toContain('npm create fixedstep@latest <dir> -- [--template <name>]');
    const help = await create(['--help'], scratch);
    expect({ code: help.code, err: help.err }).toEqual({ code: 0, err: '' });
    expect(help.out).toContain('Templates (default: canvas):');
    for (const t of Object.keys(ENGINES)) expect(help.out).toMatch(new RegExp(`^  ${t} +\\S`, 'm'));
  });

  it('refuses a folder that has files in it', async () => {
    await mkdir(path.join(scratch, 'taken'));
    await writeFile(path.join(scratch, 'taken', 'notes.txt'), 'mine\n');
    const made = await create(['taken', '--template', 'pixi'], scratch);
    expect(made.code).toBe(2);
    expect(made.err).toMatch(/taken is not empty/);
    expect(readdirSync(path.join(scratch, 'taken'))).toEqual(['notes.txt']);
  });
});
