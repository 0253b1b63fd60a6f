/**
 * A square n×n matrix whose nonzero entries lie within `bandwidth` of the diagonal
 * (`|i − j| ≤ bandwidth`), stored by rows with room for the fill-in of partial pivoting, and
 * solved in place by Gaussian elimination with partial pivoting (LAPACK `gbsv`, without
 * keeping the factors).
 *
 * Cost of {@link solve}: about `2·n·bandwidth²` multiply-adds; memory `n·(3·bandwidth + 1)`
 * float64. With `bandwidth = n − 1` it is ordinary dense Gaussian elimination (`n³` work), so
 * keep dense use to small n (a few hundred unknowns). A chain of springs numbered along the
 * chain in 2D has bandwidth 3 whatever its length; a grid W particles wide numbered row by row
 * has bandwidth about 2·W + 1.
 *
 * Allocates only in the constructor.
 */
export class BandMatrix {
  /** Number of rows and columns. */
  readonly n: number;
  /** Half-bandwidth b: entries with `|i − j| > b` are zero. At most `n − 1`. */
  readonly bandwidth: number;
  /** Stored entries per row: columns `i − b … i + 2b` (the upper `b` for pivoting fill-in). */
  private readonly width: number;
  private readonly data: Float64Array;

  /**
   * @param n — rows and columns, an integer ≥ 1.
   * @param bandwidth — half-bandwidth, an integer ≥ 0; clamped to `n − 1`.
   */
  constructor(n: number, bandwidth: number) {
    if (!Number.isInteger(n) || n < 1) {
      throw new RangeError(`BandMatrix: n must be an integer ≥ 1, got ${n}`);
    }
    if (!Number.isInteger(bandwidth) || bandwidth < 0) {
      throw new RangeError(`BandMatrix: bandwidth must be an integer ≥ 0, got ${bandwidth}`);
    }
    this.n = n;
    this.bandwidth = Math.min(bandwidth, n - 1);
    this.width = 3 * this.bandwidth + 1;
    this.data = new Float64Array(n * this.width);
  }

  /** Set every entry to 0. */
  clear(): void {
    this.data.fill(0);
  }

  /** Set the matrix to the identity. */
  setIdentity(): void {
    const d = this.data;
    d.fill(0);
    const w = this.width;
    const b = this.bandwidth;
    for (let i = 0; i < this.n; i++) d[i * w + b] = 1;
  }

  /**
   * Add `value` to entry (i, j). Throws a RangeError outside the matrix or the band — a model
   * that declared too small a bandwidth is a bug, never silently dropped.
   */
  add(i: number, j: number, value: number): void {
    const b = this.bandwidth;
    const off = j - i + b;
    if (!(i >= 0 && i < this.n && j >= 0 && j < this.n && off >= 0 && off <= 2 * b)) {
      throw new RangeError(
        `BandMatrix.add: entry (${i}, ${j}) is outside the ${this.n}×${this.n} matrix of bandwidth ${b}`,
      );
    }
    const k = i * this.width + off;
    this.data[k] = this.data[k]! + value;
  }

  /** Entry (i, j); 0 outside the band. Meaningful only before {@link solve}, which overwrites the matrix. */
  get(i: number, j: number): number {
    const b = this.bandwidth;
    if (i < 0 || i >= this.n || j < 0 || j >= this.n || j - i > b || i - j > b) return 0;
    return this.data[i * this.width + j - i + b]!;
  }

  /**
   * Solve `A·x = rhs` in place: on return `rhs` holds x and the matrix holds its (discarded)
   * factorisation — set it again before the next solve. Partial pivoting (largest magnitude in
   * the column among the rows of the band) keeps it stable for the non-symmetric, possibly
   * indefinite systems of implicit integration. Throws a RangeError if a pivot is 0 or not
   * finite (singular matrix, or NaN in it); `rhs` is then left partly reduced.
   */
  solve(rhs: Float64Array): void {
    const n = this.n;
    const b = this.bandwidth;
    const w = this.width;
    const d = this.data;
    if (rhs.length !== n) {
      throw new RangeError(`BandMatrix.solve: rhs has length ${rhs.length}, expected ${n}`);
    }
    for (let k = 0; k < n; k++) {
      const last = Math.min(n - 1, k + b);
      const jEnd = Math.min(n - 1, k + 2 * b);
      const rowK = k * w - k + b; // index of (k, j) is rowK + j
      let p = k;
      let best = Math.abs(d[rowK + k]!);
      for (let i = k + 1; i <= last; i++) {
        const m = Math.abs(d[i * w - i + b + k]!);
        if (m > best) {
          best = m;
          p = i;
        }
      }
      if (!(best > 0 && best < Infinity)) {
        throw new RangeError(
          `BandMatrix.solve: pivot ${best} in column ${k}: the matrix is singular or not finite`,
        );
      }
      if (p !== k) {
        const rowP = p * w - p + b;
        for (let j = k; j <= jEnd; j++) {
          const t = d[rowK + j]!;
          d[rowK + j] = d[rowP + j]!;
          d[rowP + j] = t;
        }
        const t = rhs[k]!;
        rhs[k] = rhs[p]!;
        rhs[p] = t;
      }
      const pivot = d[rowK + k]!;
      const rk = rhs[k]!;
      for (let i = k + 1; i <= last; i++) {
        const rowI = i * w - i + b;
        const f = d[rowI + k]! / pivot;
        if (f === 0) continue;
        for (let j = k + 1; j <= jEnd; j++) d[rowI + j] = d[rowI + j]! - f * d[rowK + j]!;
        rhs[i] = rhs[i]! - f * rk;
      }
    }
    for (let k = n - 1; k >= 0; k--) {
      const rowK = k * w - k + b;
      const jEnd = Math.min(n - 1, k + 2 * b);
      let s = rhs[k]!;
      for (let j = k + 1; j <= jEnd; j++) s -= d[rowK + j]! * rhs[j]!;
      rhs[k] = s / d[rowK + k]!;
    }
  }
}
