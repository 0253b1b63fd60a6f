import { describe, expect, it } from 'vitest';
import { ReplayError, ReplayRecorder, hex64, readReplay } from 'fixedstep';
import {
  RunnerButtons,
  gameFromReplayHeader,
  replayOptionsFor,
  runnerGame,
} from '@fixedstep/games';
import { GameSession } from '../src/chapters/games/games-lab.js';
import { gameDef, hashHex } from '../src/games-view/games.js';
import { ReplayLab, describeReplayError } from '../src/chapters/replays/replays-lab.js';

function botReplay(id: string, ms: number, seed = 5): { bytes: Uint8Array; session: GameSession } {
  const session = new GameSession({
    def: gameDef(id),
    seed,
    mode: 'fixed',
    player: 'bot',
    display: { hz: 60, jitter: 0.1 },
    bot: true,
  });
  session.advanceTo(ms);
  return { bytes: session.replay()!, session };
}

describe('ReplayLab', () => {
  it('opens, describes and verifies a recorded game', () => {
    const { bytes, session } = botReplay('ctf', 20_000);
    const lab = new ReplayLab(bytes, 'a test', { hz: 60, jitter: 0 });
    const f = lab.facts();
    expect(f).toMatchObject({ gameId: 'ctf', seed: 5, players: ['bot'], tickRate: 60 });
    expect(f.ticks).toBe(session.game.tick);
    expect(f.bytes).toBe(bytes.length);
    expect(f.keyframes).toBe(0); // a replay is the inputs and the seed: the player re-simulates to seek
    const v = lab.verify();
    expect(v.result.ok).toBe(true);
    expect(v.finalHud).toEqual(session.game.hud());
    expect(lab.tick).toBe(0);
    expect(lab.hashNow()).toBe(lab.storedHash(0));
  });

  it('seeks to the very state the live game had at that tick, and steps back and forth', () => {
    const { bytes } = botReplay('survival', 25_000);
    const replay = readReplay(bytes);
    // The live game, again, tick by tick from the recorded inputs.
    const game = gameFromReplayHeader(replay.header);
    const live = new Map<number, string>();
    const inputs: number[] = [];
    for (let t = 0; t < replay.tickCount; t++) {
      game.step(replay.inputsAt(t, inputs));
      if ((t + 1) % 97 === 0) live.set(t + 1, hashHex(game));
    }
    const lab = new ReplayLab(bytes, 'a test', { hz: 144, jitter: 0 });
    for (const tick of [...live.keys()].reverse()) {
      lab.seek(tick);
      expect(lab.hashNow(), `tick ${tick}`).toBe(live.get(tick));
    }
    lab.seek(1000);
    const at1000 = lab.hashNow();
    lab.stepBack();
    expect(lab.tick).toBe(999);
    lab.stepForward();
    expect(lab.hashNow()).toBe(at1000);
    expect(lab.playbackMismatches).toEqual([]);
  });

  it('plays identically at 30 Hz and at 144 Hz: the same hash at the same tick', () => {
    const { bytes } = botReplay('ctf', 15_000);
    const lab = new ReplayLab(bytes, 'a test', { hz: 30, jitter: 0.2 });
    lab.play();
    lab.advanceBy(10_500); // past the first checkpoint after tick 0 (every 10 s)
    expect(lab.compare()).toMatchObject({ tick: 600, equal: true });
    lab.seek(0);
    lab.setDisplay({ hz: 144, jitter: 0.1 });
    lab.play();
    lab.advanceBy(10_500);
    const c = lab.compare();
    expect(c.tick).toBe(600);
    expect(c.rows.map((r) => r.source)).toEqual([30, 144]);
    expect(c.rows[0]!.hash).toBe(c.rows[1]!.hash);
    expect(c.stored).toBe(c.rows[0]!.hash);
    expect(c.equal).toBe(true);
  });

  it('compares the latest tick two displays passed, however briefly another one played', () => {
    const { bytes } = botReplay('ctf', 15_000);
    // The page opens a replay playing at 60 Hz; the reader pauses it early…
    const lab = new ReplayLab(bytes, 'a test', { hz: 60, jitter: 0 });
    lab.play();
    lab.advanceBy(1100);
    lab.pause();
    // …then plays it from the start at 30 Hz and at 144 Hz.
    for (const hz of [30, 144] as const) {
      lab.seek(0);
      lab.setDisplay({ hz, jitter: 0.1 });
      lab.play();
      lab.advanceBy(10_500);
      lab.pause();
    }
    const c = lab.compare();
    expect(c.tick).toBe(600);
    expect(c.rows.map((r) => r.source)).toEqual([30, 144]);
    expect(c.equal).toBe(true);
  });

  it('fast-forwards by running more ticks per frame, never longer ones', () => {
    const { bytes } = botReplay('runner', 20_000);
    const lab = new ReplayLab(bytes, 'a test', { hz: 60, jitter: 0 });
    lab.setSpeed(4);
    lab.play();
    lab.advanceBy(1000);
    const fast = lab.tick;
    lab.seek(0);
    lab.setSpeed(1);
    lab.play();
    lab.advanceBy(4000);
    // 240 ticks either way (give or take the frame that lands a hair after the last ms).
    for (const ticks of [fast, lab.tick]) {
      expect(ticks).toBeGreaterThanOrEqual(237);
      expect(ticks).toBeLessThanOrEqual(240);
    }
    // Played to the end, it pauses there; play again starts over.
    lab.setSpeed(16);
    lab.advanceBy(10_000);
    expect(lab.player.ended).toBe(true);
    expect(lab.player.isPlaying).toBe(false);
    lab.play();
    expect(lab.tick).toBe(0);
  });

  it('refuses a bad file with a ReplayError the page can explain', () => {
    const garbage = new TextEncoder().encode('this is not a replay, just some text');
    let error: unknown;
    try {
      new ReplayLab(garbage, 'garbage', { hz: 60, jitter: 0 });
    } catch (e) {
      error = e;
    }
    expect(error).toBeInstanceOf(ReplayError);
    expect((error as ReplayError).code).toBe('BAD_MAGIC');
    expect(describeReplayError(error).title).toContain('not a fixedstep replay');

    const { bytes } = botReplay('runner', 3000);
    const damaged = bytes.slice();
    damaged[40] = damaged[40]! ^ 0x10;
    expect(() => new ReplayLab(damaged, 'damaged', { hz: 60, jitter: 0 })).toThrow(/BAD_CHECKSUM/);
    expect(() => new ReplayLab(bytes.slice(0, 100), 'cut', { hz: 60, jitter: 0 })).toThrow(
      /TRUNCATED/,
    );
  });

  it('reports the first mismatch of a replay whose inputs do not give its hashes', () => {
    // A recorder fed other inputs than the game was stepped with: a forgery, in effect.
    const config = { seed: 3, players: 1 };
    const game = runnerGame.create(config);
    const rec = new ReplayRecorder(
      replayOptionsFor(runnerGame, config, ['eve'], { checkpointEvery: 60, keyframeEvery: 300 }),
    );
    rec.start(game);
    const jump = (1 << RunnerButtons.jump) | (1 << (16 + RunnerButtons.jump));
    for (let t = 0; t < 900; t++) {
      game.step([t === 200 ? jump : 0]);
      rec.record([0], game);
    }
    const lab = new ReplayLab(rec.finish(), 'forged', { hz: 60, jitter: 0 });
    const v = lab.verify();
    expect(v.result.ok).toBe(false);
    expect(v.result.firstMismatchTick).toBe(240);
    expect(v.result.lastGoodTick).toBe(180);
    expect(v.score).toBeUndefined();
    expect(hex64(lab.replay.checkpoints[0]!)).toBe(lab.hashNow());
  });
});
