import { readFileSync } from 'node:fs';
import { describe, expect, it } from 'vitest';
import {
  BUTTON_WORD,
  ReplayPlayer,
  ReplayRecorder,
  defineInput,
  PlayerInput,
  packButtons,
  readReplay,
  verifyReplay,
} from 'fixedstep';
import { recordStick, StickDot } from './axis-fixture.js';
import { arenaFactory, recordArena } from './replay-fixture.js';

// Written by the format-1 recorder (commit 805b17e): 600 ticks of the test arena, 2 players,
// checkpoints every 50 ticks, keyframes every 200, per-tick hashes.
const v1 = new Uint8Array(readFileSync(new URL('./fixtures/arena-v1.fsr', import.meta.url)));
// Written before centred axes (commit 1a043ba) by recordStick with { min: -1, max: 1, bits: 6 },
// then the only quantisation: 90 ticks, the first 30 never set (−1 then), 30 at 0.3, 30 at −1.
const stickLinear = new Uint8Array(
  readFileSync(new URL('./fixtures/stick-linear-v2.fsr', import.meta.url)),
);

describe('replay format versions', () => {
  it('reads and verifies a format-1 file: its inputs are BUTTON_WORD words', () => {
    const replay = readReplay(v1);
    expect(replay.header.formatVersion).toBe(1);
    expect(replay.header.input.id).toBe(BUTTON_WORD.id);
    expect(replay.words).toBe(1);
    expect(replay.tickCount).toBe(600);
    expect(replay.keyframes).toHaveLength(3);
    const result = verifyReplay(v1, arenaFactory);
    expect(result).toMatchObject({ ok: true, ticks: 600, lastGoodTick: 600 });
    // The same run recorded today reads back the same inputs and hashes in format 2.
    const today = recordArena({
      ticks: 600,
      seed: 3,
      checkpointEvery: 50,
      keyframeEvery: 200,
      tickHashes: true,
    });
    const now = readReplay(today.bytes);
    expect(now.header.formatVersion).toBe(2);
    expect(now.finalHash).toBe(replay.finalHash);
    expect([...now.checkpoints]).toEqual([...replay.checkpoints]);
    for (const t of [0, 1, 77, 599]) expect(now.inputsAt(t)).toEqual(replay.inputsAt(t));
  });

  it('plays a format-1 file, seeking through its stored keyframes', () => {
    const player = new ReplayPlayer(readReplay(v1), arenaFactory);
    player.seek(450);
    expect(player.tick).toBe(450);
    expect(player.firstMismatch).toBeNull();
  });

  it('stores the input schema in format 2 and refuses one that does not fit the inputs', () => {
    const aim = defineInput({ buttons: ['fire'], axes: { aim: { angle: 10 } } });
    const sim = {
      tick: 0,
      step() {
        this.tick++;
      },
      save: () => new Uint8Array(1),
      load() {
        // nothing to restore
      },
      hash: () => 5n,
    };
    const rec = new ReplayRecorder({
      gameId: 'aim',
      gameVersion: '1',
      tickRate: 60,
      players: ['a'],
      input: aim,
    });
    rec.start(sim);
    const input = new PlayerInput(aim);
    for (let t = 0; t < 120; t++) {
      input.buttons = t === 30 ? packButtons(1, 1) : 0;
      input.setAxis(0, t < 60 ? 0.5 : -2);
      sim.step();
      rec.record([input], sim);
    }
    expect(() => {
      input.buttons = packButtons(2, 0); // a button the schema does not have
      rec.record([input], { ...sim, tick: sim.tick + 1 });
    }).toThrow(/player 0/);
    const replay = readReplay(rec.finish());
    expect(replay.header.input.id).toBe(aim.id);
    expect(replay.words).toBe(2);
    expect(replay.runCount(0)).toBe(4); // aim 0.5, press, aim 0.5, aim −2
    const w = replay.wordsAt(30);
    expect(w[0]).toBe(packButtons(1, 1));
    const decoded = aim.decode(w, 0);
    expect(decoded.axis(0)).toBe(aim.value(0, aim.quantise(0, 0.5)));
    expect(aim.decode(replay.wordsAt(119), 0).axis(0)).toBe(aim.value(0, aim.quantise(0, -2)));
  });

  it('reads and verifies a replay of an even-quantised axis written before centred axes', () => {
    const replay = readReplay(stickLinear);
    const schema = replay.header.input;
    // The descriptor says linear: the file decodes with the quantisation it was recorded with.
    expect(schema.id).toBe('fbc8d6b2bf12b527');
    expect(schema.axes).toEqual([
      { kind: 'linear', name: 'moveX', bits: 6, min: -1, max: 1, deadZone: 0 },
    ]);
    const axisAt = (t: number) => (schema.decode(replay.wordsAt(t), 0) as PlayerInput).axis(0);
    expect(axisAt(0)).toBe(-1); // never set: step 0, min
    expect(axisAt(45)).toBe(schema.value(0, 41)); // 0.3: step round(1.3 / 2 × 63) = 41
    expect(axisAt(45)).toBe(-1 + (41 * 2) / 63);
    expect(axisAt(89)).toBe(-1);
    expect(replay.finalHash).toBe(0x811de2501771cb9bn);
    expect(verifyReplay(stickLinear, () => new StickDot())).toMatchObject({ ok: true, ticks: 90 });
    // The same definition with centred: false records the same bytes today.
    const again = recordStick(
      defineInput({ axes: { moveX: { min: -1, max: 1, bits: 6, centred: false } } }),
    );
    expect([...again]).toEqual([...stickLinear]);
    // The default today is centred: another schema (another id), idle reads 0, not −1.
    const centred = defineInput({ axes: { moveX: { min: -1, max: 1, bits: 6 } } });
    expect(centred.id).not.toBe(schema.id);
    const dot = new StickDot();
    dot.step([new PlayerInput(centred)]);
    expect(dot.x).toBe(0);
  });
});
