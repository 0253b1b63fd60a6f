import { defineConfig } from 'vite';

// three.js is one module: the page's script is about 640 kB (170 kB gzipped), over the 500 kB at
// which Vite warns that a chunk is large. The warning would say nothing you can act on here.
export default defineConfig({ build: { chunkSizeWarningLimit: 1000 } });
