/**
 * The lead that a player's late inputs ask for, over a window of time.
 *
 * A state-sync snapshot says by how many ticks the player's inputs that arrived since the one
 * before were early (`slack`; negative: late). An input issued at lead `L` that arrived `slack`
 * ticks early would have been just in time with `L − slack + target` — its delay in ticks plus
 * the margin wanted — whatever the lead was, so these needs can be compared across time. Over a
 * stream (TCP) a lost segment holds everything behind it for a retransmission or two, so the
 * delays are a few steady ones and a long tail of stalls; reacting to each stall after it has
 * passed, and dropping the lead again after a few quiet seconds, leaves the lead short whenever
 * the next one comes (2.6 % of inputs late at 100 ± 30 ms and 5 % loss, `npm run bench --
 * state-sync`). This keeps the largest need of the last `windowMs` instead, one maximum per
 * second: the lead rises to a stall's length at once and stays there while stalls that long keep
 * coming; when they stop, the window forgets them a second at a time. Two minutes, because a
 * double loss (a stall of ~3 round trips) comes every 15–20 s on that link and a triple one every
 * few minutes: 30 s of memory left 0.47–0.81 % of inputs late over five minutes (6 seeds), two
 * minutes 0.19–0.50 %, at a lead of ~50 ticks either way.
 */
export class NeededLead {
  private readonly need: Int32Array;
  private readonly second: Float64Array;

  constructor(
    /** How long a need is remembered, ms (whole seconds). */
    readonly windowMs = 120_000,
  ) {
    const n = Math.max(1, Math.ceil(windowMs / 1000));
    this.need = new Int32Array(n);
    this.second = new Float64Array(n).fill(-Infinity);
  }

  /** A need of `ticks` seen at `now` (ms). */
  note(now: number, ticks: number): void {
    const s = Math.floor(now / 1000);
    const i = s % this.need.length;
    if (this.second[i] !== s) {
      this.second[i] = s;
      this.need[i] = ticks;
    } else if (ticks > this.need[i]!) {
      this.need[i] = ticks;
    }
  }

  /** The largest need within the window at `now`; -1 when none. */
  value(now: number): number {
    const s = Math.floor(now / 1000);
    const oldest = s - this.need.length + 1;
    let best = -1;
    for (let i = 0; i < this.need.length; i++) {
      const at = this.second[i]!;
      if (at >= oldest && at <= s && this.need[i]! > best) best = this.need[i]!;
    }
    return best;
  }
}
