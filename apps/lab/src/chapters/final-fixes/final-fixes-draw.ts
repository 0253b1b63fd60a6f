/** Chapter 8's charts: the spiral bench's steps per frame, the clock bench's lag behind the display. */
import { Chart, alignSeries } from '../../ui/chart.js';
import * as fmt from '../../ui/format.js';
import {
  BACKWARDS_LOOPS,
  HISTORY_MS,
  SPIRAL_LOOPS,
  STALL_WORK_MS,
  type BenchRun,
  type FinalLab,
} from './final-fixes-lab.js';

/** Updates asked for by each display frame over time, for the three spiral loops. */
export function spiralChart(): Chart {
  return new Chart({
    height: 220,
    label: 'Updates asked for by each display frame over time, for the three loops',
    x: { format: (v) => `${v} s`, label: 'time' },
    y: {
      scale: 'asinh',
      label: 'steps per frame',
      format: (v) => fmt.count(v),
      range: (_min, max) => [0, Math.max(200, max * 1.5)],
      splits: (_min, max) =>
        [0, 1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10_000, 20_000, 50_000].filter(
          (v) => v <= max,
        ),
      size: 44,
    },
    series: [
      ...SPIRAL_LOOPS.map((l) => ({
        label: l.title,
        color: l.color,
        stepped: true,
        gaps: false,
        width: 2,
      })),
      {
        label: 'page stalls above this',
        color: '#f87171',
        dash: [5, 4],
        width: 1.25,
        gaps: false,
      },
    ],
  });
}

/** How far each clock loop's simulated time is behind the display's time, and the wall clock's. */
export function backwardsChart(): Chart {
  return new Chart({
    height: 220,
    label:
      'How far each loop’s simulated time is behind the display’s time, and how far the wall clock is',
    x: { format: (v) => `${v} s`, label: 'display time' },
    y: {
      format: (v) => `${v} s`,
      label: 'behind the display',
      size: 44,
      range: (min, max) => [Math.min(0, min), Math.max(2, max * 1.15)],
    },
    series: [
      ...BACKWARDS_LOOPS.map((l) => ({
        label: l.title,
        color: l.color,
        gaps: false,
        width: l.id === 'fixed' ? 1.5 : 2,
        dash: l.id === 'fixed' ? [6, 4] : undefined,
      })),
      { label: 'the wall clock', color: '#94a3b8', dash: [2, 4], width: 1.25, gaps: false },
    ],
  });
}

/** Both charts up to the lab's time: steps per frame of the spiral bench, lag of the clock bench. */
export function drawCharts(lab: FinalLab, stepsChart: Chart, simChart: Chart): void {
  const t = lab.timeMs;
  const from = Math.max(0, t - HISTORY_MS);
  const end = Math.max(t, 20_000);
  const series = lab.spiral.map((run) => since(run.frames, from, (f, k) => f[k + 1]!));
  const guard = Math.floor(STALL_WORK_MS / lab.settings.costMs);
  const aligned = alignSeries([...series, { xs: [from / 1000, end / 1000], ys: [guard, guard] }]);
  stepsChart.set(aligned, `${t}:${lab.settings.costMs}:${aligned[0]?.length ?? 0}`);

  const back = lab.backwards.map((run) =>
    since(run.frames, from, (f, k) => f[k]! / 1000 - f[k + 2]!),
  );
  const first = lab.backwards[0];
  const clock = since(first?.frames ?? [], from, (f, k) => (f[k]! - f[k + 3]!) / 1000);
  simChart.set(alignSeries([...back, clock]), `${t}:${first?.frames.length ?? 0}`);
}

/**
 * A chart series from a run's frames (four numbers a frame, its display time in ms first): the
 * frames from `fromMs` on, at their display time in seconds, each valued by `y`.
 */
function since(
  frames: readonly number[],
  fromMs: number,
  y: (frames: readonly number[], k: number) => number,
): { xs: number[]; ys: number[] } {
  const xs: number[] = [];
  const ys: number[] = [];
  for (let k = 0; k < frames.length; k += 4) {
    if (frames[k]! < fromMs) continue;
    xs.push(frames[k]! / 1000);
    ys.push(y(frames, k));
  }
  return { xs, ys };
}

/** Whether the run's simulated time went down within its last few frames. */
export function isGoingBack(run: BenchRun<string>): boolean {
  const f = run.frames;
  const n = f.length;
  for (let k = Math.max(4, n - 4 * 30); k < n; k += 4)
    if (f[k + 2]! < f[k - 2]! - 1e-9) return true;
  return false;
}

/** Display time of the run's last frame that advanced simulated time. */
export function lastProgress(run: BenchRun<string>): number {
  const f = run.frames;
  for (let k = f.length - 4; k >= 4; k -= 4) if (f[k + 2]! > f[k - 2]! + 1e-9) return f[k]!;
  return 0;
}
