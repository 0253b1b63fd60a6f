/**
 * Canvas renderers of the three games, shared by chapter 9 (live play), chapter 5 (replays) and
 * chapter 6 (network).
 * They only read a game's state — positions interpolated at `alpha` between the state before
 * the last update and the current one — and never write it.
 */
import {
  CTF,
  CtfGame,
  DIR_X,
  DIR_Y,
  FLAG_STAND_X,
  FLAG_STAND_Y,
  FlagState,
  OBSTACLE_KINDS,
  RUNNER_TUNING,
  RunnerGame,
  SURVIVAL,
  SurvivalGame,
  type Game,
} from '@fixedstep/games';
import { runnerHud, type Breach } from './games.js';

/** What a canvas to draw on looks like (the lab's SceneCanvas). */
export interface Surface {
  readonly ctx: CanvasRenderingContext2D;
  /** Backing-store size, device pixels. */
  readonly w: number;
  readonly h: number;
  readonly dpr: number;
}

export interface RenderOptions {
  /** Interpolation between the previous and the current state, 0–1. */
  alpha: number;
  /** The session's clock, ms (for blinking and fading). */
  nowMs: number;
  /** Things that went through walls, drawn as fading markers. */
  breaches?: readonly Breach[];
  /** The badge in the corner: what runs the game. */
  badge?: { text: string; tone: 'good' | 'bad' | 'info' };
  /** A line under the game-over title (e.g. "Space to run again"). */
  hint?: string;
  /**
   * The player slot whose screen this is: marked "YOU", and the one whose numbers the HUD shows
   * (kills, flags, lives). Default 0 (player 1), as on a single-player screen.
   */
  you?: number;
}

/** How long a "went through a wall" marker stays on screen, ms of session time. */
export const BREACH_MS = 1500;

/** Width / height of each game's canvas. */
export const ASPECT: Readonly<Record<string, number>> = {
  runner: 16 / 5.5,
  ctf: CTF.width / CTF.height,
  survival: SURVIVAL.width / SURVIVAL.height,
};

export const TEAM = {
  red: '#f87171',
  redDark: '#7f1d1d',
  blue: '#60a5fa',
  blueDark: '#1e3a8a',
} as const;

const BG = '#0a1122';
const FLOOR = '#0e172c';
const WALL = '#33466d';
const WALL_EDGE = '#6b84b5';
const TEXT = '#e6edf7';
const MUTED = '#a3b3cc';
const MONO = "ui-monospace, 'SF Mono', 'Cascadia Code', Menlo, Consolas, monospace";
const SANS = "system-ui, -apple-system, 'Segoe UI', Roboto, Arial, sans-serif";

function lerp(a: number, b: number, t: number): number {
  return a + (b - a) * t;
}

/** A font size in device pixels that suits the canvas. */
function fontPx(s: Surface, k = 1): number {
  return Math.round(Math.max(11 * s.dpr, Math.min(22 * s.dpr, s.w / 52)) * k);
}

/** Draw `game` on `s`. */
export function drawGame(s: Surface, game: Game, o: RenderOptions): void {
  const { ctx } = s;
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.globalAlpha = 1;
  ctx.fillStyle = BG;
  ctx.fillRect(0, 0, s.w, s.h);
  if (s.w <= 1 || s.h <= 1) return;
  if (game instanceof RunnerGame) drawRunner(s, game, o);
  else if (game instanceof CtfGame) drawCtf(s, game, o);
  else if (game instanceof SurvivalGame) drawSurvival(s, game, o);
  if (o.badge) drawBadge(s, o.badge);
}

// ---------------------------------------------------------------- shared bits

function drawBadge(s: Surface, badge: NonNullable<RenderOptions['badge']>): void {
  const { ctx } = s;
  const f = fontPx(s, 0.72);
  ctx.font = `600 ${f}px ${SANS}`;
  const pad = f * 0.55;
  const tw = ctx.measureText(badge.text).width;
  const x = pad;
  const y = s.h - pad - f * 1.5;
  const colors = {
    good: ['rgba(6, 78, 59, 0.85)', '#6ee7b7'],
    bad: ['rgba(127, 29, 29, 0.85)', '#fecaca'],
    info: ['rgba(30, 58, 95, 0.85)', '#bae6fd'],
  }[badge.tone];
  ctx.fillStyle = colors[0]!;
  roundRect(ctx, x, y, tw + pad * 2, f * 1.5, f * 0.4);
  ctx.fill();
  ctx.fillStyle = colors[1]!;
  ctx.textBaseline = 'middle';
  ctx.textAlign = 'left';
  ctx.fillText(badge.text, x + pad, y + f * 0.78);
}

function roundRect(
  ctx: CanvasRenderingContext2D,
  x: number,
  y: number,
  w: number,
  h: number,
  r: number,
): void {
  const rr = Math.max(0, Math.min(r, w / 2, h / 2));
  ctx.beginPath();
  ctx.moveTo(x + rr, y);
  ctx.arcTo(x + w, y, x + w, y + h, rr);
  ctx.arcTo(x + w, y + h, x, y + h, rr);
  ctx.arcTo(x, y + h, x, y, rr);
  ctx.arcTo(x, y, x + w, y, rr);
  ctx.closePath();
}

/** Text with a dark outline, readable on anything. */
function outlined(
  ctx: CanvasRenderingContext2D,
  text: string,
  x: number,
  y: number,
  fill: string,
  width: number,
): void {
  ctx.lineJoin = 'round';
  ctx.lineWidth = width;
  ctx.strokeStyle = 'rgba(5, 9, 20, 0.9)';
  ctx.strokeText(text, x, y);
  ctx.fillStyle = fill;
  ctx.fillText(text, x, y);
}

function gameOver(s: Surface, title: string, hint: string | undefined): void {
  const { ctx } = s;
  ctx.fillStyle = 'rgba(5, 9, 20, 0.45)';
  ctx.fillRect(0, 0, s.w, s.h);
  const f = fontPx(s, 2.1);
  ctx.textAlign = 'center';
  ctx.textBaseline = 'middle';
  ctx.font = `800 ${f}px ${MONO}`;
  outlined(ctx, title, s.w / 2, s.h / 2 - (hint ? f * 0.4 : 0), TEXT, f * 0.18);
  if (hint) {
    const g = fontPx(s, 0.9);
    ctx.font = `500 ${g}px ${SANS}`;
    outlined(ctx, hint, s.w / 2, s.h / 2 + f * 0.75, MUTED, g * 0.3);
  }
}

/** The empty scene with a few lines of text in its middle: the first a title, the rest muted. */
export function drawMessage(s: Surface, lines: readonly string[]): void {
  const { ctx } = s;
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.globalAlpha = 1;
  ctx.fillStyle = BG;
  ctx.fillRect(0, 0, s.w, s.h);
  const f = fontPx(s, 1.3);
  ctx.textAlign = 'center';
  ctx.textBaseline = 'middle';
  lines.forEach((line, i) => {
    ctx.font = `${i === 0 ? 600 : 400} ${f}px ${SANS}`;
    ctx.fillStyle = i === 0 ? TEXT : MUTED;
    ctx.fillText(line, s.w / 2, s.h / 2 + (i - (lines.length - 1) / 2) * f * 1.6);
  });
}

/** Fit an arena of `aw × ah` units (y down) into the surface, centred. */
class ArenaView {
  readonly k: number;
  readonly ox: number;
  readonly oy: number;
  constructor(s: Surface, aw: number, ah: number) {
    this.k = Math.min(s.w / aw, s.h / ah);
    this.ox = (s.w - aw * this.k) / 2;
    this.oy = (s.h - ah * this.k) / 2;
  }
  x(u: number): number {
    return this.ox + u * this.k;
  }
  y(u: number): number {
    return this.oy + u * this.k;
  }
}

function drawArena(
  s: Surface,
  v: ArenaView,
  aw: number,
  ah: number,
  rects: readonly { x0: number; y0: number; x1: number; y1: number }[],
  /** Drawn on the floor, under the grid and the walls (e.g. the bases' colours). */
  under?: () => void,
): void {
  const { ctx } = s;
  ctx.fillStyle = FLOOR;
  ctx.fillRect(v.x(0), v.y(0), aw * v.k, ah * v.k);
  under?.();
  // A faint floor grid, every 40 units.
  ctx.strokeStyle = 'rgba(141, 160, 189, 0.06)';
  ctx.lineWidth = 1;
  ctx.beginPath();
  for (let x = 40; x < aw; x += 40) {
    const X = Math.round(v.x(x)) + 0.5;
    ctx.moveTo(X, v.y(0));
    ctx.lineTo(X, v.y(ah));
  }
  for (let y = 40; y < ah; y += 40) {
    const Y = Math.round(v.y(y)) + 0.5;
    ctx.moveTo(v.x(0), Y);
    ctx.lineTo(v.x(aw), Y);
  }
  ctx.stroke();
  // Walls: solid blocks with a lit edge, at least 2 px thick so a 4-unit wall reads on a phone.
  const minPx = 2 * s.dpr;
  for (const r of rects) {
    let x = v.x(r.x0);
    let y = v.y(r.y0);
    let w = (r.x1 - r.x0) * v.k;
    let h = (r.y1 - r.y0) * v.k;
    if (w < minPx) {
      x -= (minPx - w) / 2;
      w = minPx;
    }
    if (h < minPx) {
      y -= (minPx - h) / 2;
      h = minPx;
    }
    ctx.fillStyle = WALL;
    ctx.fillRect(x, y, w, h);
    ctx.strokeStyle = WALL_EDGE;
    ctx.lineWidth = Math.max(1, s.dpr * 0.75);
    ctx.strokeRect(x + 0.5, y + 0.5, Math.max(0, w - 1), Math.max(0, h - 1));
  }
}

function drawBreaches(s: Surface, v: ArenaView, o: RenderOptions): void {
  const list = o.breaches;
  if (!list || list.length === 0) return;
  const { ctx } = s;
  for (const b of list) {
    const age = (o.nowMs - b.atMs) / BREACH_MS;
    if (age < 0 || age >= 1) continue;
    const x = v.x(b.x);
    const y = v.y(b.y);
    const r = (8 + 18 * age) * v.k;
    ctx.globalAlpha = 1 - age;
    ctx.strokeStyle = '#ff4d6d';
    ctx.lineWidth = 2 * s.dpr;
    ctx.beginPath();
    ctx.arc(x, y, r, 0, 2 * Math.PI);
    ctx.stroke();
    const c = 5 * v.k;
    ctx.beginPath();
    ctx.moveTo(x - c, y - c);
    ctx.lineTo(x + c, y + c);
    ctx.moveTo(x + c, y - c);
    ctx.lineTo(x - c, y + c);
    ctx.stroke();
  }
  ctx.globalAlpha = 1;
}

/** A player disc with a gun barrel pointing at `facing` (0–7). */
function drawShooter(
  ctx: CanvasRenderingContext2D,
  x: number,
  y: number,
  r: number,
  facing: number,
  fill: string,
  dark: string,
  lineW: number,
): void {
  const dx = DIR_X[facing] ?? 1;
  const dy = DIR_Y[facing] ?? 0;
  ctx.strokeStyle = dark;
  ctx.lineCap = 'round';
  ctx.lineWidth = r * 0.55;
  ctx.beginPath();
  ctx.moveTo(x, y);
  ctx.lineTo(x + dx * r * 1.7, y + dy * r * 1.7);
  ctx.stroke();
  ctx.strokeStyle = fill;
  ctx.lineWidth = r * 0.3;
  ctx.beginPath();
  ctx.moveTo(x, y);
  ctx.lineTo(x + dx * r * 1.65, y + dy * r * 1.65);
  ctx.stroke();
  ctx.beginPath();
  ctx.arc(x, y, r, 0, 2 * Math.PI);
  ctx.fillStyle = fill;
  ctx.fill();
  ctx.lineWidth = lineW;
  ctx.strokeStyle = dark;
  ctx.stroke();
  ctx.lineCap = 'butt';
}

function drawBullets(
  ctx: CanvasRenderingContext2D,
  v: ArenaView,
  b: CtfGame['state']['bullets'],
  alpha: number,
  color: (team: number) => string,
  dpr: number,
): void {
  ctx.lineCap = 'round';
  for (let i = 0; i < b.capacity; i++) {
    if (b.alive[i] !== 1) continue;
    const x = lerp(b.prevX[i]!, b.x[i]!, alpha);
    const y = lerp(b.prevY[i]!, b.y[i]!, alpha);
    const speed = Math.hypot(b.vx[i]!, b.vy[i]!) || 1;
    const tail = 18; // units of tracer behind the bullet
    const tx = x - (b.vx[i]! / speed) * tail;
    const ty = y - (b.vy[i]! / speed) * tail;
    const c = color(b.team[i]!);
    const grad = ctx.createLinearGradient(v.x(tx), v.y(ty), v.x(x), v.y(y));
    grad.addColorStop(0, 'rgba(255,255,255,0)');
    grad.addColorStop(1, c);
    ctx.strokeStyle = grad;
    ctx.lineWidth = Math.max(1.5 * dpr, 2.5 * v.k);
    ctx.beginPath();
    ctx.moveTo(v.x(tx), v.y(ty));
    ctx.lineTo(v.x(x), v.y(y));
    ctx.stroke();
    ctx.fillStyle = '#fff';
    ctx.beginPath();
    ctx.arc(v.x(x), v.y(y), Math.max(1.2 * dpr, b.radius * v.k), 0, 2 * Math.PI);
    ctx.fill();
  }
  ctx.lineCap = 'butt';
}

/**
 * The HUD's font size for one row of pills across the top of the canvas: {@link fontPx}, shrunk
 * (to 6 CSS px at the least) until the pills `texts`, `extraEm` em of other width, the gaps
 * between them and the margins fit side by side — so a small canvas shows a smaller HUD, not
 * overlapping pills. `fits` is false if they do not fit even at the smallest size: the caller
 * then leaves a pill out.
 */
function hudFont(
  s: Surface,
  texts: readonly string[],
  extraEm = 0,
): { readonly f: number; readonly fits: boolean } {
  const f = fontPx(s);
  const { ctx } = s;
  ctx.font = `700 ${f}px ${MONO}`;
  let w = (extraEm + 1.2 + 0.6 * (texts.length - 1)) * f; // other width, margins, gaps
  for (const t of texts) w += ctx.measureText(t).width + f; // text + padding
  if (w <= s.w) return { f, fits: true };
  const min = 6 * s.dpr;
  const scaled = Math.floor((f * s.w) / w);
  return { f: Math.max(min, scaled), fits: scaled >= min };
}

/** A HUD line in a dark pill of font size `f`: `text` at (x, y), aligned left or right. */
function hudText(
  s: Surface,
  text: string,
  x: number,
  y: number,
  align: 'left' | 'right',
  f: number,
  color = TEXT,
  weight = 700,
): number {
  const { ctx } = s;
  ctx.font = `${weight} ${f}px ${MONO}`;
  ctx.textBaseline = 'middle';
  ctx.textAlign = align;
  const w = ctx.measureText(text).width;
  const pad = f * 0.5;
  const bx = align === 'left' ? x : x - w - pad * 2;
  ctx.fillStyle = 'rgba(5, 9, 20, 0.72)';
  roundRect(ctx, bx, y, w + pad * 2, f * 1.6, f * 0.35);
  ctx.fill();
  ctx.fillStyle = color;
  ctx.fillText(text, align === 'left' ? x + pad : x - pad, y + f * 0.83);
  return f * 1.6;
}

// ---------------------------------------------------------------- capture the flag

function drawCtf(s: Surface, game: CtfGame, o: RenderOptions): void {
  const { ctx } = s;
  const st = game.state;
  const v = new ArenaView(s, CTF.width, CTF.height);
  const a = o.alpha;
  const you = o.you ?? 0;
  drawArena(s, v, CTF.width, CTF.height, game.walls.rects, () => {
    // The bases, tinted in their team's colour.
    ctx.fillStyle = 'rgba(248, 113, 113, 0.1)';
    ctx.fillRect(v.x(16), v.y(216), 184 * v.k, 208 * v.k);
    ctx.fillStyle = 'rgba(96, 165, 250, 0.1)';
    ctx.fillRect(v.x(CTF.width - 200), v.y(216), 184 * v.k, 208 * v.k);
  });

  // Flag stands, and the flags (home, dropped or carried).
  for (let t = 0; t < 2; t++) {
    const color = t === 0 ? TEAM.red : TEAM.blue;
    ctx.strokeStyle = color;
    ctx.globalAlpha = 0.55;
    ctx.lineWidth = 1.5 * s.dpr;
    ctx.setLineDash([4 * s.dpr, 3 * s.dpr]);
    ctx.beginPath();
    ctx.arc(v.x(FLAG_STAND_X[t]!), v.y(FLAG_STAND_Y[t]!), CTF.captureRadius * v.k, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.globalAlpha = 1;
  }

  // Players.
  const lw = Math.max(1, 1.5 * s.dpr);
  const r = Math.max(CTF.playerRadius * v.k, 5 * s.dpr);
  for (let p = 0; p < st.x.length; p++) {
    if (st.alive[p] !== 1) continue;
    const x = v.x(lerp(st.prevX[p]!, st.x[p]!, a));
    const y = v.y(lerp(st.prevY[p]!, st.y[p]!, a));
    const red = (p & 1) === 0;
    if (st.protect[p]! > 0) {
      ctx.strokeStyle = 'rgba(230, 237, 247, 0.55)';
      ctx.lineWidth = lw;
      ctx.setLineDash([3 * s.dpr, 3 * s.dpr]);
      ctx.beginPath();
      ctx.arc(x, y, r * 1.7, 0, 2 * Math.PI);
      ctx.stroke();
      ctx.setLineDash([]);
    }
    if (p === you) {
      ctx.strokeStyle = '#ffffff';
      ctx.lineWidth = 2 * s.dpr;
      ctx.beginPath();
      ctx.arc(x, y, r * 1.45, 0, 2 * Math.PI);
      ctx.stroke();
    }
    drawShooter(
      ctx,
      x,
      y,
      r,
      st.facing[p]!,
      red ? TEAM.red : TEAM.blue,
      red ? TEAM.redDark : TEAM.blueDark,
      lw,
    );
    // Health pips.
    for (let k = 0; k < CTF.health; k++) {
      ctx.fillStyle = k < st.health[p]! ? '#e6edf7' : 'rgba(230, 237, 247, 0.2)';
      ctx.fillRect(
        x - r + k * ((2 * r) / CTF.health) + 1,
        y + r * 1.45,
        (2 * r) / CTF.health - 2,
        Math.max(2, 2 * s.dpr),
      );
    }
    if (p === you) {
      const f = fontPx(s, 0.7);
      ctx.font = `700 ${f}px ${SANS}`;
      ctx.textAlign = 'center';
      ctx.textBaseline = 'bottom';
      outlined(ctx, 'YOU', x, y - r * 1.6, '#ffffff', f * 0.3);
    }
  }

  // Flags on top of everything but bullets.
  for (let t = 0; t < 2; t++) {
    let fx = st.flagX[t]!;
    let fy = st.flagY[t]!;
    if (st.flagState[t] === FlagState.carried) {
      const c = st.flagCarrier[t]!;
      fx = lerp(st.prevX[c]!, st.x[c]!, a) + 6;
      fy = lerp(st.prevY[c]!, st.y[c]!, a) - 4;
    }
    drawFlag(
      ctx,
      v,
      fx,
      fy,
      t === 0 ? TEAM.red : TEAM.blue,
      s.dpr,
      st.flagState[t] === FlagState.dropped,
    );
  }

  drawBullets(ctx, v, st.bullets, a, (team) => (team === 0 ? '#fca5a5' : '#93c5fd'), s.dpr);
  drawBreaches(s, v, o);

  // The HUD, as on the slide: "Kills: 1, Flags captured: 0".
  const hud = game.hud();
  // The HUD of this screen's player (the game's own hud() is player 1's).
  const left = `Kills: ${st.kills[you] ?? 0}, Flags captured: ${st.captures[you] ?? 0}`;
  const time = Math.max(0, hud.timeLeft ?? 0);
  const clock = `${Math.floor(time / 60)}:${String(time % 60).padStart(2, '0')}`;
  const scoreText = `${hud.red} : ${hud.blue}`;
  // Three pills in a row; the score pill is its text, 2 em of padding and 1.2 em of chips.
  const full = hudFont(s, [left, clock, scoreText], 2.2);
  const showClock = full.fits; // too narrow for three pills: the clock goes
  const { f } = showClock ? full : hudFont(s, [left, scoreText], 2.2);
  const m = Math.round(f * 0.6);
  hudText(s, left, m, m, 'left', f);
  const right = s.w - m;
  // Team scores: red and blue chips.
  ctx.font = `700 ${f}px ${MONO}`;
  const sw = ctx.measureText(scoreText).width;
  const pad = f * 0.5;
  const boxW = sw + pad * 4 + f * 1.2;
  const bx = right - boxW;
  ctx.fillStyle = 'rgba(5, 9, 20, 0.72)';
  roundRect(ctx, bx, m, boxW, f * 1.6, f * 0.35);
  ctx.fill();
  ctx.fillStyle = TEAM.red;
  ctx.beginPath();
  ctx.arc(bx + pad + f * 0.3, m + f * 0.8, f * 0.3, 0, 2 * Math.PI);
  ctx.fill();
  ctx.fillStyle = TEAM.blue;
  ctx.beginPath();
  ctx.arc(bx + boxW - pad - f * 0.3, m + f * 0.8, f * 0.3, 0, 2 * Math.PI);
  ctx.fill();
  ctx.fillStyle = TEXT;
  ctx.textAlign = 'center';
  ctx.textBaseline = 'middle';
  ctx.fillText(scoreText, bx + boxW / 2, m + f * 0.83);
  if (showClock) hudText(s, clock, bx - f * 0.6, m, 'right', f, MUTED, 600);
  if (game.over) {
    const title =
      hud.red === hud.blue ? 'DRAW' : (hud.red ?? 0) > (hud.blue ?? 0) ? 'RED WINS' : 'BLUE WINS';
    gameOver(s, title, o.hint);
  }
}

function drawFlag(
  ctx: CanvasRenderingContext2D,
  v: ArenaView,
  x: number,
  y: number,
  color: string,
  dpr: number,
  dropped: boolean,
): void {
  const px = v.x(x);
  const py = v.y(y);
  const h = 22 * v.k;
  ctx.strokeStyle = '#e6edf7';
  ctx.lineWidth = Math.max(1.5, 1.5 * dpr);
  ctx.beginPath();
  ctx.moveTo(px, py + h * 0.35);
  ctx.lineTo(px, py - h * 0.65);
  ctx.stroke();
  ctx.fillStyle = color;
  ctx.beginPath();
  ctx.moveTo(px, py - h * 0.65);
  ctx.lineTo(px + h * 0.7, py - h * 0.42);
  ctx.lineTo(px, py - h * 0.2);
  ctx.closePath();
  ctx.fill();
  ctx.strokeStyle = 'rgba(5, 9, 20, 0.8)';
  ctx.lineWidth = Math.max(1, dpr);
  ctx.stroke();
  if (dropped) {
    ctx.strokeStyle = color;
    ctx.setLineDash([2 * dpr, 2 * dpr]);
    ctx.beginPath();
    ctx.arc(px, py, 12 * v.k, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.setLineDash([]);
  }
}

// ---------------------------------------------------------------- survival

function drawSurvival(s: Surface, game: SurvivalGame, o: RenderOptions): void {
  const { ctx } = s;
  const st = game.state;
  const v = new ArenaView(s, SURVIVAL.width, SURVIVAL.height);
  const a = o.alpha;
  const you = o.you ?? 0;
  drawArena(s, v, SURVIVAL.width, SURVIVAL.height, game.walls.rects);

  // Enemies.
  const er = Math.max(SURVIVAL.enemyRadius * v.k, 4.5 * s.dpr);
  const lw = Math.max(1, 1.5 * s.dpr);
  for (let e = 0; e < st.enemyAlive.length; e++) {
    if (st.enemyAlive[e] !== 1) continue;
    const x = v.x(lerp(st.enemyPrevX[e]!, st.ex[e]!, a));
    const y = v.y(lerp(st.enemyPrevY[e]!, st.ey[e]!, a));
    const sp = Math.hypot(st.evx[e]!, st.evy[e]!) || 1;
    const ux = st.evx[e]! / sp;
    const uy = st.evy[e]! / sp;
    ctx.fillStyle = '#fb923c';
    ctx.beginPath();
    // A rounded arrowhead pointing where it runs.
    ctx.moveTo(x + ux * er * 1.35, y + uy * er * 1.35);
    ctx.lineTo(x - uy * er - ux * er * 0.8, y + ux * er - uy * er * 0.8);
    ctx.lineTo(x - ux * er * 0.35, y - uy * er * 0.35);
    ctx.lineTo(x + uy * er - ux * er * 0.8, y - ux * er - uy * er * 0.8);
    ctx.closePath();
    ctx.fill();
    ctx.strokeStyle = '#7c2d12';
    ctx.lineWidth = lw;
    ctx.stroke();
  }

  // Players.
  const pr = Math.max(SURVIVAL.playerRadius * v.k, 5 * s.dpr);
  for (let p = 0; p < st.x.length; p++) {
    if (st.alive[p] !== 1) continue;
    const x = v.x(lerp(st.prevX[p]!, st.x[p]!, a));
    const y = v.y(lerp(st.prevY[p]!, st.y[p]!, a));
    const blink = st.invulnerable[p]! > 0 && Math.floor(o.nowMs / 90) % 2 === 0;
    ctx.globalAlpha = blink ? 0.35 : 1;
    drawShooter(ctx, x, y, pr, st.facing[p]!, p === you ? '#34d399' : '#a78bfa', '#064e3b', lw);
    ctx.globalAlpha = 1;
  }

  drawBullets(ctx, v, st.bullets, a, () => '#fde047', s.dpr);
  drawBreaches(s, v, o);

  const hud = game.hud();
  // As on the slide: "Kills: 0, Lives: 15".
  const left = `Kills: ${st.kills[you] ?? 0}, Lives: ${st.lives[you] ?? 0}`;
  const wave = hud.wave ?? 0;
  const long = wave === 0 ? 'Get ready' : `Wave ${wave} · ${hud.enemies} on the field`;
  const full = hudFont(s, [left, long]);
  const keepLong = full.fits || wave === 0; // too narrow: the wave without its enemy count
  const right = keepLong ? long : `Wave ${wave}`;
  const { f } = keepLong ? full : hudFont(s, [left, right]);
  const m = Math.round(f * 0.6);
  hudText(s, left, m, m, 'left', f);
  hudText(s, right, s.w - m, m, 'right', f, MUTED, 600);
  if (game.over) gameOver(s, 'GAME OVER', o.hint);
}

// ---------------------------------------------------------------- runner

/** Metres of course on screen, and where the runner stands in them. */
const RUNNER_VIEW_M = 20;
const RUNNER_AT_M = 3;

function drawRunner(s: Surface, game: RunnerGame, o: RenderOptions): void {
  const { ctx } = s;
  const k = s.w / RUNNER_VIEW_M; // px per metre
  const groundY = s.h * 0.8;
  const dist = game.over ? game.distance : game.renderDistance(o.alpha);
  const left = dist - RUNNER_AT_M;
  const X = (m: number) => (m - left) * k;
  const Y = (m: number) => groundY - m * k;

  // Sky.
  const sky = ctx.createLinearGradient(0, 0, 0, groundY);
  sky.addColorStop(0, '#0a1024');
  sky.addColorStop(1, '#14203d');
  ctx.fillStyle = sky;
  ctx.fillRect(0, 0, s.w, groundY);
  // Stars, barely moving; far hills, scrolling slowly (parallax).
  ctx.fillStyle = 'rgba(203, 213, 225, 0.35)';
  const starShift = left * 0.05 * k;
  const span = s.w + 40;
  for (let i = 0; i < 40; i++) {
    const sx = (((i * 977) % 1000) / 1000) * span;
    const x = ((((sx - starShift) % span) + span) % span) - 20;
    const y = (((i * 613) % 1000) / 1000) * groundY * 0.6;
    const r = (i % 3 === 0 ? 1.3 : 0.8) * s.dpr;
    ctx.fillRect(x, y, r, r);
  }
  ctx.fillStyle = '#17264a';
  ctx.beginPath();
  ctx.moveTo(0, groundY);
  const far = left * 0.25;
  for (let px = 0; px <= s.w + 8; px += 8) {
    const m = far + px / k;
    const hgt = 1.1 + 0.55 * Math.sin(m * 0.45) + 0.3 * Math.sin(m * 1.13 + 1.7);
    ctx.lineTo(px, groundY - hgt * k);
  }
  ctx.lineTo(s.w, groundY);
  ctx.closePath();
  ctx.fill();

  // Ground: a line and dashes every 2 m that move with the course.
  ctx.fillStyle = '#0d1526';
  ctx.fillRect(0, groundY, s.w, s.h - groundY);
  ctx.strokeStyle = '#7487a4';
  ctx.lineWidth = Math.max(1, 2 * s.dpr);
  ctx.beginPath();
  ctx.moveTo(0, groundY);
  ctx.lineTo(s.w, groundY);
  ctx.stroke();
  ctx.strokeStyle = 'rgba(116, 135, 164, 0.45)';
  ctx.lineWidth = Math.max(1, s.dpr);
  ctx.beginPath();
  for (let m = Math.ceil(left / 2) * 2; m < left + RUNNER_VIEW_M + 2; m += 2) {
    const x = X(m);
    ctx.moveTo(x, groundY + 0.35 * k);
    ctx.lineTo(x + 0.5 * k, groundY + 0.35 * k);
  }
  for (let m = Math.ceil(left / 3) * 3 + 1; m < left + RUNNER_VIEW_M + 3; m += 3) {
    const x = X(m);
    ctx.moveTo(x, groundY + 0.8 * k);
    ctx.lineTo(x + 0.25 * k, groundY + 0.8 * k);
  }
  ctx.stroke();

  // Obstacles.
  for (let i = 0; i < game.obstacleCount; i++) {
    const ox = game.obstacleX(i);
    const kind = OBSTACLE_KINDS[game.obstacleKind(i)]!;
    if (ox > left + RUNNER_VIEW_M || ox + kind.width < left) continue;
    if (kind.bottom > 0)
      drawBird(ctx, X(ox), Y(kind.bottom + kind.height), kind.width * k, kind.height * k, ox);
    else {
      const x = X(ox);
      const y = Y(kind.height);
      ctx.fillStyle = '#f87171';
      roundRect(ctx, x, y, kind.width * k, kind.height * k, 0.12 * k);
      ctx.fill();
      ctx.fillStyle = 'rgba(127, 29, 29, 0.55)';
      for (let sx = x + 0.16 * k; sx < x + kind.width * k - 0.1 * k; sx += 0.3 * k) {
        ctx.fillRect(sx, y + 0.15 * k, Math.max(1, 0.06 * k), kind.height * k - 0.3 * k);
      }
    }
  }

  // The runner: a shadow that shrinks with height, a body, an eye.
  const y = game.over ? game.y : game.renderY(o.alpha);
  const ph = game.playerHeight;
  const pw = RUNNER_TUNING.playerWidth;
  const px = X(dist);
  ctx.fillStyle = 'rgba(0, 0, 0, 0.35)';
  ctx.beginPath();
  const shadow = Math.max(0.25, 1 - y / 3);
  ctx.ellipse(
    px + (pw * k) / 2,
    groundY + 0.08 * k,
    ((pw * k) / 2) * 1.3 * shadow,
    0.1 * k * shadow,
    0,
    0,
    2 * Math.PI,
  );
  ctx.fill();
  ctx.fillStyle = game.over ? '#94a3b8' : '#38bdf8';
  roundRect(ctx, px, Y(y + ph), pw * k, ph * k, 0.16 * k);
  ctx.fill();
  ctx.strokeStyle = '#0c4a6e';
  ctx.lineWidth = Math.max(1, 1.5 * s.dpr);
  ctx.stroke();
  ctx.fillStyle = '#0b1020';
  const eye = 0.12 * k;
  if (game.over) {
    ctx.font = `800 ${eye * 2.2}px ${SANS}`;
    ctx.textAlign = 'center';
    ctx.textBaseline = 'middle';
    ctx.fillText('×', px + pw * k * 0.68, Y(y + ph - 0.22));
  } else {
    ctx.fillRect(px + pw * k * 0.58, Y(y + ph - 0.16), eye, eye);
  }

  // The HUD, as on the slide: SCORE and HIGHSCORE, top right.
  const text = runnerHud(game.score, game.highscore);
  const speed = `${game.speed.toFixed(1)} m/s · run ${game.runs}`;
  const full = hudFont(s, [text, speed]);
  const { f } = full.fits ? full : hudFont(s, [text]); // too narrow for both: the speed goes
  const m = Math.round(f * 0.6);
  hudText(s, text, s.w - m, m, 'right', f);
  if (full.fits) hudText(s, speed, m, m, 'left', f, MUTED, 500);
  if (game.over) gameOver(s, 'GAME OVER', o.hint);
}

function drawBird(
  ctx: CanvasRenderingContext2D,
  x: number,
  y: number,
  w: number,
  h: number,
  seed: number,
): void {
  const flap = Math.sin(x / 18 + seed) > 0;
  ctx.fillStyle = '#fbbf24';
  ctx.beginPath();
  ctx.ellipse(x + w / 2, y + h * 0.55, w / 2, h * 0.3, 0, 0, 2 * Math.PI);
  ctx.fill();
  ctx.beginPath();
  ctx.moveTo(x + w * 0.3, y + h * 0.5);
  ctx.lineTo(x + w * 0.55, flap ? y - h * 0.1 : y + h * 1.1);
  ctx.lineTo(x + w * 0.75, y + h * 0.5);
  ctx.closePath();
  ctx.fill();
  ctx.fillStyle = '#0b1020';
  ctx.fillRect(x + w * 0.1, y + h * 0.45, Math.max(1, w * 0.07), Math.max(1, w * 0.07));
  ctx.fillStyle = '#f97316';
  ctx.beginPath();
  ctx.moveTo(x, y + h * 0.5);
  ctx.lineTo(x - w * 0.15, y + h * 0.6);
  ctx.lineTo(x + w * 0.02, y + h * 0.68);
  ctx.closePath();
  ctx.fill();
}
