/** Builds the loss harness's page with Vite into `e2e/netem/dist` (the library from its sources). */
import { fileURLToPath } from 'node:url';
import { buildTestPage } from '../page-build.js';

export const pageRoot = fileURLToPath(new URL('./page', import.meta.url));
export const pageDist = fileURLToPath(new URL('./dist', import.meta.url));

/** Builds the page; returns the output directory. */
export function buildNetemPage(): Promise<string> {
  return buildTestPage(pageRoot, pageDist);
}
