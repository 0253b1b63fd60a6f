import { fileURLToPath } from 'node:url';
import { defaultClientConditions, defineConfig } from 'vite';

// The lab imports `fixedstep` and `@fixedstep/games` by package name, like any user would; the
// `source` export condition resolves them to their TypeScript sources, so no build step between.
export default defineConfig({
  root: fileURLToPath(new URL('.', import.meta.url)),
  base: './',
  resolve: { conditions: ['source', ...defaultClientConditions] },
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    target: 'es2022',
    sourcemap: true,
    // Chapter 10 loads Rapier's deterministic build on demand: one chunk of ~2.2 MB (its
    // WebAssembly inlined as base64, so it works offline). Every other chunk stays far below this.
    chunkSizeWarningLimit: 2400,
  },
});
