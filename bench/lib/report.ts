/** What a suite reports (also the JSON shape), and how it reads as text. Pure. */
import { formatBytes, formatDuration, formatRange, formatRatio, formatTable } from './format.js';
import type { Spread } from './stats.js';

export interface ComparisonSection {
  readonly kind: 'comparison';
  readonly title: string;
  /** What one op is: `frame`, `step`, `tick` … */
  readonly unit: string;
  readonly baseline: string;
  readonly rounds: number;
  readonly sampleMs: number;
  readonly candidates: readonly {
    readonly name: string;
    readonly opsPerSample: number;
    /** ns per op over the rounds. */
    readonly ns: Spread;
    /** Per-round ratio to the baseline; absent for the baseline. */
    readonly ratio?: Spread;
    /** ns per op, one per round, in round order. */
    readonly samplesNs: readonly number[];
  }[];
}

export interface AllocationSection {
  readonly kind: 'allocation';
  readonly title: string;
  readonly unit: string;
  readonly chunks: number;
  readonly opsPerChunk: number;
  /** Why nothing was measured (e.g. no `--expose-gc`). */
  readonly skipped?: string;
  readonly candidates: readonly { readonly name: string; readonly bytes: Spread }[];
}

export interface TableSection {
  readonly kind: 'table';
  readonly title: string;
  readonly header: readonly string[];
  readonly rows: readonly (readonly string[])[];
}

export interface NoteSection {
  readonly kind: 'note';
  readonly text: string;
}

export type Section = ComparisonSection | AllocationSection | TableSection | NoteSection;

export interface SuiteReport {
  readonly name: string;
  readonly description: string;
  readonly ok: boolean;
  readonly error?: string;
  readonly seconds: number;
  readonly sections: readonly Section[];
}

/** Fewer bytes than this per chunk of ops is measurement noise, not an allocation. */
export const ALLOCATION_NOISE_BYTES = 64;

export function renderSection(section: Section): string {
  switch (section.kind) {
    case 'comparison':
      return renderComparison(section);
    case 'allocation':
      return renderAllocation(section);
    case 'table':
      return `${section.title}\n${formatTable(section.header, section.rows)}`;
    case 'note':
      return `  ${section.text}`;
  }
}

export function renderComparison(s: ComparisonSection): string {
  const rows = s.candidates.map((c) => [
    c.name,
    formatDuration(c.ns.median),
    c.ratio ? formatRatio(c.ratio.median) : formatRatio(1),
    c.ratio ? formatRange(c.ratio.min, c.ratio.max) : '(baseline)',
  ]);
  const table = formatTable(['candidate', `per ${s.unit}`, 'ratio', 'ratio min–max'], rows);
  const footer =
    `  median of ${s.rounds} interleaved rounds (~${s.sampleMs} ms per sample); ` +
    `ratio = per-round time / ${s.baseline}`;
  return `${s.title}\n${table}\n${footer}`;
}

export function renderAllocation(s: AllocationSection): string {
  if (s.skipped !== undefined) return `${s.title}\n  skipped: ${s.skipped}`;
  const noise = ALLOCATION_NOISE_BYTES / s.opsPerChunk;
  const rows = s.candidates.map((c) => [
    c.name,
    formatBytes(c.bytes.median),
    formatBytes(c.bytes.max),
    c.bytes.median * s.opsPerChunk < ALLOCATION_NOISE_BYTES ? 'no' : 'yes',
  ]);
  const table = formatTable(['candidate', `B/${s.unit}`, 'max chunk', 'allocates'], rows);
  const footer =
    `  ${s.chunks} chunks × ${s.opsPerChunk} ${s.unit}s, each after a minor gc; median chunk; ` +
    `'no' = under ${formatBytes(noise)} B/${s.unit}`;
  return `${s.title}\n${table}\n${footer}`;
}
