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
    expect(twinStick.problem(Uint32Array.of(0, 1 << 17, 1 << 15), 0)).toBeUndefined();
  });

  it('round-trips any input through its words (property)', () => {
    fc.assert(
      fc.property(
        fc.integer({ min: 0, max: 31 }),
        fc.integer({ min: 0, max: 31 }),
        fc.integer({ min: 0, max: 1023 }),
        fc.integer({ min: 0, max: 255 }),
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
    // Linear: both ends exact, clamped outside.
    expect(twinStick.value(moveX, twinStick.quantise(moveX, -1))).toBe(-1);
    expect(twinStick.value(moveX, twinStick.quantise(moveX, 1))).toBe(1);
    expect(twinStick.quantise(moveX, 7)).toBe(255);
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
