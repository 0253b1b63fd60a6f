import { readFileSync } from 'node:fs';
import { describe, expect, it } from 'vitest';
import {
  BUTTON_WORD,
  ReplayPlayer,
  readReplay,
  replayFactory,
  setupFromReplayHeader,
  verifyReplay,
} from 'fixedstep';
import { GAMES, gameFromReplayHeader } from '@fixedstep/games';

// Written by the format-1 recorder (commit 805b17e) with each game's bot, seed 42: the runner
// 1800 ticks with keyframes every 600; CTF 1200 ticks, 2 players; Survival 900 ticks with
// keyframes every 300 and per-tick hashes.
const fixture = (id: string) =>
  new Uint8Array(readFileSync(new URL(`./fixtures/${id}-v1.fsr`, import.meta.url)));

describe('format-1 replays of the talk games still read and verify', () => {
  for (const id of ['runner', 'ctf', 'survival']) {
    it(`${id}: verifies through the registry and the game definitions`, () => {
      const bytes = fixture(id);
      const replay = readReplay(bytes);
      expect(replay.header.formatVersion).toBe(1);
      expect(replay.header.input.id).toBe(BUTTON_WORD.id);
      expect(verifyReplay(bytes, gameFromReplayHeader).ok).toBe(true);
      const result = verifyReplay(bytes, GAMES); // a list of definitions is a factory too
      expect(result).toMatchObject({ ok: true, ticks: replay.tickCount });
      const player = new ReplayPlayer(replay, GAMES);
      player.seek(replay.tickCount);
      player.seek(Math.floor(replay.tickCount / 3));
      expect(player.firstMismatch).toBeNull();
    });
  }

  it('a replay refuses a registry without its game, and another game’s definition, by name', () => {
    expect(() => verifyReplay(fixture('ctf'), replayFactory(GAMES[0]!))).toThrow(
      /unknown game "ctf" \(this build knows runner\)/,
    );
    expect(() =>
      verifyReplay(fixture('ctf'), (h) => GAMES[0]!.create(setupFromReplayHeader(GAMES[0]!, h))),
    ).toThrow(/replay of game "ctf", not "runner"/);
  });
});
