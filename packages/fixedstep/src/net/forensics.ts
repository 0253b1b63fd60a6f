/** How two snapshots (`save()` bytes) of the same tick differ: desync forensics. */
export interface SnapshotDiff {
  /** Lengths of the two snapshots. */
  lengthA: number;
  lengthB: number;
  /** Bytes that differ, counting the length difference as differing bytes. */
  differingBytes: number;
  /** The first differing byte offset, or -1 when the snapshots are equal. */
  firstOffset: number;
  /** Runs of differing bytes as `[start, end)` offsets, the first `maxRanges` of them. */
  ranges: [number, number][];
  /** Whether there were more runs than `ranges` holds. */
  truncated: boolean;
}

/**
 * Which byte offsets differ between two snapshots of one tick. With the simulation's layout of
 * its `save()` bytes at hand, the offsets name the fields that diverged.
 */
export function diffSnapshots(a: Uint8Array, b: Uint8Array, maxRanges = 32): SnapshotDiff {
  const n = Math.min(a.length, b.length);
  const ranges: [number, number][] = [];
  let truncated = false;
  let differing = Math.abs(a.length - b.length);
  let first = -1;
  let runStart = -1;
  const close = (end: number) => {
    if (runStart < 0) return;
    if (ranges.length < maxRanges) ranges.push([runStart, end]);
    else truncated = true;
    runStart = -1;
  };
  for (let i = 0; i < n; i++) {
    if (a[i] !== b[i]) {
      differing++;
      if (first < 0) first = i;
      if (runStart < 0) runStart = i;
    } else {
      close(i);
    }
  }
  close(n);
  if (a.length !== b.length) {
    if (first < 0) first = n;
    runStart = n;
    close(Math.max(a.length, b.length));
  }
  return {
    lengthA: a.length,
    lengthB: b.length,
    differingBytes: differing,
    firstOffset: first,
    ranges,
    truncated,
  };
}
