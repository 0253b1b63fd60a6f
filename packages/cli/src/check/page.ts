/**
 * The browser side of `fixedstep check`: bundled with the user's games module into one page. It
 * asks the command for its plan, runs the input script with the very code Node runs
 * (./script.ts), posts the hashes back and, when the command asks, the state bytes of one tick.
 * Relative URLs: the command serves each browser under its own path.
 * @module
 */
import type { AnyGameDefinition } from 'fixedstep';
import { stateAt, toHex, traceGame, type CheckPlan } from './script.js';

async function post(path: string, body: unknown): Promise<unknown> {
  const res = await fetch(path, { method: 'POST', body: JSON.stringify(body) });
  return res.json();
}

function gamesOf(namespace: Record<string, unknown>): AnyGameDefinition[] {
  const picked = namespace.default ?? namespace.games;
  return (Array.isArray(picked) ? picked : [picked]) as AnyGameDefinition[];
}

/** Runs the check in this page, for the module whose namespace is `namespace`. */
export async function checkPage(namespace: Record<string, unknown>): Promise<void> {
  try {
    const plan = (await (await fetch('plan')).json()) as CheckPlan;
    const game = gamesOf(namespace).find((g) => g.id === plan.gameId);
    if (!game) throw new Error(`the bundled module has no game "${plan.gameId}"`);
    const started = performance.now();
    const result = traceGame(game, plan);
    const answer = (await post('trace', {
      ...result,
      ms: performance.now() - started,
      // The package builds without the DOM's types: the page reads the browser's global itself.
      userAgent: (globalThis as { navigator?: { userAgent?: string } }).navigator?.userAgent ?? '',
    })) as { stateAt?: number };
    if (answer.stateAt !== undefined) {
      await post('state', {
        tick: answer.stateAt,
        hex: toHex(stateAt(game, plan, answer.stateAt)),
      });
    }
  } catch (e) {
    await post('error', { message: e instanceof Error ? `${e.name}: ${e.message}` : String(e) });
  }
}
