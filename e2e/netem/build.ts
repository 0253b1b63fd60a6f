/** Builds the loss harness's page with Vite into `e2e/netem/dist` (the library from its sources). */
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { build, defaultClientConditions } from 'vite';

export const pageRoot = fileURLToPath(new URL('./page', import.meta.url));
export const pageDist = fileURLToPath(new URL('./dist', import.meta.url));

export async function buildNetemPage(): Promise<string> {
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
