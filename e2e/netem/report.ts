/** Writes the loss harness's comparison: `artifacts/netem/<name>.json` (for the lab to chart) and `.md`. */
import { mkdirSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import type { Impairment } from './impair.js';
import { comparisonTable, type TransportSummary } from './probe.js';

const artifacts = fileURLToPath(new URL('../../artifacts/netem', import.meta.url));

export interface NetemReport {
  format: 'fixedstep-netem/1';
  date: string;
  where: string;
  game: string;
  ticks: number;
  tickRate: number;
  players: number;
  link: Impairment;
  rows: TransportSummary[];
}

export function writeNetemReport(name: string, report: NetemReport): string {
  mkdirSync(artifacts, { recursive: true });
  const base = path.join(artifacts, name);
  writeFileSync(`${base}.json`, `${JSON.stringify(report, null, 2)}\n`);
  const l = report.link;
  const md =
    `# Loss harness: ${report.where}\n\n` +
    `${report.game}, ${report.players} players, ${report.ticks} ticks at ${report.tickRate} Hz; the joiner's link ` +
    `${l.latencyMs} ± ${l.jitterMs} ms one way, ${(l.loss * 100).toFixed(0)} % loss each way (${report.date}).\n\n` +
    `${comparisonTable(report.rows)}\n`;
  writeFileSync(`${base}.md`, md);
  return md;
}
