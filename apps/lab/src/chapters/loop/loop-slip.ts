/**
 * Chapter 1's note on the slides' own slip: the naive loop reads `lastUpdateTime` but adds to
 * `lastUpdate`, so `lastUpdateTime` never moves and every frame's Δt is the time since the start.
 * The numbers are computed here (a pure function, tested), not written by hand.
 */
import { code, h } from '../../ui/dom.js';
import { textSection } from '../../ui/prose.js';

/** The naive loop exactly as the slide writes it. */
export const SLIDE_NAIVE = 'dt = GetCurrentTime() - lastUpdateTime; lastUpdate += dt;';
/** What it means: the time of the last update moves with every frame. */
export const SLIDE_NAIVE_MEANT = 'dt = GetCurrentTime() - lastUpdateTime; lastUpdateTime += dt;';

/**
 * Seconds of simulated time the slide's loop, as written, hands `update(dt)` over the first
 * `seconds` of a `hz` display (frames at k/hz, `lastUpdateTime` stuck at 0): the sum of every
 * frame's Δt, each the whole time since the start. As meant, it would be `seconds`.
 */
export function slipSimulatedSeconds(hz: number, seconds: number): number {
  const frames = Math.round(hz * seconds);
  const lastUpdateTime = 0; // the slip: only lastUpdate is ever written
  let lastUpdate = 0;
  let simulated = 0;
  for (let k = 1; k <= frames; k++) {
    const dt = k / hz - lastUpdateTime;
    lastUpdate += dt;
    simulated += dt;
  }
  return lastUpdate === simulated ? simulated : Number.NaN;
}

/** The section: the slide's line, what it does (at 60 Hz over 1 s), and the line as meant. */
export function slipSection(): HTMLElement {
  const at60 = slipSimulatedSeconds(60, 1);
  return textSection(
    'slip',
    'slip-title',
    'The slide’s own slip: lastUpdate or lastUpdateTime',
    'The naive loop on the slide reads one variable and writes another:',
    code(SLIDE_NAIVE),
    h(
      'p',
      { 'data-testid': 'slip-text', 'data-value': String(at60) },
      `As written, lastUpdateTime never moves, so each frame’s dt is the whole time since the start: the 60th frame of a 60 Hz display hands update() 1 s, not 16.7 ms, and the first second of the display adds up to ${at60.toFixed(1)} s of simulated time — a game that races further ahead with every frame. What the talk means, and what the variable-Δt panel above runs:`,
    ),
    code(SLIDE_NAIVE_MEANT),
  );
}
