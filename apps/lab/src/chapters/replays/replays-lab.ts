/**
 * The model behind chapter 5, "Replays": a replay file opened, verified and played back by
 * re-simulation with a {@link ReplayPlayer} — play, pause, speed, seek, a tick back or forward —
 * on a simulated display (or the page's real clock). While it plays it notes the state hash at
 * every checkpoint tick it passes, per display, so the page can show that every display rate
 * visits the very same states. No DOM here.
 */
import {
  ReplayError,
  ReplayPlayer,
  hex64,
  readReplay,
  verifyReplay,
  type Replay,
  type ReplayHeader,
  type ReplayMismatch,
  type Simulation,
  type VerifyResult,
} from 'fixedstep';
import { findGame, gameFromReplayHeader, type Game, type RegisteredGame } from '@fixedstep/games';
import { hashHex, scoreKeyOf, type DisplayRate, type DisplaySpec } from '../../games-view/games.js';
import { replayContents, type ReplayContents } from '../../games-view/replays.js';
import { DisplayClock, OnDisplayClock } from '../../shell/display-clock.js';

/** Where playback frames come from. */
export type Source = DisplayRate | 'real';

/** Playback speeds on offer (ticks run per tick of real time). */
export const SPEEDS = [1, 4, 16] as const;
export type Speed = (typeof SPEEDS)[number];

/** What the page shows about a replay file. */
export interface ReplayFacts {
  gameId: string;
  title: string;
  gameVersion: string;
  seed: number | undefined;
  players: readonly string[];
  ticks: number;
  tickRate: number;
  seconds: number;
  bytes: number;
  bytesPerMinute: number;
  checkpointEvery: number;
  keyframeEvery: number;
  keyframes: number;
  /** What the file holds, section by section (inputs, hashes, keyframes, header), bytes. */
  contents: ReplayContents;
}

/** What verification found, with the score the replay ends on (what a server would rank). */
export interface Verification {
  result: VerifyResult;
  /** The HUD after the last tick (when the game could be built). */
  finalHud: Readonly<Record<string, number>> | undefined;
  /** The ranked score after the last tick, if the game has one. */
  score: number | undefined;
  /** Milliseconds it took. */
  ms: number;
}

/** A checkpoint tick and the hash each display (and the file) had there. */
export interface Comparison {
  /** The latest checkpoint tick two displays (or the only one) passed while playing, or -1. */
  tick: number;
  /** The hash stored in the file for that tick. */
  stored: string | undefined;
  rows: { source: Source; hash: string }[];
  /** Whether every display's hash equals the stored one. */
  equal: boolean;
}

/** A person-readable account of why a file could not be opened. */
export function describeReplayError(e: unknown): { title: string; detail: string } {
  if (e instanceof ReplayError) {
    const titles: Record<string, string> = {
      TOO_LARGE: 'The file is too large to be a replay this lab accepts.',
      BAD_MAGIC: 'This is not a fixedstep replay file: it does not start with “FSREPLAY”.',
      TRUNCATED: 'The replay file is cut short: it is shorter than its header says.',
      TRAILING_DATA: 'The replay file has extra bytes after its end.',
      UNSUPPORTED_VERSION: 'This replay uses a format version this lab does not know.',
      BAD_CHECKSUM: 'The replay file is damaged: its checksum does not match its bytes.',
      WRONG_GAME: 'This replay is of another game.',
      CORRUPT: 'The replay file breaks the format’s rules (damaged, or written by a buggy tool).',
      GAME_REJECTED: 'The game refused this replay (another game, or another version of it).',
    };
    return { title: titles[e.code] ?? 'The replay could not be read.', detail: e.message };
  }
  return { title: 'The replay could not be read.', detail: String(e) };
}

/**
 * An opened replay and its player. Construction parses the file and builds tick 0: it throws a
 * {@link ReplayError} for a file it cannot play.
 */
export class ReplayLab extends OnDisplayClock {
  readonly bytes: Uint8Array;
  readonly replay: Replay;
  readonly player: ReplayPlayer;
  readonly def: RegisteredGame | undefined;
  /** Where the file came from (“your last game”, a file name …). */
  readonly label: string;
  protected readonly clock: DisplayClock;
  private inFrame = false;
  private verification: Verification | undefined;
  /** Checkpoint tick → hash, per display, for the ticks passed while playing. */
  readonly passes = new Map<Source, Map<number, string>>();
  private mismatches: ReplayMismatch[] = [];

  constructor(bytes: Uint8Array, label: string, display: DisplaySpec | 'real') {
    super();
    this.bytes = bytes;
    this.label = label;
    this.replay = readReplay(bytes);
    this.def = findGame(this.replay.header.gameId);
    this.player = new ReplayPlayer(this.replay, gameFromReplayHeader, {
      onTick: (tick, sim, resimulating) => {
        this.onTick(tick, sim, resimulating);
      },
      onMismatch: (m) => this.mismatches.push(m),
    });
    this.player.frame(0);
    this.clock = new DisplayClock(display, (t) => {
      this.frame(t);
    });
  }

  get header(): ReplayHeader {
    return this.replay.header;
  }

  get game(): Game {
    return this.player.sim as Game;
  }

  get tick(): number {
    return this.player.tick;
  }

  get displaySpec(): DisplaySpec | 'real' {
    return this.clock.displaySpec as DisplaySpec | 'real';
  }

  /** Mismatches the player met while playing or seeking. */
  get playbackMismatches(): readonly ReplayMismatch[] {
    return this.mismatches;
  }

  /** How far between the last two states to draw: the loop's alpha while playing, else 1. */
  get alpha(): number {
    return this.player.isPlaying ? this.player.loop.alpha : 1;
  }

  facts(): ReplayFacts {
    const r = this.replay;
    const h = r.header;
    const contents = replayContents(r);
    const tickRate = contents.tickRate;
    return {
      gameId: h.gameId,
      title: this.def?.info.title ?? h.gameId,
      gameVersion: h.gameVersion,
      seed: h.seeds[0],
      players: h.players,
      ticks: r.tickCount,
      tickRate,
      seconds: r.tickCount / tickRate,
      bytes: r.byteLength,
      bytesPerMinute: contents.bytesPerMinute,
      checkpointEvery: r.checkpointEvery,
      keyframeEvery: r.keyframeEvery,
      keyframes: r.keyframes.length,
      contents,
    };
  }

  /** Re-simulate the whole file and compare every stored hash (done once, then remembered). */
  verify(): Verification {
    if (this.verification) return this.verification;
    let game: Game | undefined;
    const t0 = performance.now();
    const result = verifyReplay(this.replay, (header) => {
      game = gameFromReplayHeader(header);
      return game;
    });
    const finalHud = result.ok && game ? game.hud() : undefined;
    const score = finalHud && this.def ? finalHud[scoreKeyOf(this.def)] : undefined;
    this.verification = { result, finalHud, score, ms: performance.now() - t0 };
    return this.verification;
  }

  /** The state hash at the current tick, 16 hex digits. */
  hashNow(): string {
    return hashHex(this.player.sim);
  }

  /** The hash the file stores for `tick` (a checkpoint tick), 16 hex digits. */
  storedHash(tick: number): string | undefined {
    const h = this.replay.checkpointAt(tick);
    return h === undefined ? undefined : hex64(h);
  }

  // ---------------------------------------------------------------- transport

  play(): void {
    if (this.player.ended) this.player.seek(0);
    this.player.play();
  }

  pause(): void {
    this.player.pause();
  }

  setSpeed(speed: number): void {
    this.player.setSpeed(speed);
  }

  seek(tick: number): void {
    const t = Math.max(0, Math.min(this.replay.tickCount, Math.round(tick)));
    this.player.seek(t);
  }

  stepForward(): void {
    this.player.pause();
    this.player.stepForward();
  }

  stepBack(): void {
    this.player.pause();
    this.player.stepBack();
  }

  // ---------------------------------------------------------------- the display

  /** Switch the display (rate, jitter, or the real clock); playback goes on. */
  setDisplay(spec: DisplaySpec | 'real'): void {
    this.clock.setDisplay(spec);
  }

  private frame(t: number): void {
    this.inFrame = true;
    try {
      this.player.frame(t);
    } finally {
      this.inFrame = false;
    }
  }

  private get source(): Source {
    const spec = this.displaySpec;
    return spec === 'real' ? 'real' : spec.hz;
  }

  private onTick(tick: number, sim: Simulation, resimulating: boolean): void {
    if (!this.inFrame || resimulating || tick % this.replay.checkpointEvery !== 0) return;
    let m = this.passes.get(this.source);
    if (!m) {
      m = new Map();
      this.passes.set(this.source, m);
    }
    m.set(tick, hashHex(sim));
  }

  /**
   * The latest checkpoint tick passed while playing on two or more displays (on the only one, if
   * only one has played), and the hash each of those displays had there, next to the one stored
   * in the file. A display that stopped early (the replay opened playing at 60 Hz, then paused)
   * does not hold the comparison back.
   */
  compare(): Comparison {
    const sources = [...this.passes.keys()];
    const need = Math.min(2, sources.length);
    const counts = new Map<number, number>();
    for (const s of sources) {
      for (const t of this.passes.get(s)!.keys()) counts.set(t, (counts.get(t) ?? 0) + 1);
    }
    let tick = -1;
    for (const [t, n] of counts) if (n >= need && t > tick) tick = t;
    const stored = tick >= 0 ? this.storedHash(tick) : undefined;
    const rows: Comparison['rows'] = [];
    for (const source of sources) {
      const hash = this.passes.get(source)!.get(tick);
      if (hash !== undefined) rows.push({ source, hash });
    }
    return {
      tick,
      stored,
      rows,
      equal: rows.length > 0 && rows.every((r) => r.hash === stored),
    };
  }
}
