/** A small, dependency-free SVG line chart for the CLI's experiment reports. */

export interface Series {
  label: string;
  x: readonly number[];
  y: readonly number[];
}

export interface ChartOptions {
  title: string;
  xLabel: string;
  yLabel: string;
  /** Log-scale y (values ≤ 0 or non-finite are clipped to the range). */
  logY?: boolean;
  /** Clip y to this range (after the log, in log10 units when logY). */
  yRange?: [number, number];
  width?: number;
  height?: number;
}

const COLORS = [
  '#e4572e',
  '#f3a712',
  '#29335c',
  '#669bbc',
  '#2a9d8f',
  '#8338ec',
  '#ff006e',
  '#3a86ff',
];

function esc(s: string): string {
  return s.replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;');
}

function niceTicks(lo: number, hi: number, count = 6): number[] {
  const span = hi - lo || 1;
  const raw = span / count;
  const mag = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => span / s <= count) ?? 10 * mag;
  const out: number[] = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step)
    out.push(Number(v.toPrecision(12)));
  return out;
}

/** Renders series as an SVG document. */
export function lineChartSvg(series: readonly Series[], o: ChartOptions): string {
  const W = o.width ?? 980;
  const H = o.height ?? 520;
  const m = { l: 70, r: 270, t: 48, b: 56 };
  const tr = (v: number) => (o.logY ? (v > 0 && Number.isFinite(v) ? Math.log10(v) : NaN) : v);
  const xs = series.flatMap((s) => s.x);
  const ys = series.flatMap((s) => s.y.map(tr)).filter(Number.isFinite);
  const x0 = Math.min(...xs);
  const x1 = Math.max(...xs);
  let [y0, y1] = o.yRange ?? [Math.min(...ys), Math.max(...ys)];
  if (!(y1 > y0)) {
    y0 -= 1;
    y1 += 1;
  }
  const px = (x: number) => m.l + ((x - x0) / (x1 - x0 || 1)) * (W - m.l - m.r);
  const py = (y: number) =>
    H - m.b - ((Math.min(Math.max(y, y0), y1) - y0) / (y1 - y0)) * (H - m.t - m.b);
  const parts: string[] = [
    `<svg xmlns="http://www.w3.org/2000/svg" width="${W}" height="${H}" viewBox="0 0 ${W} ${H}" font-family="system-ui, sans-serif" font-size="13">`,
    `<rect width="${W}" height="${H}" fill="#ffffff"/>`,
    `<text x="${m.l}" y="28" font-size="16" font-weight="600">${esc(o.title)}</text>`,
  ];
  for (const t of niceTicks(x0, x1)) {
    parts.push(`<line x1="${px(t)}" x2="${px(t)}" y1="${m.t}" y2="${H - m.b}" stroke="#e5e5e5"/>`);
    parts.push(
      `<text x="${px(t)}" y="${H - m.b + 18}" text-anchor="middle" fill="#444">${t}</text>`,
    );
  }
  for (const t of niceTicks(y0, y1)) {
    const label = o.logY ? `1e${t}` : String(t);
    parts.push(`<line x1="${m.l}" x2="${W - m.r}" y1="${py(t)}" y2="${py(t)}" stroke="#e5e5e5"/>`);
    parts.push(
      `<text x="${m.l - 8}" y="${py(t) + 4}" text-anchor="end" fill="#444">${label}</text>`,
    );
  }
  parts.push(
    `<rect x="${m.l}" y="${m.t}" width="${W - m.l - m.r}" height="${H - m.t - m.b}" fill="none" stroke="#999"/>`,
  );
  parts.push(
    `<text x="${(m.l + W - m.r) / 2}" y="${H - 14}" text-anchor="middle">${esc(o.xLabel)}</text>`,
  );
  parts.push(
    `<text transform="translate(18 ${(m.t + H - m.b) / 2}) rotate(-90)" text-anchor="middle">${esc(o.yLabel)}</text>`,
  );
  series.forEach((s, i) => {
    const color = COLORS[i % COLORS.length]!;
    const pts: string[] = [];
    for (let k = 0; k < s.x.length; k++) {
      const y = tr(s.y[k]!);
      const yy = Number.isFinite(y) ? y : y1;
      pts.push(`${px(s.x[k]!).toFixed(1)},${py(yy).toFixed(1)}`);
    }
    parts.push(
      `<polyline fill="none" stroke="${color}" stroke-width="2" points="${pts.join(' ')}"/>`,
    );
    const ly = m.t + 14 + i * 22;
    parts.push(
      `<line x1="${W - m.r + 16}" x2="${W - m.r + 40}" y1="${ly - 4}" y2="${ly - 4}" stroke="${color}" stroke-width="3"/>`,
    );
    parts.push(`<text x="${W - m.r + 46}" y="${ly}">${esc(s.label)}</text>`);
  });
  parts.push('</svg>');
  return parts.join('\n') + '\n';
}
