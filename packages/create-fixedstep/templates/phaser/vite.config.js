import { defineConfig } from 'vite';

// Phaser is one module: the page's script is about 1.5 MB (410 kB gzipped), over the 500 kB at
// which Vite warns that a chunk is large. The warning would say nothing you can act on here.
export default defineConfig({ build: { chunkSizeWarningLimit: 2000 } });
