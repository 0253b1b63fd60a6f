/**
 * The determinism report: `artifacts/determinism/report.json` and `report.md` — which engines ran
 * (and their versions), which were skipped and why, ticks compared, every mismatch with its first
 * tick, scene and differing field, and how the engines' own `Math` functions differ.
 */
import { mkdirSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import type { TraceScene } from '@fixedstep/games';
import { formatMismatch, type InformationalResult, type Mismatch } from './compare.js';
import { ENGINE_NAMES, type EngineId } from './engines/session.js';

export interface EngineReport {
  id: EngineId;
  name: string;
  status: 'passed' | 'failed' | 'skipped';
  /** Skipped: why. Failed without traces: what went wrong. */
  reason?: string;
  version?: string;
  jsVersion?: string;
  /** Whether the engine ran the WebAssembly spring kernel (the cloth scenes). */
  wasm?: boolean;
  /** Whether it ran PhysicsWorld's WebAssembly kernels (the big piles). */
  worldWasm?: boolean;
  userAgent?: string;
  /** Start-up and page load, ms. */
  startMs?: number;
  /** Tracing every scene, ms (measured inside the engine). */
  runMs?: number;
  /** Wall time of each scene in the engine, ms (where the time goes). */
  sceneMs?: Record<string, number>;
  /** Required scenes and ticks compared. */
  scenes?: number;
  ticks?: number;
  mismatches: Mismatch[];
  informational: InformationalResult[];
}

export interface DeterminismReport {
  generatedAt: string;
  /** Wall time of the whole suite's set-up (build, engines, comparison), ms. */
  totalMs: number;
  host: string;
  catalogue: {
    scenes: { id: string; title: string; ticks: number; sameAs?: string; informational?: true }[];
    /** Ticks over the required scenes (what each engine is compared on). */
    requiredTicks: number;
  };
  engines: EngineReport[];
  notes: string[];
}

export function catalogueSummary(scenes: readonly TraceScene[]): DeterminismReport['catalogue'] {
  return {
    scenes: scenes.map((s) => ({
      id: s.id,
      title: s.title,
      ticks: s.ticks,
      ...(s.sameAs !== undefined ? { sameAs: s.sameAs } : {}),
      ...(s.informational ? { informational: true as const } : {}),
    })),
    requiredTicks: scenes.filter((s) => !s.informational).reduce((sum, s) => sum + s.ticks, 0),
  };
}

function dash(s: string | undefined): string {
  return s === undefined || s === '' ? '—' : s;
}

function seconds(ms: number | undefined): string {
  return ms === undefined ? '—' : `${(ms / 1000).toFixed(1)} s`;
}

/** The report as Markdown. */
export function reportMarkdown(r: DeterminismReport): string {
  const lines: string[] = [];
  const ran = r.engines.filter((e) => e.status !== 'skipped');
  lines.push('# Determinism across engines and display rates', '');
  lines.push(
    `Generated ${r.generatedAt} on ${r.host}; ${String(r.catalogue.scenes.length)} scenes, ` +
      `${String(r.catalogue.requiredTicks)} required ticks per engine; set-up to verdict ${seconds(r.totalMs)}.`,
    '',
  );
  lines.push(
    '| Engine | Status | Version | JS engine | WebAssembly kernels (springs / world) | Scenes | Ticks compared | Start | Run |',
  );
  lines.push('|---|---|---|---|---|---|---|---|---|');
  for (const e of r.engines) {
    lines.push(
      `| ${e.name} | ${e.status}${e.status === 'failed' && e.mismatches.length ? ` (${String(e.mismatches.length)} mismatches)` : ''} | ` +
        `${e.version ?? '—'} | ${dash(e.jsVersion)} | ${yesNo(e.wasm)} / ${yesNo(e.worldWasm)} | ${e.scenes === undefined ? '—' : String(e.scenes)} | ` +
        `${e.ticks === undefined ? '—' : e.ticks.toLocaleString('en-US')} | ${seconds(e.startMs)} | ${seconds(e.runMs)} |`,
    );
  }
  lines.push('');
  const skipped = r.engines.filter((e) => e.status === 'skipped');
  if (skipped.length > 0) {
    lines.push('## Skipped engines', '');
    for (const e of skipped) lines.push(`- **${e.name}**: ${e.reason ?? 'no reason given'}`);
    lines.push('');
  }
  const broken = r.engines.filter((e) => e.status === 'failed' && e.reason !== undefined);
  if (broken.length > 0) {
    lines.push('## Engines that could not run', '');
    for (const e of broken) lines.push(`- **${e.name}**: ${e.reason ?? ''}`);
    lines.push('');
  }
  const mismatches = r.engines.flatMap((e) => e.mismatches);
  lines.push('## Mismatches', '');
  if (mismatches.length === 0) {
    lines.push(
      ran.length > 0
        ? `None: every required scene gave the same hash at every tick in ${ran.map((e) => e.name).join(', ')}, ` +
            'and every display-rate and replay scene matched its reference.'
        : 'No engine ran.',
    );
  } else {
    for (const m of mismatches) lines.push(`- ${formatMismatch(m)}`);
  }
  lines.push('');

  const info = ran.filter((e) => e.informational.length > 0);
  if (info.length > 0) {
    lines.push(
      '## The engines’ own Math (informational: why simulations use the det helpers)',
      '',
      'Inputs (one per tick) whose result differs from Node’s, bit for bit:',
      '',
    );
    lines.push(`| Function | ${info.map((e) => e.name).join(' | ')} |`);
    lines.push(`|---|${info.map(() => '---').join('|')}|`);
    const names = info[0]!.informational.map((x) => x.scene);
    for (const name of names) {
      const cells = info.map((e) => {
        const x = e.informational.find((y) => y.scene === name);
        if (!x) return '—';
        if (x.detail.startsWith('threw')) return x.detail;
        return x.differingTicks === 0
          ? `0 / ${String(x.ticks)}`
          : `**${String(x.differingTicks)} / ${String(x.ticks)}**`;
      });
      lines.push(`| ${name.replace(/^engine\//, '')} | ${cells.join(' | ')} |`);
    }
    lines.push('');
    const firsts = info.flatMap((e) =>
      e.informational
        .filter((x) => x.differingTicks > 0)
        .slice(0, 3)
        .map((x) => `- ${e.name}, ${x.scene}, first at tick ${String(x.firstTick)}: ${x.detail}`),
    );
    if (firsts.length > 0) lines.push('Examples:', '', ...firsts, '');
  }

  if (r.notes.length > 0) {
    lines.push('## Notes', '', ...r.notes.map((n) => `- ${n}`), '');
  }
  lines.push('## Scenes', '', '| Scene | Ticks | Must equal |', '|---|---|---|');
  for (const s of r.catalogue.scenes) {
    lines.push(
      `| \`${s.id}\` — ${s.title} | ${String(s.ticks)} | ${s.informational ? '(informational)' : s.sameAs ? `every engine’s Node trace, and \`${s.sameAs}\`` : 'every engine’s Node trace'} |`,
    );
  }
  lines.push('');
  return lines.join('\n');
}

/** Writes `report.json` and `report.md` into `dir`; returns their paths. */
export function writeReport(dir: string, r: DeterminismReport): { json: string; md: string } {
  mkdirSync(dir, { recursive: true });
  const json = path.join(dir, 'report.json');
  const md = path.join(dir, 'report.md');
  writeFileSync(json, `${JSON.stringify(r, null, 2)}\n`);
  writeFileSync(md, reportMarkdown(r));
  return { json, md };
}

/** A short summary for the console: one line per engine, then skips and mismatches. */
export function consoleSummary(r: DeterminismReport, files: { json: string; md: string }): string {
  const lines = ['Determinism across engines:'];
  for (const e of r.engines) {
    const what =
      e.status === 'skipped'
        ? `SKIPPED — ${e.reason ?? ''}`
        : e.reason !== undefined
          ? `FAILED to run — ${e.reason}`
          : `${e.status === 'passed' ? 'same traces' : `${String(e.mismatches.length)} MISMATCHES`}: ` +
            `${String(e.scenes ?? 0)} scenes, ${(e.ticks ?? 0).toLocaleString('en-US')} ticks; ` +
            `${e.version ?? ''}${e.jsVersion ? `, ${e.jsVersion}` : ''}${e.wasm === undefined ? '' : `, WebAssembly springs ${yesNo(e.wasm)}, world ${yesNo(e.worldWasm)}`}; start ${seconds(e.startMs)}, run ${seconds(e.runMs)}`;
    lines.push(`  ${ENGINE_NAMES[e.id].padEnd(27)} ${what}`);
  }
  for (const m of r.engines.flatMap((e) => e.mismatches).slice(0, 20)) {
    lines.push(`  ✗ ${formatMismatch(m)}`);
  }
  lines.push(`  report: ${files.md}`);
  return lines.join('\n');
}

function yesNo(flag: boolean | undefined): string {
  return flag === undefined ? '—' : flag ? 'yes' : 'no';
}
