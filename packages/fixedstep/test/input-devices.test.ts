import { describe, expect, it } from 'vitest';
import {
  FixedLoop,
  InputSampler,
  attachButtons,
  attachKeyboard,
  attachStick,
  defineInput,
  gamepadPoller,
  type PointerTarget,
} from 'fixedstep';

const schema = defineInput({
  buttons: ['left', 'right', 'up', 'down', 'jump', 'fire'],
  axes: {
    aim: { angle: 10 },
    moveX: { min: -1, max: 1, bits: 8 },
    moveY: { min: -1, max: 1, bits: 8 },
  },
});
const B = schema.button;

/** Node's EventTarget stands in for window and for elements; events carry the fields we read. */
class FakeTarget extends EventTarget {
  rect = { left: 100, top: 100, width: 100, height: 100 };
  captured: number[] = [];
  setPointerCapture(id: number): void {
    this.captured.push(id);
  }
  getBoundingClientRect() {
    return this.rect;
  }
}

function key(
  target: EventTarget,
  type: 'keydown' | 'keyup',
  code: string,
  at: number,
  repeat = false,
): boolean {
  const e = Object.assign(new Event(type, { cancelable: true }), { code, repeat });
  Object.defineProperty(e, 'timeStamp', { value: at });
  target.dispatchEvent(e);
  return e.defaultPrevented;
}

function pointer(
  target: EventTarget,
  type: string,
  id: number,
  x: number,
  y: number,
  at: number,
): void {
  const e = Object.assign(new Event(type, { cancelable: true }), {
    pointerId: id,
    clientX: x,
    clientY: y,
  });
  Object.defineProperty(e, 'timeStamp', { value: at });
  target.dispatchEvent(e);
}

/** Runs a 60 Hz loop over frames every `frameMs` until `untilMs`, returning each tick's input. */
function ticks(sampler: InputSampler<unknown>, untilMs: number, frameMs = 1000 / 60) {
  const loop = new FixedLoop({ step: 60, onWarning: null });
  const out: ReturnType<typeof schema.decode>[] = [];
  loop.frame(0);
  for (let t = frameMs; t <= untilMs + 1e-9; t += frameMs) {
    const n = loop.frame(t);
    for (let j = 0; j < n; j++)
      out.push(sampler.sample(loop, j) as ReturnType<typeof schema.decode>);
  }
  return out;
}

describe('device adapters feed one sampler', () => {
  it('keyboard: names or indices, repeats ignored, mapped keys do not scroll, blur releases', () => {
    const win = new FakeTarget();
    const s = new InputSampler(schema);
    const detach = attachKeyboard(win as never, s, {
      Space: 'jump',
      ArrowLeft: B.left,
    });
    expect(key(win, 'keydown', 'Space', 20)).toBe(true); // preventDefault: no page scroll
    expect(key(win, 'keydown', 'Space', 25, true)).toBe(true); // a repeat: no second press
    key(win, 'keyup', 'Space', 40);
    expect(key(win, 'keydown', 'KeyQ', 41)).toBe(false); // unmapped: left alone
    key(win, 'keydown', 'ArrowLeft', 60);
    win.dispatchEvent(Object.defineProperty(new Event('blur'), 'timeStamp', { value: 90 }));
    const t = ticks(s, 120);
    expect(t.filter((i) => i.wasPressed(B.jump)).length).toBe(1);
    expect(t.findIndex((i) => i.wasPressed(B.jump))).toBe(1); // 20 ms is in tick 1
    expect(t.map((i) => i.isDown(B.left))).toEqual([false, false, false, true, true, true, false]);
    detach();
    key(win, 'keydown', 'Space', 130);
    expect(s.pending).toBe(0);
    expect(() =>
      attachKeyboard(win as never, s as InputSampler<unknown>, { KeyX: 'dash' }),
    ).toThrow(/unknown button "dash"/);
  });

  it('on-screen buttons: a tap lands on one tick like a key; two fingers on one button are one press', () => {
    const jump = new FakeTarget();
    const fire = new FakeTarget();
    const s = new InputSampler(schema);
    attachButtons(s, [
      { element: jump as unknown as PointerTarget, button: 'jump' },
      { element: fire as unknown as PointerTarget, button: 'fire' },
    ]);
    pointer(jump, 'pointerdown', 1, 0, 0, 20);
    pointer(jump, 'pointerdown', 2, 0, 0, 22); // a second finger: no second press
    pointer(jump, 'pointerup', 1, 0, 0, 24);
    pointer(jump, 'pointerup', 2, 0, 0, 26); // the last finger lifts: released
    pointer(fire, 'pointerdown', 3, 0, 0, 50);
    pointer(fire, 'pointercancel', 3, 0, 0, 70); // the browser took the touch: released
    const t = ticks(s, 100);
    expect(t.map((i) => i.wasPressed(B.jump))).toEqual([false, true, false, false, false, false]);
    expect(t.map((i) => i.isDown(B.jump))).toEqual([false, true, false, false, false, false]);
    expect(t.map((i) => i.isDown(B.fire))).toEqual([false, false, false, true, true, false]);
    expect(jump.captured).toEqual([1, 2]);
  });

  it('virtual stick: deflection to quantised axes, an angle and 8-way directions; release recentres', () => {
    const stick = new FakeTarget(); // centre (150, 150), radius 50
    const s = new InputSampler(schema);
    attachStick(stick as unknown as PointerTarget, s, {
      x: 'moveX',
      y: 'moveY',
      angle: 'aim',
      left: 'left',
      right: 'right',
      up: 'up',
      down: 'down',
      active: 'fire',
    });
    pointer(stick, 'pointerdown', 7, 200, 150, 5); // full right
    pointer(stick, 'pointermove', 8, 100, 150, 6); // another finger: ignored
    pointer(stick, 'pointermove', 7, 150, 100, 20); // full up
    pointer(stick, 'pointermove', 7, 100 + 50 - 35.36, 150 + 35.36, 40); // down-left diagonal
    pointer(stick, 'pointerup', 7, 0, 0, 60);
    const t = ticks(s, 100);
    const ax = (i: (typeof t)[number]) => [i.axis(schema.axis.moveX), i.axis(schema.axis.moveY)];
    expect(ax(t[0]!)).toEqual([
      1,
      schema.value(schema.axis.moveY, schema.quantise(schema.axis.moveY, 0)),
    ]);
    expect(t[0]!.isDown(B.right) && !t[0]!.isDown(B.up)).toBe(true);
    expect(t[1]!.isDown(B.up) && t[1]!.axis(schema.axis.moveY) === -1).toBe(true);
    expect(Math.abs(t[1]!.axis(schema.axis.aim) + Math.PI / 2)).toBeLessThan(0.004);
    // "Down" means down at any moment of the tick: up is released during tick 2, held no longer after.
    expect(t[2]!.isDown(B.left) && t[2]!.isDown(B.down) && t[2]!.wasPressed(B.left)).toBe(true);
    expect(t[3]!.isDown(B.up) || t[3]!.isDown(B.right)).toBe(false);
    expect(t.map((i) => i.isDown(B.fire))).toEqual([true, true, true, true, false, false]);
    expect(t[4]!.axis(schema.axis.moveX)).toBe(0); // recentred: exactly 0 (a centred axis)
  });

  it('gamepad: polled per frame; each change is one event at the frame time; disconnect releases', () => {
    const pad: { connected: boolean; buttons: { pressed: boolean }[]; axes: number[] } = {
      connected: true,
      buttons: Array.from({ length: 16 }, () => ({ pressed: false })),
      axes: [0, 0, 0, 0],
    };
    const s = new InputSampler(schema);
    const poll = gamepadPoller({ getGamepads: () => [null, pad] }, s, {
      buttons: { 0: 'jump' },
      axes: { 0: 'moveX' },
      angle: { x: 2, y: 3, axis: 'aim' },
      stickButtons: { x: 0, y: 1, left: 'left', right: 'right' },
    });
    const loop = new FixedLoop({ step: 60, onWarning: null });
    const seen: ReturnType<typeof schema.decode>[] = [];
    const frame = (t: number, change: () => void) => {
      change();
      poll(t);
      const n = loop.frame(t);
      for (let j = 0; j < n; j++) seen.push(s.sample(loop, j));
    };
    frame(0, () => undefined);
    frame(16.7, () => {
      pad.buttons[0]!.pressed = true;
      pad.axes[0] = -0.8;
      pad.axes[3] = 1;
    });
    frame(33.4, () => undefined); // still held: no second press
    frame(50.1, () => {
      pad.connected = false;
    });
    frame(66.8, () => undefined);
    // The change polled at 16.7 ms lies just after tick 0's end (16.67 ms): tick 1 sees it. The
    // disconnect at 50.1 ms releases during tick 3 (down at some moment of it), nothing after.
    expect(seen.map((i) => i.wasPressed(B.jump))).toEqual([false, true, false, false]);
    expect(seen.map((i) => i.isDown(B.jump))).toEqual([false, true, true, true]);
    expect(seen.map((i) => i.isDown(B.left))).toEqual([false, true, true, true]);
    expect(seen[1]!.axis(schema.axis.moveX)).toBeCloseTo(-0.8, 1);
    expect(seen[1]!.axis(schema.axis.aim)).toBeCloseTo(Math.PI / 2, 2);
    frame(83.5, () => undefined);
    expect(seen[4]!.isDown(B.jump) || seen[4]!.isDown(B.left)).toBe(false);
    expect(seen[4]!.axis(schema.axis.moveX)).toBe(0);
  });
});
