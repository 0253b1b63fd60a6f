/**
 * The life of a networked session, kept in one place for every kind: its phase, its events, and
 * its `finished` promise — settled once, resolved at the session's end or rejected with the first
 * fatal error before it.
 * @module
 */
import { SessionError, type SessionEvent, type SessionPhase } from './events.js';

/**
 * A session's phase, events and outcome. The session decides what its end is ({@link finish})
 * and what went wrong ({@link error}); this keeps the rules the same for every kind: one
 * settlement, every fatal error before the end rejects, a close before the end is `CLOSED`, and
 * `closed` is the last event.
 *
 * @typeParam W — the session's welcome message.
 * @typeParam X — the session's own events beside the shared ones.
 * @internal
 */
export class SessionLife<W, X extends { type: string } = never> {
  phase: SessionPhase = 'connecting';
  /** Resolves at the session's end; rejects with the fatal {@link SessionError} that came first. */
  readonly finished: Promise<void>;

  private outcome: 'pending' | 'finished' | 'failed' = 'pending';
  private failed: SessionError | undefined;
  private settle: { resolve: () => void; reject: (error: SessionError) => void } | undefined;

  constructor(private readonly onEvent: ((event: SessionEvent<W> | X) => void) | undefined) {
    this.finished = new Promise<void>((resolve, reject) => {
      this.settle = { resolve, reject };
    });
    // Nobody need await `finished` (a test driving frames reads `isFinished`): a rejection that
    // nobody observes must not surface as an unhandled rejection. Awaiting it still throws.
    this.finished.catch(() => undefined);
  }

  /** Whether the session reached its end (`finished` resolved). */
  get isFinished(): boolean {
    return this.outcome === 'finished';
  }

  /** The fatal error `finished` rejected with, if it did. */
  get failure(): SessionError | undefined {
    return this.failed;
  }

  /** Whether `finished` is settled either way. */
  get settled(): boolean {
    return this.outcome !== 'pending';
  }

  emit(event: SessionEvent<W> | X): void {
    this.onEvent?.(event);
  }

  /** The session reached its end: `finished` resolves (unless it already failed). */
  finish(): void {
    if (this.outcome !== 'pending') return;
    this.outcome = 'finished';
    this.settle?.resolve();
  }

  /**
   * Report `error` (the `error` event); a fatal one before the end also rejects `finished`. The
   * event comes first, so a listener sees the cause before any awaiting code does.
   */
  error(error: SessionError): void {
    this.emit({ type: 'error', error });
    if (!error.fatal || this.outcome !== 'pending') return;
    this.outcome = 'failed';
    this.failed = error;
    this.settle?.reject(error);
  }

  /**
   * The transport closed: the phase is `'closed'`; before the end and with no error said, that is
   * the `CLOSED` error; then the `closed` event, the last.
   */
  closed(reason: string): void {
    if (this.phase === 'closed') return;
    this.phase = 'closed';
    if (this.outcome === 'pending') {
      this.error(
        new SessionError('CLOSED', `the connection closed before the session's end (${reason})`),
      );
    }
    this.emit({ type: 'closed', reason });
  }
}
