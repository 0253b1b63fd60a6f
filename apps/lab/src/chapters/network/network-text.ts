/** What chapter 6 says: the lede, the guarantee, the bench's intro, and each session kind. */
import type { NetMode } from './network-lab.js';

export const LEDE =
  'When every machine steps the same world the same way, players only need to agree on the inputs and the clock — never send the state itself.';

export const GUARANTEE =
  'each machine sends the relay its player’s buttons for upcoming ticks; the relay puts every player’s input for a tick in one order and sends that order to everyone. Each machine then computes the whole world itself, step by step, and because a fixed step is deterministic every machine computes the same world. To prove it they send a hash of their state now and then — 8 bytes — and the relay compares them.';

export const BENCH_INTRO =
  'Two bots play the same game over the same simulated network, once with lockstep sessions and once with rollback sessions. Each panel shows both players’ machines. Move the sliders and watch input delay, rollbacks and stalls change — and the hashes stay equal.';

export const ABOUT: Readonly<Record<NetMode, { title: string; text: string }>> = {
  lockstep: {
    title: 'Lockstep',
    text: 'A machine steps tick t only once the relay has every player’s input for it. Nothing is guessed, nothing is undone; the price is an input delay of about one round trip.',
  },
  rollback: {
    title: 'Rollback',
    text: 'A machine runs ahead, guessing that the other player keeps holding the same buttons. When the real input differs it loads the saved state of that tick and steps again to now.',
  },
};

/** A panel's verdict from its readouts. */
export function verdictText(r: { checkpoint: number; equal: boolean; desyncs: number }): string {
  if (r.checkpoint < 0) return 'Connecting and syncing clocks…';
  if (r.equal) return `Both machines computed the same world at tick ${r.checkpoint}.`;
  if (r.desyncs > 0) return 'The relay saw the machines disagree: a desync.';
  return 'Waiting for both machines to reach the checkpoint…';
}
