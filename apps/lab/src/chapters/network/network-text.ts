/**
 * What chapter 6 says: the lede, the two ways to agree, the bench's intro, each model, what each
 * needs from the game, and when to use which. Numbers come from the model (network-model.ts).
 */
import type { ModelNumbers, NetMode } from './network-model.js';

export const LEDE =
  'With a fixed step it is enough to synchronise the state of the world and the clock — or, when every machine computes the same world, only the inputs and the clock.';

export const GUARANTEE =
  'with state sync the server runs the game and sends each machine the world — only what changed since the snapshot that machine last confirmed — with the server’s tick and time; machines send nothing but their buttons, so nobody can change the world except by playing. With lockstep and rollback the relay only puts everyone’s buttons in one order; each machine computes the whole world itself, and because a fixed step is deterministic they all compute the same one — an 8-byte hash now and then proves it.';

export const BENCH_INTRO =
  'Two bots play the same game over the same simulated network three times: the server sending the world (state sync), and the relay sending the inputs to lockstep and to rollback sessions. Each panel shows both players’ machines. Move the sliders and compare what each sends, how late each shows an input, and what each has to correct.';

export const ABOUT: Readonly<Record<NetMode, { title: string; text: string }>> = {
  statesync: {
    title: 'State sync',
    text: 'The server runs the game and sends the world 20 times a second. A machine moves its own player at once, predicted from its own buttons, and puts it right — gliding — when the server’s world arrives; everyone else is drawn between two of the server’s snapshots, a little in the past.',
  },
  lockstep: {
    title: 'Lockstep',
    text: 'A machine steps tick t only once the relay has every player’s input for it. Nothing is guessed, nothing is undone; the price is an input delay of about one round trip.',
  },
  rollback: {
    title: 'Rollback',
    text: 'A machine runs ahead, guessing that the other player keeps holding the same buttons. When the real input differs it loads the saved state of that tick and steps again to now.',
  },
};

/** What each model needs from the game. */
export const NEEDS: Readonly<Record<NetMode, string>> = {
  statesync:
    'save() and load() of the whole state as bytes, and a server that runs it. It need not be deterministic.',
  lockstep: 'A deterministic step: the same inputs give the same bytes on every machine.',
  rollback:
    'Deterministic, and save() and load() fast enough to step several ticks again within a frame.',
};

export const COMPARE_INTRO =
  'The same match, measured the same way for each model since the start: bytes per second each client sends and receives, the mean time from player 1’s input being sampled to a screen showing a state that includes it, and the corrections a player could see — a guess that the server’s world or a rollback moved by half a unit or more (a respawn is not counted).';

/** When to use which, in our words. */
export const WHEN_TO_USE: readonly { mode: NetMode; text: string }[] = [
  {
    mode: 'statesync',
    text: 'State sync when the server must be the referee — anything worth cheating at — when the game is not deterministic (a physics engine that is not, floats that differ between browsers), when players come and go all the time, or when each player may only see part of the world. It sends the most towards the players and needs a server that runs every room.',
  },
  {
    mode: 'lockstep',
    text: 'Lockstep when every machine can compute the same world, the world is large but the inputs are few — strategy games with hundreds of units — and a round trip of input delay does not hurt. It sends the least and never shows a correction.',
  },
  {
    mode: 'rollback',
    text: 'Rollback when a deterministic game must answer every player at once — fighting games, sports, platformers — and the game can save, load and re-step a few ticks within a frame. Other players can be seen to jump when a guess was wrong.',
  },
];

/** A panel's verdict from its readouts. */
export function verdictText(
  mode: NetMode,
  r: { checkpoint: number; equal: boolean; desyncs: number },
): string {
  if (r.checkpoint < 0) return 'Connecting and syncing clocks…';
  if (mode === 'statesync') {
    if (r.equal)
      return `Both machines got the server’s world of tick ${r.checkpoint}, byte for byte.`;
    return 'A machine holds a world that is not the server’s.';
  }
  if (r.equal) return `Both machines computed the same world at tick ${r.checkpoint}.`;
  if (r.desyncs > 0) return 'The relay saw the machines disagree: a desync.';
  return 'Waiting for both machines to reach the checkpoint…';
}

/** A time in ms for the comparison table ('—' until measured). */
export function latencyText(ms: number): string {
  return Number.isFinite(ms) ? `${Math.round(ms)} ms` : '—';
}

/** The corrections cell: how many, the largest, and how they look. */
export function correctionText(n: ModelNumbers): string {
  if (n.corrections === 0) return n.mode === 'lockstep' ? 'none (nothing is guessed)' : 'none yet';
  const how = n.smoothed ? 'glide' : 'jump';
  return `${n.corrections}, up to ${n.largestCorrection.toFixed(1)} units (${how})`;
}
