/**
 * The determinism suite's own tools, in Node: hex floats, state diffs, trace comparison, the
 * input script round trip, and a mismatch report that names the tick, engine, scene and field.
 */
import { describe, expect, it } from 'vitest';
import { ButtonSampler, FixedLoop, SimulatedDisplay, Timestep, packButtons } from 'fixedstep';
import {
  StateLayout,
  bytesToHex,
  diffStates,
  firstDifferentTick,
  hexFloat,
  hexToBytes,
  inputsToScript,
  sampledInputs,
  traceDisplay,
  traceScene,
  type TraceScene,
} from '@fixedstep/games';
import { compareEngine, compareInNode, formatMismatch } from './compare.js';
import { reportMarkdown, catalogueSummary } from './report.js';
import { runScenes } from './run.js';

describe('determinism tools', () => {
  it('hexFloat prints every double exactly, C99 %a style', () => {
    expect(hexFloat(Math.PI)).toBe('0x1.921fb54442d18p+1');
    expect(hexFloat(1)).toBe('0x1p+0');
    expect(hexFloat(-0.5)).toBe('-0x1p-1');
    expect(hexFloat(0)).toBe('0x0p+0');
    expect(hexFloat(-0)).toBe('-0x0p+0');
    expect(hexFloat(Number.MIN_VALUE)).toBe('0x0.0000000000001p-1022');
    expect(hexFloat(Infinity)).toBe('Infinity');
    expect(hexFloat(NaN)).toBe('NaN(0x7ff8000000000000)');
    expect(hexFloat(0.1 + 0.2)).not.toBe(hexFloat(0.3));
  });

  it('diffStates names the first differing field and both values', () => {
    const layout = new StateLayout()
      .add('u32', 'tick')
      .array('f64', 3, (i) => `body[${String(i)}].x`);
    const a = new DataView(new ArrayBuffer(layout.length));
    a.setUint32(0, 7, true);
    for (let i = 0; i < 3; i++) a.setFloat64(4 + 8 * i, i + 0.1, true);
    const b = new DataView(a.buffer.slice(0));
    b.setFloat64(12, 1.1000000000000003, true); // body[1].x, 1 ulp off
    const d = diffStates(new Uint8Array(a.buffer), new Uint8Array(b.buffer), layout.fields);
    expect(d.equal).toBe(false);
    expect(d.field?.name).toBe('body[1].x');
    expect(d.a).toContain('0x1.199999999999ap+0');
    expect(d.b).toContain('0x1.199999999999bp+0');
    expect(d.summary).toMatch(/^first difference at byte 12: body\[1\]\.x/);
    const raw = diffStates(new Uint8Array(a.buffer), new Uint8Array(b.buffer));
    expect(raw.summary).toContain('no field map');
    expect(diffStates(new Uint8Array(4), new Uint8Array(4)).equal).toBe(true);
    expect(hexToBytes(bytesToHex(Uint8Array.of(0, 15, 255)))).toEqual(Uint8Array.of(0, 15, 255));
  });

  it('firstDifferentTick finds the first differing hash, or the end of a shorter trace', () => {
    const t = (...hs: number[]) => hs.map((h) => h.toString(16).padStart(16, '0')).join('');
    expect(firstDifferentTick(t(1, 2, 3), t(1, 2, 3))).toBe(0);
    expect(firstDifferentTick(t(1, 2, 3), t(9, 2, 3))).toBe(1);
    expect(firstDifferentTick(t(1, 2, 3, 4, 5), t(1, 2, 3, 4, 6))).toBe(5);
    expect(firstDifferentTick(t(1, 2, 3), t(1, 2))).toBe(3);
  });

  it('inputsToScript: a sampler gives back every input a key can produce, at any display', () => {
    const A = 1;
    const B = 2;
    // press A; hold A; release; press A and B the same tick; re-press A while held; idle
    const inputs = Uint32Array.of(
      packButtons(A, A),
      packButtons(A, 0),
      0,
      packButtons(A | B, A | B),
      packButtons(A | B, A),
      packButtons(B, 0),
      0,
      packButtons(A, A),
    );
    const step = Timestep.fromHz(60);
    const script = inputsToScript(inputs, step.ms);
    expect(sampledInputs(script, inputs.length, step.ms)).toEqual(inputs);
    for (const hz of [30, 59.94, 144]) {
      const loop = new FixedLoop({ step, maxAccumulatorMs: 1000 });
      const display = new SimulatedDisplay(traceDisplay(hz));
      const sampler = new ButtonSampler();
      const got: number[] = [];
      let i = 0;
      while (got.length < inputs.length) {
        const now = display.next().time;
        while (i < script.length && script[i]!.timeMs <= now) {
          const e = script[i++]!;
          sampler.push(e.timeMs, e.button, e.down);
        }
        const n = loop.frame(now);
        for (let j = 0; j < n; j++) got.push(sampler.sample(loop, j));
      }
      expect(got.slice(0, inputs.length), `${String(hz)} Hz`).toEqual([...inputs]);
    }
    // A bot that says "held" without a press comes out as a press, like a real key.
    const held = Uint32Array.of(packButtons(A, 0), packButtons(A, 0));
    expect([...sampledInputs(inputsToScript(held, step.ms), 2, step.ms)]).toEqual([
      packButtons(A, A),
      packButtons(A, 0),
    ]);
  });

  it('a perturbed engine is reported with its first tick, the scene and the differing field', async () => {
    const layout = new StateLayout().add('f64', 'x').add('f64', 'v');
    const counter = (bug: boolean): TraceScene => ({
      id: 'test/counter',
      title: 'x += v; a bug adds 2^-52 to v from tick 5',
      ticks: 10,
      start() {
        const s = new Float64Array(2);
        s[1] = 1;
        let tick = 0;
        return {
          next() {
            tick++;
            if (bug && tick === 5) s[1] = s[1]! + 2 ** -52;
            s[0] = s[0]! + s[1]!;
            return new Uint8Array(s.buffer);
          },
        };
      },
      fields: (state) => layout.covering(state.length),
    });
    const good = [counter(false)];
    const bad = [counter(true)];
    const c = await compareInNode('firefox', good, bad);
    expect(c.mismatches).toHaveLength(1);
    const line = formatMismatch(c.mismatches[0]!);
    expect(line).toMatch(/^firefox · test\/counter: differs from Node first at tick 5 /);
    expect(line).toContain('v (f64 at offset 8) 0x1p+0 (1) vs 0x1.0000000000001p+0');
    const md = reportMarkdown({
      generatedAt: 'now',
      totalMs: 0,
      host: 'test',
      catalogue: catalogueSummary(good),
      engines: [
        {
          id: 'firefox',
          name: 'Firefox',
          status: 'failed',
          mismatches: c.mismatches,
          informational: [],
        },
        {
          id: 'webkit',
          name: 'WebKit',
          status: 'skipped',
          reason: 'not installed',
          mismatches: [],
          informational: [],
        },
      ],
      notes: [],
    });
    expect(md).toContain('- **WebKit**: not installed');
    expect(md).toContain('differs from Node first at tick 5');
  });

  it('a scene that throws is a mismatch, not a crash', async () => {
    const broken: TraceScene = {
      id: 'test/broken',
      title: 'throws at tick 3',
      ticks: 5,
      start() {
        let t = 0;
        return {
          next() {
            if (++t === 3) throw new RangeError('boom');
            return new Uint8Array(1);
          },
        };
      },
    };
    const run = runScenes([broken]);
    expect(run.scenes[0]!.error).toBe('RangeError: boom');
    expect(() => traceScene(broken)).toThrow('boom');
    const c = await compareEngine({
      engine: 'node',
      scenes: [broken],
      run,
      reference: run,
      state: () => Promise.resolve(''),
      referenceState: () => Promise.resolve(''),
    });
    expect(c.mismatches.map(formatMismatch)).toEqual([
      'node · test/broken: threw: RangeError: boom',
    ]);
  });
});
