/** Number formatting for readouts. Pure, so the unit tests cover it. */

/** Seconds with 3 decimals, e.g. "4.983 s". */
export function seconds(s: number): string {
  return Number.isFinite(s) ? `${s.toFixed(3)} s` : '—';
}

/** A ratio like "2.403×". */
export function ratio(r: number): string {
  return Number.isFinite(r) ? `${r.toFixed(3)}×` : '—';
}

/** Milliseconds: one decimal below 100 ms, whole and grouped above: "12.5 ms", "1 758 ms". */
export function millis(ms: number | undefined): string {
  if (ms === undefined) return 'n/a';
  if (!Number.isFinite(ms)) return '—';
  const abs = Math.abs(ms);
  const text = abs < 99.95 ? (Math.round(abs * 10) / 10).toString() : count(abs);
  if (text === '0') return '0 ms';
  return `${ms < 0 ? '−' : ''}${text} ms`;
}

/** A count, grouped with thin spaces. */
export function count(n: number): string {
  return Math.round(n)
    .toString()
    .replace(/\B(?=(\d{3})+(?!\d))/g, '\u202f');
}

/** A hue (0–359) from a hex hash, so equal hashes get equal colours. */
export function hashHue(hex: string): number {
  const v = parseInt(hex.slice(0, 6), 16);
  return Number.isFinite(v) ? v % 360 : 0;
}

/** Full precision for `data-value` (what the browser tests read). */
export function exact(v: number | string | boolean | undefined): string {
  if (v === undefined) return '';
  if (typeof v === 'number') return Number.isNaN(v) ? 'NaN' : String(v);
  return String(v);
}

const SUPERSCRIPT = '⁰¹²³⁴⁵⁶⁷⁸⁹';

/** Powers of ten as people write them: sci(4e-118) = "4.00 × 10⁻¹¹⁸", sci(1e9, 0) = "10⁹". */
export function sci(x: number, digits = 2): string {
  if (!Number.isFinite(x) || x === 0) return String(x);
  const [mantissa = '', power = '0'] = x.toExponential(digits).split('e');
  const e = Number(power);
  const sup = `${e < 0 ? '⁻' : ''}${String(Math.abs(e))
    .split('')
    .map((d) => SUPERSCRIPT[Number(d)])
    .join('')}`;
  return mantissa === '1' ? `10${sup}` : `${mantissa} × 10${sup}`;
}

/** A count with its noun, singular for exactly one: plural(1, 'point') = "1 point", "2 points". */
export function plural(n: number, noun: string, nouns = `${noun}s`): string {
  return `${count(n)} ${Math.round(n) === 1 ? noun : nouns}`;
}
