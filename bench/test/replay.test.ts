import { describe, expect, it } from 'vitest';
import { verifyReplay } from 'fixedstep';
import { GAMES, gameFromReplayHeader, runnerGame } from '@fixedstep/games';
import { quickRun } from '../lib/suite.js';
import type { AllocationSection, TableSection } from '../lib/report.js';
import suite, {
  bareStep,
  botAndStep,
  botConfig,
  recordBotGame,
  replaySize,
  resimulation,
  verification,
} from '../suites/replay.js';

describe.each(GAMES.map((def) => ({ id: def.info.id, def })))('replay suite: $id', ({ def }) => {
  const rec = recordBotGame(def, 10 * def.info.tickRate);

  it('records a bot game that verifies, with the registered config', () => {
    expect(rec.replay.header.gameId).toBe(def.info.id);
    expect(rec.replay.tickCount).toBe(rec.ticks);
    expect(def.decodeConfig(rec.replay.header.config)).toEqual(botConfig(def));
    expect(verifyReplay(rec.bytes, gameFromReplayHeader).ok).toBe(true);
  });

  it('the candidates do the same work: every tick of the replay', () => {
    expect(bareStep(rec).run(2)).toBe(2 * rec.ticks);
    expect(verification(rec, false).run(2)).toBe(2 * rec.ticks);
    expect(verification(rec, true).run(1)).toBe(rec.ticks);
  });

  it('the allocation candidates tick a live match: the recorded one again from its start, a new one when over', () => {
    const again = resimulation(rec);
    expect(again.run(rec.ticks)).toBe(rec.ticks);
    expect(again.run(5)).toBe(5);
    const bots = botAndStep(def);
    expect(bots.run(100)).toBe(100);
  });

  it('the bare loop reaches the recorded final state', () => {
    const game = def.create(rec.config);
    const players = rec.config.players;
    const frame = new Array<number>(players).fill(0);
    for (let t = 0; t < rec.ticks; t++) {
      for (let p = 0; p < players; p++) frame[p] = rec.inputs[t * players + p]!;
      game.step(frame);
    }
    expect(game.hash()).toBe(rec.replay.finalHash);
  });
});

describe('replay suite: a finished match', () => {
  it('bots + step() goes on with a new match when one is over', () => {
    // Capture the flag ends by its time limit: 10 minutes.
    const ctf = GAMES.find((g) => g.info.id === 'ctf')!;
    const bots = botAndStep(ctf);
    // Ticks of the match being played: fewer than were run, as it started again.
    const tick = bots.run(40_000);
    expect(tick).toBeGreaterThan(0);
    expect(tick).toBeLessThan(36_001);
    expect(bots.run(10)).toBe(tick + 10);
  });
});

describe('replay suite: sizes', () => {
  it('measures bytes per minute from the file and its INPUTS section', () => {
    const rec = recordBotGame(runnerGame, 2 * 3600);
    const size = replaySize(rec);
    expect(size.minutes).toBe(2);
    expect(size.fileBytes).toBe(rec.bytes.length);
    expect(size.filePerMinute).toBe(rec.bytes.length / 2);
    const inputs = rec.replay.sections.find((s) => s.name === 'INPUTS')!;
    expect(size.inputsPerMinute).toBe(inputs.length / 2);
    expect(size.runsPerMinute).toBe(rec.replay.runCount(0) / 2);
    // The runner's bot: a couple of hundred bytes of inputs a minute, under a kilobyte in all.
    expect(size.inputsPerMinute).toBeLessThan(400);
    expect(size.filePerMinute).toBeLessThan(1200);
  });

  it('a verification that fails throws instead of being timed', () => {
    const rec = recordBotGame(runnerGame, 600);
    const damaged = { ...rec, bytes: rec.bytes.slice() };
    damaged.bytes[100] = damaged.bytes[100]! ^ 0xff;
    expect(() => verification(damaged, true).run(1)).toThrow();
  });
});

describe('replay suite: a tiny run', () => {
  it('reports speed, size and allocation for every registered game', async () => {
    const { sections, comparisons } = await quickRun(suite);
    expect(comparisons).toHaveLength(GAMES.length);
    for (const c of comparisons) {
      expect(c.candidates.map((x) => x.name)).toEqual([
        'bare step() loop',
        'verifyReplay(parsed)',
        'verifyReplay(file bytes)',
      ]);
    }
    const tables = sections.filter((s): s is TableSection => s.kind === 'table');
    expect(tables.map((t) => t.rows.map((r) => r[0]))).toEqual([
      GAMES.map((g) => g.info.id),
      GAMES.map((g) => g.info.id),
      GAMES.map((g) => g.info.id),
      GAMES.flatMap((g) => [g.info.id, g.info.id]),
    ]);
    // CPU time: the bare loop beside verification, with the goals in the title and per row.
    const cpu = tables[1]!;
    expect(cpu.title).toMatch(
      /verifyReplay ≤ 1\.3× the bare step for ctf and survival, ctf ≥ 1 M ticks\/s/,
    );
    expect(cpu.header).toEqual([
      'game',
      'replay',
      'bare step(), ticks/s',
      'verifyReplay, ticks/s',
      'verify / bare',
      'goals',
    ]);
    expect(cpu.rows.map((r) => r[5]!.replace(/[✓✗] /g, ''))).toEqual(
      GAMES.map((g) =>
        g.info.id === 'ctf' ? 'ratio, speed' : g.info.id === 'survival' ? 'ratio' : '—',
      ),
    );
    // The stored size, bots beside the human-pace model: the model changes keys less often.
    const pace = tables[3]!.rows;
    expect(pace.map((r) => r[1])).toEqual(
      GAMES.flatMap(() => ['bots', 'human pace (≥ 200 ms a key)']),
    );
    for (let i = 0; i < pace.length; i += 2) {
      expect(Number(pace[i + 1]![2])).toBeLessThanOrEqual(Number(pace[i]![2]));
    }
    const alloc = sections.find((s): s is AllocationSection => s.kind === 'allocation');
    // Measured under node --expose-gc (npm run bench), skipped under vitest.
    const measured =
      alloc?.skipped === undefined ? alloc?.candidates.map((c) => c.name) : 'skipped';
    expect([
      GAMES.flatMap((g) => [`${g.info.id}: bots + step()`, `${g.info.id}: re-simulation`]),
      'skipped',
    ]).toContainEqual(measured);
  });
});
