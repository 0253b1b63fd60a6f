/**
 * Builds the determinism page with Vite into `e2e/determinism/dist`: the catalogue bundled from
 * the TypeScript sources (the `source` export condition), exactly the code the Node side runs.
 */
import { fileURLToPath } from 'node:url';
import path from 'node:path';
import { build, defaultClientConditions } from 'vite';

export const pageRoot = fileURLToPath(new URL('./page', import.meta.url));
export const pageDist = fileURLToPath(new URL('./dist', import.meta.url));

/** Builds the page; returns the output directory. */
export async function buildPage(): Promise<string> {
  await build({
    configFile: false,
    root: pageRoot,
    base: './',
    logLevel: 'warn',
    resolve: { conditions: ['source', ...defaultClientConditions] },
    build: {
      outDir: pageDist,
      emptyOutDir: true,
      target: 'es2022',
      minify: false,
      sourcemap: true,
      modulePreload: false,
      reportCompressedSize: false,
    },
  });
  return path.resolve(pageDist);
}
