import { describe, expect, it } from 'vitest';
import fc from 'fast-check';
import {
  BUTTON_WORD,
  FixedLoop,
  InputSampler,
  PlayerInput,
  anyBit,
  defineInput,
  deinterleave,
  downBit,
  heldOnly,
  inputSchemaFromDescriptor,
  interleave,
  isDown,
  packButtons,
  pressedBit,
  wasPressed,
} from 'fixedstep';

/** A twin-stick schema's definition, new at every call. */
function twinStickDefinition() {
  return {
    buttons: ['left', 'right', 'up', 'down', 'fire'] as const,
    axes: {
      aim: { angle: 10 },
      moveX: { min: -1, max: 1, bits: 8 },
      throttle: { min: 0, max: 1, bits: 16 },
    },
  };
}

const twinStick = defineInput(twinStickDefinition());

describe('the button word', () => {
  it('has one layout: down bits 0–15, pressed bits 16–31', () => {
    expect(downBit(3)).toBe(8);
    expect(pressedBit(3)).toBe(8 << 16);
    expect(pressedBit(15)).toBe(0x80000000);
    expect(anyBit(0)).toBe(0x10001);
    const w = packButtons(0b101, 0b100);
    expect(isDown(w, 0) && isDown(w, 2) && !isDown(w, 1)).toBe(true);
    expect(wasPressed(w, 2) && !wasPressed(w, 0)).toBe(true);
    expect(heldOnly(w)).toBe(0b101);
    expect(() => downBit(16)).toThrow(/0 to 15, got 16/);
  });

  it('interleave is a bijection on u32 that puts a button’s two bits side by side', () => {
    expect(interleave(packButtons(1, 1))).toBe(0b11);
    expect(interleave(packButtons(0b10, 0))).toBe(0b100);
    fc.assert(
      fc.property(
        fc.integer({ min: 0, max: 0xffffffff }),
        (v) => deinterleave(interleave(v)) === v,
      ),
    );
  });
});

describe('input schemas', () => {
  it('a schema without axes is one word and its input is the plain button number', () => {
    const s = defineInput({ buttons: ['jump', 'duck'] });
    expect(s.words).toBe(1);
    expect(s.button).toEqual({ jump: 0, duck: 1 });
    const out = new Uint32Array(1);
    s.encode(packButtons(0b11, 0b01), out, 0);
    expect(s.decode(out, 0)).toBe(packButtons(0b11, 0b01));
    expect(() => {
      s.encode(packButtons(0b100, 0), out, 0);
    }).toThrow(/buttons this schema does not define/);
    expect(s.problem(Uint32Array.of(packButtons(0b100, 0)), 0)).toMatch(/does not define/);
    expect(s.problem(Uint32Array.of(packButtons(0b11, 0b10)), 0)).toBeUndefined();
  });

  it('BUTTON_WORD, written out by hand, is exactly the schema defineInput builds for b0 … b15', () => {
    const built = defineInput({ buttons: Array.from({ length: 16 }, (_, i) => `b${i}`) });
    expect([...BUTTON_WORD.descriptor]).toEqual([...built.descriptor]);
    expect(BUTTON_WORD.id).toBe(built.id);
    expect(BUTTON_WORD.button).toEqual(built.button);
    expect(BUTTON_WORD.axes).toEqual(built.axes);
    const a = new Uint32Array(2);
    const b = new Uint32Array(2);
    for (const v of [0, 1, 0x10001, 0xffff0000, 0xffffffff]) {
      BUTTON_WORD.encode(v, a, 1);
      built.encode(v, b, 1);
      expect(a[1]).toBe(b[1]);
      expect(BUTTON_WORD.decode(a, 1)).toBe(built.decode(b, 1));
      expect(BUTTON_WORD.problem(a, 1)).toBe(built.problem(b, 1));
      BUTTON_WORD.missing(a, 1, a, 0);
      built.missing(b, 1, b, 0);
      expect(a[0]).toBe(b[0]);
    }
    expect(() => {
      BUTTON_WORD.encode(-1, a, 0);
    }).toThrow(/must be a u32/);
    expect(() => BUTTON_WORD.quantise(0, 1)).toThrow(/no axes/);
    expect(BUTTON_WORD.neutral()).toBe(built.neutral());
  });

  it('BUTTON_WORD takes every u32, like the classic ButtonInput', () => {
    expect(BUTTON_WORD.words).toBe(1);
    expect(BUTTON_WORD.problem(Uint32Array.of(0xffffffff), 0)).toBeUndefined();
    expect(BUTTON_WORD.buttons).toHaveLength(16);
  });

  it('packs axes into words after the button word, never across a word boundary', () => {
    // 10 + 8 bits in word 1; the 16-bit axis does not fit the 14 left, so it starts word 2.
    expect(twinStick.words).toBe(3);
    const p = new PlayerInput(twinStick);
    p.buttons = packButtons(0b10001, 0b10000);
    p.steps[0] = 1023;
    p.steps[1] = 255;
    p.steps[2] = 65535;
    const out = new Uint32Array(3);
    twinStick.encode(p, out, 0);
    expect([...out]).toEqual([p.buttons, 1023 | (255 << 10), 65535]);
    const back = twinStick.decode(out, 0);
    expect(back.buttons).toBe(p.buttons);
    expect([...back.steps]).toEqual([1023, 255, 65535]);
    expect(twinStick.problem(Uint32Array.of(0, 1 << 18, 0), 0)).toMatch(/bits no axis uses/);
    expect(twinStick.problem(Uint32Array.of(0, 1 << 16, 1 << 15), 0)).toBeUndefined();
    // moveX is centred: its field 0x80 (−128) is no level.
    expect(twinStick.problem(Uint32Array.of(0, 1 << 17, 0), 0)).toMatch(/moveX field 0x80/);
  });

  it('round-trips any input through its words (property)', () => {
    fc.assert(
      fc.property(
        fc.integer({ min: 0, max: 31 }),
        fc.integer({ min: 0, max: 31 }),
        fc.integer({ min: 0, max: 1023 }),
        fc.integer({ min: 0, max: 255 }).filter((v) => v !== 128), // 128: no level (centred)
        fc.integer({ min: 0, max: 65535 }),
        (down, pressed, a, b, c) => {
          const p = new PlayerInput(twinStick);
          p.buttons = packButtons(down, pressed);
          p.steps.set([a, b, c]);
          const w = new Uint32Array(4);
          twinStick.encode(p, w, 1);
          const q = twinStick.decode(w, 1);
          return q.buttons === p.buttons && q.steps.every((v, i) => v === p.steps[i]);
        },
      ),
    );
  });

  it('quantises on the device side and reads back exact, engine-independent values', () => {
    const aim = twinStick.axis.aim;
    const moveX = twinStick.axis.moveX;
    // Centred: both ends exact, clamped outside (field 127: +127 steps from the centre).
    expect(twinStick.value(moveX, twinStick.quantise(moveX, -1))).toBe(-1);
    expect(twinStick.value(moveX, twinStick.quantise(moveX, 1))).toBe(1);
    expect(twinStick.quantise(moveX, 7)).toBe(127);
    expect(twinStick.quantise(moveX, Number.NaN)).toBe(0);
    expect(Math.abs(twinStick.value(moveX, twinStick.quantise(moveX, 0.3)) - 0.3)).toBeLessThan(
      1 / 255,
    );
    // Angle: wraps, step 0 is −π, the error is at most half a step.
    expect(twinStick.quantise(aim, -Math.PI)).toBe(0);
    expect(twinStick.quantise(aim, Math.PI)).toBe(0);
    expect(twinStick.value(aim, 512)).toBe(0);
    for (const a of [-3, -1.2, 0.1, 1.5707963267948966, 3.1]) {
      const back = twinStick.value(aim, twinStick.quantise(aim, a));
      expect(Math.abs(back - a)).toBeLessThanOrEqual(Math.PI / 1024 + 1e-12);
    }
    expect(twinStick.quantise(aim, 3 * Math.PI)).toBe(twinStick.quantise(aim, Math.PI));
  });

  it('has a canonical descriptor and an id: equal schemas, equal ids; any change, another id', () => {
    const again = defineInput(twinStickDefinition());
    expect(again.id).toBe(twinStick.id);
    expect(defineInput({ buttons: ['left', 'right', 'up', 'down', 'fire'] }).id).not.toBe(
      twinStick.id,
    );
    const read = inputSchemaFromDescriptor(twinStick.descriptor);
    expect(read.id).toBe(twinStick.id);
    expect(read.words).toBe(3);
    expect(read.axes.map((a) => a.name)).toEqual(['aim', 'moveX', 'throttle']);
    expect(inputSchemaFromDescriptor(BUTTON_WORD.descriptor).id).toBe(BUTTON_WORD.id);
  });

  it('refuses bad definitions and bad descriptors with a clear message', () => {
    expect(() => defineInput({ buttons: Array.from({ length: 17 }, (_, i) => `b${i}`) })).toThrow(
      /at most 16 buttons/,
    );
    expect(() => defineInput({ buttons: ['a', 'a'] })).toThrow(/used twice/);
    expect(() => defineInput({ buttons: ['no spaces'] })).toThrow(/names must be/);
    expect(() => defineInput({ axes: { x: { min: 1, max: 1, bits: 8 } } })).toThrow(/min < max/);
    expect(() => defineInput({ axes: { x: { angle: 17 } } })).toThrow(/1 to 16/);
    const d = twinStick.descriptor;
    expect(() => inputSchemaFromDescriptor(d.subarray(0, d.length - 1))).toThrow(/descriptor/);
    expect(() => inputSchemaFromDescriptor(Uint8Array.of(9))).toThrow(/unknown descriptor version/);
    expect(() => inputSchemaFromDescriptor(Uint8Array.of(...d, 0))).toThrow(/left over/);
    fc.assert(
      fc.property(fc.uint8Array({ maxLength: 80 }), (bytes) => {
        try {
          inputSchemaFromDescriptor(bytes);
        } catch (e) {
          return e instanceof RangeError;
        }
        return true;
      }),
    );
  });
});

describe('InputSampler with axes', () => {
  it('gives each tick the last axis value set before it ends, and keeps it after', () => {
    const loop = new FixedLoop({ step: 60 });
    const sampler = new InputSampler(twinStick);
    const aim = twinStick.axis.aim;
    loop.frame(0);
    sampler.setAxis(5, aim, 1.0); // inside tick 0 (0 … 16.67 ms)
    sampler.setAxis(10, aim, 2.0); // later in tick 0: this one wins
    sampler.setAxis(20, aim, -2.0); // tick 1
    sampler.push(21, twinStick.button.fire, true);
    const ticks: PlayerInput[] = [];
    const n = loop.frame(50);
    for (let j = 0; j < n; j++) ticks.push(sampler.sample(loop, j));
    expect(n).toBe(3);
    const q = (v: number) => twinStick.value(aim, twinStick.quantise(aim, v));
    expect(ticks.map((t) => t.axis(aim))).toEqual([q(2), q(-2), q(-2)]);
    expect(ticks.map((t) => t.wasPressed(twinStick.button.fire))).toEqual([false, true, false]);
    expect(ticks.map((t) => t.isDown(twinStick.button.fire))).toEqual([false, true, true]);
    // sampleWords is the same input as words, without allocating.
    const words = new Uint32Array(twinStick.words);
    sampler.sampleWords(loop, 0, words);
    expect(twinStick.decode(words, 0).axis(aim)).toBe(q(-2));
  });

  it('places an axis change on the same tick at any display rate', () => {
    const perTick = (hz: number) => {
      const loop = new FixedLoop({ step: 60, maxStepsPerFrame: 100 });
      const s = new InputSampler(twinStick);
      const out: number[] = [];
      loop.frame(0);
      let t = 0;
      let sent = false;
      while (out.length < 30) {
        t += 1000 / hz;
        if (!sent && t >= 123.4) {
          s.setAxis(123.4, twinStick.axis.moveX, 0.5);
          sent = true;
        }
        const n = loop.frame(t);
        for (let j = 0; j < n; j++) out.push(s.sample(loop, j).steps[1]!);
      }
      return out.slice(0, 30);
    };
    const ref = perTick(60);
    expect(ref.indexOf(ref.find((v) => v !== 0)!)).toBe(7); // 123.4 ms lies in tick 7
    for (const hz of [24, 30, 75, 144, 240]) expect(perTick(hz)).toEqual(ref);
  });
});

describe('centred axes and dead zones', () => {
  const pong = defineInput({ axes: { paddle: { min: -1, max: 1, bits: 6 } } });
  const paddle = pong.axis.paddle;

  it('a two-sided axis is centred by default: never set, it reads exactly 0', () => {
    expect(pong.axes[paddle]!.kind).toBe('centred');
    expect(new PlayerInput(pong).axis(paddle)).toBe(0);
    expect(pong.neutral().axis(paddle)).toBe(0);
    expect(pong.decode(new Uint32Array(2), 0).axis(paddle)).toBe(0);
    // A value of 0 quantises to field 0 and reads back exactly 0 (the even quantisation read
    // 0.015873 at 6 bits: the bug this fixes).
    expect(pong.quantise(paddle, 0)).toBe(0);
    expect(new PlayerInput(pong).setAxis(paddle, 0).axis(paddle)).toBe(0);
    expect(new PlayerInput(pong).setAxis(paddle, -0.004).axis(paddle)).toBe(0);
  });

  it('has 2^bits − 1 levels, both ends exact, symmetric around the centre', () => {
    // 6 bits: 31 steps each side, fields 0..31 and 33..63 (two's complement), 32 unused.
    const levels = new Set<number>();
    for (let v = -1.5; v <= 1.5; v += 1 / 256) levels.add(pong.quantise(paddle, v));
    expect(levels.size).toBe(63);
    expect(levels.has(32)).toBe(false);
    expect(pong.quantise(paddle, 1)).toBe(31);
    expect(pong.quantise(paddle, -1)).toBe(33);
    expect(pong.value(paddle, 31)).toBe(1);
    expect(pong.value(paddle, 33)).toBe(-1);
    expect(pong.value(paddle, 1)).toBeCloseTo(1 / 31, 15);
    expect(pong.value(paddle, 63)).toBeCloseTo(-1 / 31, 15);
    for (const v of [0.1, 0.5, 0.77]) {
      expect(pong.value(paddle, pong.quantise(paddle, -v))).toBeCloseTo(
        -pong.value(paddle, pong.quantise(paddle, v)),
        14,
      );
    }
    // A range not around 0 is centred on its middle: 5…9 rests at 7.
    const dial = defineInput({ axes: { d: { min: 5, max: 9, bits: 4, centred: true } } });
    expect(new PlayerInput(dial).axis(0)).toBe(7);
    expect(dial.value(0, dial.quantise(0, 9))).toBe(9);
    expect(dial.value(0, dial.quantise(0, 5))).toBe(5);
  });

  it('refuses the one field that is no level, in encode, writeAxis and problem', () => {
    const p = new PlayerInput(pong);
    p.steps[0] = 32;
    expect(() => {
      pong.encode(p, new Uint32Array(2), 0);
    }).toThrow(/axis paddle step 32 out of range/);
    expect(() => {
      pong.writeAxis(new Uint32Array(2), 0, paddle, 32);
    }).toThrow(/cannot set axis 0 to step 32/);
    expect(pong.problem(Uint32Array.of(0, 32), 0)).toMatch(/paddle field 0x20 is no level/);
    expect(pong.problem(Uint32Array.of(0, 33), 0)).toBeUndefined();
  });

  it('a one-sided axis keeps the even quantisation: step 0 is min, its rest', () => {
    const t = defineInput({ axes: { throttle: { min: 0, max: 1, bits: 4 } } });
    expect(t.axes[0]!.kind).toBe('linear');
    expect(new PlayerInput(t).axis(0)).toBe(0);
    expect(t.value(0, 15)).toBe(1);
  });

  it('a dead zone quantises small values to rest and stretches the rest of the travel', () => {
    const s = defineInput({ axes: { x: { min: -1, max: 1, bits: 8, deadZone: 0.25 } } });
    const read = (v: number) => s.value(0, s.quantise(0, v));
    for (const v of [0.08, -0.08, 0.25, -0.25]) expect(read(v)).toBe(0);
    expect(read(1)).toBe(1);
    expect(read(-1)).toBe(-1);
    // 0.625 is halfway from the dead zone's edge to full: 0.5 × 127 steps = 63.5, rounded away
    // from the centre on both sides.
    expect(s.quantise(0, 0.625)).toBe(64);
    expect(read(0.625)).toBe(64 / 127);
    expect(read(-0.625)).toBe(-64 / 127);
    // On a linear axis the zone is measured from min.
    const trigger = defineInput({ axes: { t: { min: 0, max: 1, bits: 8, deadZone: 0.1 } } });
    expect(trigger.quantise(0, 0.05)).toBe(0);
    expect(trigger.quantise(0, 0.55)).toBe(Math.round(0.5 * 255));
    // Not part of the encoding: same descriptor, same id as without a dead zone.
    expect(s.id).toBe(defineInput({ axes: { x: { min: -1, max: 1, bits: 8 } } }).id);
  });

  it('refuses a dead zone outside [0, 1) and a 1-bit centred axis, naming the value', () => {
    for (const dz of [-0.1, 1, 1.5, Number.NaN]) {
      expect(() =>
        defineInput({ axes: { x: { min: -1, max: 1, bits: 8, deadZone: dz } } }),
      ).toThrow(
        new RangeError(
          `defineInput: axis x: deadZone must be a number in [0, 1), got ${String(dz)}`,
        ),
      );
    }
    expect(() => defineInput({ axes: { x: { min: -1, max: 1, bits: 1, centred: true } } })).toThrow(
      /centred axis needs 2 bits or more, got 1/,
    );
    // A 1-bit two-sided axis stays linear by default (it has no centre to give).
    expect(defineInput({ axes: { x: { min: -1, max: 1, bits: 1 } } }).axes[0]!.kind).toBe('linear');
  });

  it('records centred and linear in the descriptor: each reads back as it was defined', () => {
    const both = defineInput({
      axes: {
        stick: { min: -1, max: 1, bits: 6 },
        old: { min: -1, max: 1, bits: 6, centred: false },
      },
    });
    expect(both.axes.map((a) => a.kind)).toEqual(['centred', 'linear']);
    const read = inputSchemaFromDescriptor(both.descriptor);
    expect(read.id).toBe(both.id);
    expect(read.axes.map((a) => a.kind)).toEqual(['centred', 'linear']);
    const idle = read.decode(new Uint32Array(2), 0) as PlayerInput;
    expect([idle.axis(0), idle.axis(1)]).toEqual([0, -1]);
    // The kind byte: 2 centred, 0 linear.
    expect(both.descriptor[both.descriptor.indexOf(5) + 6]).toBe(2);
  });

  it('an even-quantised axis has the descriptor and id it had before centred axes', () => {
    // Written by the library before centred axes (commit 1a043ba) for { min: -1, max: 1, bits: 6 }.
    const before = defineInput({ axes: { moveX: { min: -1, max: 1, bits: 6, centred: false } } });
    expect(Buffer.from(before.descriptor).toString('hex')).toBe(
      '010001056d6f7665580006000000000000f0bf000000000000f03f',
    );
    expect(before.id).toBe('fbc8d6b2bf12b527');
    expect(before.value(0, before.quantise(0, 0))).toBe(0.015873015873015817);
    expect(new PlayerInput(before).axis(0)).toBe(-1);
  });
});
