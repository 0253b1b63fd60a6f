/**
 * Sessions on real sockets in the server's tests, framed from a timer as a Node client (or a
 * throttled tab) runs them.
 */
import { expect } from 'vitest';

/** What {@link frameUntilFinished} drives: any networked session. */
interface FramedSession {
  frame(): unknown;
  readonly isFinished: boolean;
}

/**
 * Frames `sessions` every 8 ms until every one has finished — failing the test after
 * `timeoutMs` — and stops the timer either way.
 */
export async function frameUntilFinished(
  sessions: readonly FramedSession[],
  timeoutMs = 30_000,
): Promise<void> {
  const timer = setInterval(() => {
    for (const s of sessions) s.frame();
  }, 8);
  try {
    await expect
      .poll(() => sessions.every((s) => s.isFinished), { timeout: timeoutMs, interval: 50 })
      .toBe(true);
  } finally {
    clearInterval(timer);
  }
}
