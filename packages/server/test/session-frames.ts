/**
 * Sessions on real sockets in the server's tests, framed from a timer as a Node client (or a
 * throttled tab) runs them.
 */
import { expect } from 'vitest';
import WebSocket from 'ws';
import { LockstepSession, hex64, nodeWebSocketTransport, performanceClock } from 'fixedstep';
import { ctfGame, type Game } from '@fixedstep/games';

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

/**
 * Two capture-the-flag bots joining relay room `room` at `url` (a `ws://…/ws/<room>` address)
 * over real WebSockets — each with its own `headers` (e.g. an X-Forwarded-For) — played to `ticks`
 * by {@link frameUntilFinished}. Resolves with both players' hashes at `ticks`; closes the sockets.
 */
export async function ctfBotsOnRelay(options: {
  url: string;
  room: string;
  ticks: number;
  seed: number;
  headers?: readonly [Record<string, string>, Record<string, string>];
  timeoutMs?: number;
}): Promise<[string, string]> {
  const clock = performanceClock();
  const sockets: WebSocket[] = [];
  try {
    const sessions = await Promise.all(
      [0, 1].map(
        (i) =>
          new Promise<LockstepSession>((resolve, reject) => {
            const ws = new WebSocket(options.url, { headers: options.headers?.[i] ?? {} });
            sockets.push(ws);
            ws.on('error', reject);
            ws.on('open', () => {
              let slot = 0;
              resolve(
                new LockstepSession({
                  transport: nodeWebSocketTransport(ws),
                  clock,
                  room: options.room,
                  game: ctfGame,
                  players: 2,
                  seed: options.seed,
                  stopAt: options.ticks,
                  createSimulation: (w) => {
                    slot = w.slot;
                    return ctfGame.create(ctfGame.decodeConfig(w.config));
                  },
                  localInput: (_t, sim) => ctfGame.bot(sim as Game, slot),
                }),
              );
            });
          }),
      ),
    );
    await frameUntilFinished(sessions, options.timeoutMs);
    return [hex64(sessions[0]!.hashAt(options.ticks)!), hex64(sessions[1]!.hashAt(options.ticks)!)];
  } finally {
    for (const ws of sockets) ws.terminate();
  }
}
