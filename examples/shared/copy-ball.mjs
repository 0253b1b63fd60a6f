// The recipes' `prepare` script (npm runs it on `npm install`): the three recipes play one game,
// kept once here, so each recipe gets its own copy in src/ (where `fixedstep` resolves from the
// recipe's own node_modules) instead of the repository holding three.
import { copyFileSync } from 'node:fs';

copyFileSync(new URL('./ball.ts', import.meta.url), 'src/ball.ts');
