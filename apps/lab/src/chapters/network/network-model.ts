/**
 * Chapter 6, network — what the three models' matches share: the settings, the readouts, and the
 * probes that measure, the same way for every model, the bytes each sends, the time from an input
 * to the screens, and the corrections each shows. No DOM.
 */
import { SimulatedLink, type LinkConditions } from 'fixedstep';
import type { Game, RegisteredGame } from '@fixedstep/games';
import { SimulatedMachines, type Agreement } from '../../shell/simulated-machines.js';

/** The three network models, side by side. */
export type NetMode = 'statesync' | 'lockstep' | 'rollback';
export const NET_MODES: readonly NetMode[] = ['statesync', 'lockstep', 'rollback'];
export const NET_GAMES = ['ctf', 'survival'] as const;
export type NetGameId = (typeof NET_GAMES)[number];

/** Hashes are compared at checkpoints this many ticks apart (1 s at 60 Hz). */
export const CHECKPOINT_TICKS = 60;
/** Bots re-decide every this many ticks and hold in between (a human-like 100 ms). */
export const BOT_EVERY = 6;
/** A correction moving a player by less than this (game units) is not counted as one. */
export const VISIBLE_CORRECTION = 0.5;
/** Farther than this (game units) is a respawn, not a correction: drawn at once, never blended. */
export const TELEPORT_UNITS = 40;

/** Whether a change of `units` is a correction the table counts. */
export function visibleCorrection(units: number): boolean {
  return units >= VISIBLE_CORRECTION && units <= TELEPORT_UNITS;
}

export interface NetSettings {
  game: NetGameId;
  seed: number;
  latencyMs: number;
  jitterMs: number;
  /** 0–1. */
  loss: number;
  /** Player 0 on the keyboard instead of its bot. */
  keyboard: boolean;
}

export const DEFAULT_NET_SETTINGS: Readonly<NetSettings> = {
  game: 'ctf',
  seed: 7,
  latencyMs: 80,
  jitterMs: 20,
  loss: 0.02,
  keyboard: false,
};

export function linkOf(s: NetSettings): LinkConditions {
  return { latencyMs: s.latencyMs, jitterMs: s.jitterMs, loss: s.loss };
}

/**
 * What the page shows of one match: its numbers, and whether the machines agree (lockstep and
 * rollback: the relay's desyncs; state sync: bad snapshots, and the server's hash too).
 */
export interface MatchReadouts extends Agreement {
  mode: NetMode;
  ticks: [number, number];
  /** Lockstep: input delay now, ticks (the larger of the two players'). */
  inputDelay: number;
  /** Rollback: rollbacks of both players, and the deepest, ticks. */
  rollbacks: number;
  maxDepth: number;
  stalls: number;
  rttMs: number;
  /** State sync: render delay (ms), prediction lead (ticks), snapshots received (both machines). */
  renderDelayMs: number;
  lead: number;
  snapshots: number;
}

/** What the comparison table shows of one model. */
export interface ModelNumbers {
  mode: NetMode;
  /** Bytes a second per client, client → server and back (payload, no frame headers). */
  upBytesPerSecond: number;
  downBytesPerSecond: number;
  /**
   * Mean time from player 1's input being sampled to a screen showing its effect, ms: its own
   * screen, and the other player's. NaN until measured.
   */
  ownLatencyMs: number;
  otherLatencyMs: number;
  /**
   * Corrections shown: a prediction that a snapshot or a rollback moved a drawn player by
   * {@link VISIBLE_CORRECTION} to {@link TELEPORT_UNITS} units.
   */
  corrections: number;
  /** The largest of those, game units. */
  largestCorrection: number;
  /** Whether corrections glide on screen (state sync smooths them) or jump. */
  smoothed: boolean;
}

/** One match of one model, on its own virtual clock. */
export interface ModelMatch {
  readonly mode: NetMode;
  /** Buttons held on the keyboard (player 0 when `settings.keyboard`). */
  keys: number;
  /** Whether the page's real frames drive the machines (instead of simulated 60 Hz displays). */
  realFrames: boolean;
  readonly nowMs: number;
  advanceTo(ms: number): void;
  realFrame(ms: number): void;
  setLink(c: LinkConditions): void;
  readouts(): MatchReadouts;
  numbers(): ModelNumbers;
  /**
   * What machine `i` draws now, the blend between its last two states, and its own player slot
   * (the relay's welcome: the screen marks that player "YOU" and shows its HUD).
   */
  view(i: 0 | 1): MachineView | undefined;
}

/** What one machine draws: its game, the blend, its tick and its own player's slot. */
export interface MachineView {
  game: Game;
  alpha: number;
  tick: number;
  /** The machine's own player (0 = player 1); before its welcome, the order it connected in. */
  slot: number;
}

/**
 * Times from player 1's inputs to the screens. Every {@link BOT_EVERY}-th tick's input is timed:
 * from the moment the session asks for it to the first frame each screen shows a state that
 * includes it (a state after that tick).
 */
export class LatencyProbe {
  private readonly pending = new Map<number, { at: number; own: boolean; other: boolean }>();
  private own = { sum: 0, n: 0 };
  private other = { sum: 0, n: 0 };

  /** Player 1's input for `tick` was sampled at `ms`. */
  sample(tick: number, ms: number): void {
    if (tick % BOT_EVERY !== 0 || this.pending.has(tick)) return;
    this.pending.set(tick, { at: ms, own: false, other: false });
    if (this.pending.size > 600) this.pending.delete(this.pending.keys().next().value!);
  }

  /** A frame at `ms`: player 1's screen shows the inputs of ticks before `ownTick`, player 2's before `otherTick`. */
  frame(ms: number, ownTick: number, otherTick: number): void {
    for (const [t, s] of this.pending) {
      if (!s.own && t < ownTick) {
        s.own = true;
        this.own.sum += ms - s.at;
        this.own.n++;
      }
      if (!s.other && t < otherTick) {
        s.other = true;
        this.other.sum += ms - s.at;
        this.other.n++;
      }
      if (s.own && s.other) this.pending.delete(t);
    }
  }

  get ownMs(): number {
    return this.own.n === 0 ? NaN : this.own.sum / this.own.n;
  }

  get otherMs(): number {
    return this.other.n === 0 ? NaN : this.other.sum / this.other.n;
  }
}

/** Bytes a second per client over two links (client → server is direction 0). */
export function traffic(links: readonly SimulatedLink[], ms: number): { up: number; down: number } {
  const s = Math.max(ms, 1) / 1000;
  let up = 0;
  let down = 0;
  for (const l of links) {
    up += l.stats[0].bytesSent;
    down += l.stats[1].bytesSent;
  }
  return { up: up / links.length / s, down: down / links.length / s };
}

/** How far the players moved between two states of one game (the largest, game units). */
export function playerShift(before: Game, after: Game): number {
  const a = (before as unknown as { state: PlayerState }).state;
  const b = (after as unknown as { state: PlayerState }).state;
  let most = 0;
  for (let p = 0; p < a.x.length; p++) {
    if (a.alive[p] !== 1 || b.alive[p] !== 1) continue;
    const dx = b.x[p]! - a.x[p]!;
    const dy = b.y[p]! - a.y[p]!;
    most = Math.max(most, Math.sqrt(dx * dx + dy * dy));
  }
  return most;
}

/** The part of an arena game's state the chapter reads: players by slot. */
export interface PlayerState {
  readonly x: Float64Array;
  readonly y: Float64Array;
  readonly prevX: Float64Array;
  readonly prevY: Float64Array;
  readonly alive: Uint8Array;
}

/**
 * What the three models' matches share: two machines on simulated links seeded from the settings,
 * each player's input (the keyboard or its bot), the latency probe, the corrections counted and
 * the links' traffic.
 */
export abstract class TwoPlayerMatch extends SimulatedMachines implements ModelMatch {
  abstract readonly mode: NetMode;
  /** Buttons held on the keyboard (player 0 when `settings.keyboard`). */
  keys = 0;
  protected readonly probe = new LatencyProbe();
  private corrections = 0;
  private largestCorrection = 0;

  constructor(readonly settings: NetSettings) {
    super();
  }

  abstract readouts(): MatchReadouts;
  abstract view(i: 0 | 1): MachineView | undefined;

  /** The link of the machine that connects `slot`-th (seeded by the settings' seed). */
  protected newLink(slot: 0 | 1): SimulatedLink {
    return new SimulatedLink({
      scheduler: this.scheduler,
      seed: this.settings.seed * 7919 + slot,
      ...linkOf(this.settings),
    });
  }

  /**
   * A machine's `localInput`: player 0 on the keyboard (with `settings.keyboard`), otherwise the
   * player's bot; `me` says which player the machine plays (its welcome's slot). Player 0's inputs
   * are timed by the latency probe.
   */
  protected playerInput(
    def: RegisteredGame,
    me: () => number,
  ): (tick: number, sim: object) => number {
    let held = 0;
    let prevKeys = 0;
    return (tick, sim) => {
      const slot = me();
      let input: number;
      if (this.settings.keyboard && slot === 0) {
        // Held buttons in the low half, this tick's new presses in the high half.
        const down = this.keys;
        input = (down | ((down & ~prevKeys) << 16)) >>> 0;
        prevKeys = down;
      } else {
        if (tick % BOT_EVERY === 0) held = def.bot(sim as Game, slot);
        input = held;
      }
      if (slot === 0) this.probe.sample(tick, this.scheduler.now);
      return input;
    };
  }

  /** A prediction was corrected by `units`: counted when visible ({@link visibleCorrection}). */
  protected noteCorrection(units: number): void {
    if (!visibleCorrection(units)) return;
    this.corrections++;
    this.largestCorrection = Math.max(this.largestCorrection, units);
  }

  numbers(): ModelNumbers {
    const { up, down } = traffic(this.links, this.scheduler.now);
    return {
      mode: this.mode,
      upBytesPerSecond: up,
      downBytesPerSecond: down,
      ownLatencyMs: this.probe.ownMs,
      otherLatencyMs: this.probe.otherMs,
      corrections: this.corrections,
      largestCorrection: this.largestCorrection,
      // State sync glides its corrections; a rollback's jump.
      smoothed: this.mode === 'statesync',
    };
  }
}
