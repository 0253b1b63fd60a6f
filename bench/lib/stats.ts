/** The statistics of a side-by-side run. Pure: numbers in, numbers out. */

/** The median of a non-empty list (the mean of the two middle values for an even count). */
export function median(values: readonly number[]): number {
  if (values.length === 0) throw new RangeError('median of an empty list');
  const sorted = [...values].sort((a, b) => a - b);
  const mid = sorted.length >> 1;
  return sorted.length % 2 === 1 ? sorted[mid]! : (sorted[mid - 1]! + sorted[mid]!) / 2;
}

export interface Spread {
  readonly median: number;
  readonly min: number;
  readonly max: number;
}

export function spread(values: readonly number[]): Spread {
  return { median: median(values), min: Math.min(...values), max: Math.max(...values) };
}

/** Per-round ratios `a[r] / b[r]`: each round's candidate against the same round's baseline. */
export function ratios(a: readonly number[], b: readonly number[]): number[] {
  if (a.length !== b.length) throw new RangeError(`ratios: ${a.length} vs ${b.length} rounds`);
  return a.map((x, r) => x / b[r]!);
}

export interface CandidateSummary {
  readonly name: string;
  /** Time per op over the rounds, in ns. */
  readonly ns: Spread;
  /** Per-round ratio to the baseline; `undefined` for the baseline itself. */
  readonly ratio: Spread | undefined;
}

/**
 * Summarises an interleaved run: `samples[c][r]` is candidate `c`'s ns/op in round `r`. Ratios are
 * taken round by round (both candidates ran moments apart, under the same machine noise), then
 * summarised; a ratio of medians would mix rounds with different noise.
 */
export function summarize(
  names: readonly string[],
  samples: readonly (readonly number[])[],
  baseline: number,
): CandidateSummary[] {
  const base = samples[baseline];
  if (base === undefined) throw new RangeError(`no baseline candidate ${baseline}`);
  if (samples.length !== names.length) throw new RangeError('one sample list per candidate');
  return names.map((name, c) => {
    const s = samples[c]!;
    return { name, ns: spread(s), ratio: c === baseline ? undefined : spread(ratios(s, base)) };
  });
}

/**
 * The order in which candidates run in round `round`: forwards on even rounds, backwards on odd
 * ones (A B C, C B A, A B C …), so no candidate always runs first or last after the gc.
 */
export function roundOrder(count: number, round: number): number[] {
  const order = Array.from({ length: count }, (_, i) => i);
  return round % 2 === 0 ? order : order.reverse();
}

/** How many ops fill a sample of `sampleNs`, given a measured cost per op (at least 1). */
export function opsForSample(sampleNs: number, nsPerOp: number): number {
  if (!(nsPerOp > 0)) return 1_000_000;
  return Math.max(1, Math.min(1e9, Math.round(sampleNs / nsPerOp)));
}

/**
 * Bytes allocated per op from heap readings around chunks of `ops` ops, each chunk starting after
 * a gc: the median chunk, less the readings' own overhead (median of empty chunks).
 */
export function bytesPerOp(
  chunkBytes: readonly number[],
  emptyBytes: readonly number[],
  ops: number,
): Spread {
  const overhead = emptyBytes.length > 0 ? median(emptyBytes) : 0;
  return spread(chunkBytes.map((b) => Math.max(0, b - overhead) / ops));
}
