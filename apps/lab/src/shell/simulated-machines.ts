/**
 * Machines that play one match over simulated links, on one event scheduler (virtual ms) — the
 * network chapter's three models and the rigid-bodies chapter's duel. What they share: the
 * scheduler, the displays (simulated 60 Hz ones, or the page's own frames), the links and what
 * was lost on them, and the hashes at the last checkpoint both machines have confirmed. No DOM.
 */
import { EventScheduler, hex64, type LinkConditions, type SimulatedLink } from 'fixedstep';

/** A simulated display's frame interval, ms (60 Hz). */
const DISPLAY_FRAME_MS = 1000 / 60;

/**
 * Machines on one scheduler, each drawing on a simulated 60 Hz display — or, with
 * {@link realFrames}, when the page draws ({@link realFrame}).
 */
export abstract class SimulatedMachines {
  readonly scheduler = new EventScheduler(0);
  /**
   * Real display frames: the machines draw when the page does ({@link realFrame}) instead of on
   * their simulated 60 Hz displays.
   */
  realFrames = false;
  /** Each machine's link to the server. */
  abstract readonly links: readonly SimulatedLink[];

  get nowMs(): number {
    return this.scheduler.now;
  }

  advanceTo(ms: number): void {
    if (ms > this.scheduler.now) this.scheduler.runUntil(ms);
  }

  /** A real display frame at virtual `ms`: the links and the server run to then, every machine draws. */
  realFrame(ms: number): void {
    this.advanceTo(ms);
    this.drawAll();
  }

  /** Change every link now, both directions. */
  setLink(c: LinkConditions): void {
    for (const l of this.links) l.setConditions(c);
  }

  /** One display frame of every machine, at the scheduler's time. */
  protected abstract drawAll(): void;

  /**
   * A machine's simulated display: `draw` every 60 Hz frame from `offsetMs` (machines out of
   * phase draw at different offsets), unless real frames drive the machines.
   */
  protected display(offsetMs: number, draw: () => void): void {
    this.scheduler.every(
      DISPLAY_FRAME_MS,
      () => {
        if (!this.realFrames) draw();
      },
      offsetMs,
    );
  }
}

/** Messages lost and sent on the links, both directions. */
export function lossOf(links: readonly SimulatedLink[]): { lost: number; sent: number } {
  let lost = 0;
  let sent = 0;
  for (const l of links) {
    for (const d of l.stats) {
      lost += d.lost;
      sent += d.sent;
    }
  }
  return { lost, sent };
}

/** What {@link confirmedCheckpoint} reads of a session: its confirmed states' hashes. */
interface ConfirmingSession {
  confirmedStateTick(): number;
  hashAt(tick: number): bigint | undefined;
}

/**
 * The last checkpoint (a multiple of `every`, at least one) both machines have a confirmed state
 * of, or -1; and each one's hash there (16 hex digits, or '' when it no longer keeps it).
 */
function confirmedCheckpoint(
  a: ConfirmingSession,
  b: ConfirmingSession,
  every: number,
): { checkpoint: number; hashes: [string, string] } {
  const confirmed = Math.min(a.confirmedStateTick(), b.confirmedStateTick());
  const checkpoint = confirmed >= every ? Math.floor(confirmed / every) * every : -1;
  const hashOf = (s: ConfirmingSession): string => {
    if (checkpoint < 0) return '';
    const h = s.hashAt(checkpoint);
    return h === undefined ? '' : hex64(h);
  };
  return { checkpoint, hashes: [hashOf(a), hashOf(b)] };
}

/**
 * Whether two machines agree, as a page shows it: the last checkpoint both have confirmed, each
 * one's hash there, whether those are equal with no desync seen, and the messages lost and sent.
 */
export interface Agreement {
  /** The last checkpoint both machines have a confirmed state of (-1: none yet). */
  checkpoint: number;
  /** Each machine's hash (FNV-1a 64 of `save()`) of its confirmed state there (16 hex, or ''). */
  hashes: [string, string];
  /** Both machines have a hash at the checkpoint, equal, and no desync was seen. */
  equal: boolean;
  desyncs: number;
  /** Messages lost and sent on all links so far, both directions. */
  lost: number;
  sent: number;
}

/**
 * The {@link Agreement} of sessions `a` and `b` at their last confirmed checkpoint (a multiple
 * of `every`), with the `desyncs` their server saw, over `links`.
 */
export function agreementOf(
  a: ConfirmingSession,
  b: ConfirmingSession,
  every: number,
  desyncs: number,
  links: readonly SimulatedLink[],
): Agreement {
  const { checkpoint, hashes } = confirmedCheckpoint(a, b, every);
  const equal = hashes[0] !== '' && hashes[0] === hashes[1] && desyncs === 0;
  return { checkpoint, hashes, equal, desyncs, ...lossOf(links) };
}
