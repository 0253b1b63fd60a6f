/** Text formatting of results. Pure. */

export type Align = 'left' | 'right';

/**
 * A plain-text table: a header, a rule, the rows; columns padded to their widest cell and
 * separated by two spaces. The first column is left-aligned and the others right-aligned unless
 * `align` says otherwise. Every line is prefixed with `indent`.
 */
export function formatTable(
  header: readonly string[],
  rows: readonly (readonly string[])[],
  align: readonly Align[] = header.map((_, i) => (i === 0 ? 'left' : 'right')),
  indent = '  ',
): string {
  for (const row of rows) {
    if (row.length !== header.length) {
      throw new RangeError(
        `formatTable: a row has ${row.length} cells, the header ${header.length}`,
      );
    }
  }
  const widths = header.map((h, c) => Math.max(h.length, ...rows.map((r) => r[c]!.length)));
  const line = (cells: readonly string[]) =>
    indent +
    cells
      .map((cell, c) =>
        align[c] === 'right' ? cell.padStart(widths[c]!) : cell.padEnd(widths[c]!),
      )
      .join('  ')
      .trimEnd();
  const rule = indent + widths.map((w) => '-'.repeat(w)).join('  ');
  return [line(header), rule, ...rows.map(line)].join('\n');
}

/** Three significant digits, no exponent: 3.14, 31.4, 314, 3142. */
function sig3(x: number): string {
  const a = Math.abs(x);
  if (a >= 100) return x.toFixed(0);
  if (a >= 10) return x.toFixed(1);
  return x.toFixed(2);
}

/** A duration given in ns, in the unit that reads best: `6.21 ns`, `12.3 µs`, `1.50 ms`, `2.00 s`. */
export function formatDuration(ns: number): string {
  if (!Number.isFinite(ns)) return String(ns);
  const a = Math.abs(ns);
  if (a < 1e3) return `${sig3(ns)} ns`;
  if (a < 1e6) return `${sig3(ns / 1e3)} µs`;
  if (a < 1e9) return `${sig3(ns / 1e6)} ms`;
  return `${sig3(ns / 1e9)} s`;
}

/** A ratio: `2.01×`. */
export function formatRatio(r: number): string {
  return `${r.toFixed(2)}×`;
}

/** A ratio's spread: `1.85–2.30`. */
export function formatRange(min: number, max: number): string {
  return `${min.toFixed(2)}–${max.toFixed(2)}`;
}

/** Bytes per op, to a thousandth of a byte: `0.000`, `32.0`, `216`. */
export function formatBytes(b: number): string {
  return b < 10 ? b.toFixed(3) : sig3(b);
}
