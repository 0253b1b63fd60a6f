/**
 * Builds the determinism page with Vite into `e2e/determinism/dist`: the catalogue bundled from
 * the TypeScript sources (the `source` export condition), exactly the code the Node side runs.
 */
import { fileURLToPath } from 'node:url';
import { buildTestPage } from '../page-build.js';

export const pageRoot = fileURLToPath(new URL('./page', import.meta.url));
export const pageDist = fileURLToPath(new URL('./dist', import.meta.url));

/** Builds the page; returns the output directory. */
export function buildPage(): Promise<string> {
  return buildTestPage(pageRoot, pageDist);
}
