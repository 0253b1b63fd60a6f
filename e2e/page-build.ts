/**
 * How the browser tests build their own pages (the determinism page, the loss harness's page):
 * Vite, from the TypeScript sources (the `source` export condition, exactly the code the Node
 * side runs), unminified with source maps.
 */
import path from 'node:path';
import { build, defaultClientConditions } from 'vite';

/** Builds the page in `root` into `outDir` (emptied first); returns the output directory. */
export async function buildTestPage(root: string, outDir: string): Promise<string> {
  await build({
    configFile: false,
    root,
    base: './',
    logLevel: 'warn',
    resolve: { conditions: ['source', ...defaultClientConditions] },
    build: {
      outDir,
      emptyOutDir: true,
      target: 'es2022',
      minify: false,
      sourcemap: true,
      modulePreload: false,
      reportCompressedSize: false,
    },
  });
  return path.resolve(outDir);
}
