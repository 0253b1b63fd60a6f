/**
 * A spectator of a relay room: step the confirmed inputs only, send none, and join at any time
 * from a member's snapshot.
 * @module
 */
import type { ButtonInput } from '../../sim/buttons.js';
import { LockstepSession, type LockstepSessionOptions } from './lockstep.js';

/**
 * Watches a room: steps confirmed inputs only, sends none. Joins late at any time (from a
 * member's snapshot) and catches up at `maxTicksPerFrame` ticks a frame.
 */
export class SpectatorSession<I = ButtonInput> extends LockstepSession<I> {
  constructor(options: Omit<LockstepSessionOptions<I>, 'localInput' | 'inputDelay'>) {
    super(options, 'spectator');
  }
}
