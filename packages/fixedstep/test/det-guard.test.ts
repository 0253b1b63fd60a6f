import { describe, expect, it } from 'vitest';
import {
  ByteReader,
  ByteWriter,
  DeterminismError,
  FORBIDDEN_FUNCTIONS,
  Random,
  dsin,
  fnv1a64,
  guardSimulation,
  guardStep,
  isGuardActive,
  withDeterminismGuard,
  type Simulation,
} from 'fixedstep';

// The functions the guard patches, looked up by name (they are compared, never called here).
const patched: [object, string][] = [
  [Math, 'random'],
  [Math, 'sin'],
  [Math, 'pow'],
  [Date, 'now'],
  [performance, 'now'],
  [crypto, 'getRandomValues'],
];
const originals = patched.map(([owner, key]) => Reflect.get(owner, key) as unknown);

function expectRestored(): void {
  expect(isGuardActive()).toBe(false);
  patched.forEach(([owner, key], i) => {
    expect(Reflect.get(owner, key), `${key} restored`).toBe(originals[i]);
  });
  expect(Object.hasOwn(performance, 'now')).toBe(false);
  expect(typeof Math.random()).toBe('number');
  expect(Date.now()).toBeGreaterThan(0);
}

/** Runs `fn` guarded and returns what it threw. */
function thrownBy(fn: () => unknown, tick?: number): unknown {
  try {
    withDeterminismGuard(fn, tick);
  } catch (error) {
    return error;
  }
  return undefined;
}

describe('withDeterminismGuard', () => {
  it('traps Math.random with a clear error, and Math.random works again after', () => {
    const error = thrownBy(() => Math.random());
    expect(error).toBeInstanceOf(DeterminismError);
    expect((error as Error).message).toBe(
      'Math.random called during a simulation step: use a seeded Random kept in the simulation state',
    );
    expect(error).toMatchObject({ call: 'Math.random', tick: undefined });
    expectRestored();
  });

  it('traps every function on the one forbidden list (the list the lint rule reads), and restores each', () => {
    const owners: Record<string, object> = { Math, Date, performance, crypto };
    expect(FORBIDDEN_FUNCTIONS.length).toBeGreaterThanOrEqual(27);
    for (const f of FORBIDDEN_FUNCTIONS) {
      const owner = owners[f.object]!;
      const original: unknown = Reflect.get(owner, f.property);
      expect(typeof original, `${f.object}.${f.property} exists here`).toBe('function');
      const error = thrownBy(
        () => (Reflect.get(owner, f.property) as (x: number) => unknown)(0.5),
        7,
      );
      expect(error, `${f.object}.${f.property}`).toBeInstanceOf(DeterminismError);
      expect((error as DeterminismError).call).toBe(`${f.object}.${f.property}`);
      expect((error as DeterminismError).message).toContain(f.advice);
      expect(Reflect.get(owner, f.property), `${f.property} restored`).toBe(original);
    }
    expect(FORBIDDEN_FUNCTIONS.map((f) => f.property)).toEqual(
      expect.arrayContaining(['asinh', 'acosh', 'atanh', 'random', 'now', 'getRandomValues']),
    );
  });

  it('names the tick when it is known', () => {
    expect(() => withDeterminismGuard(() => Math.random(), 42)).toThrow(
      /^Math\.random called during a simulation step \(tick 42\): /,
    );
  });

  it.each([
    ['Date.now', () => Date.now(), /clock/],
    ['performance.now', () => performance.now(), /tick × step/],
    ['Math.sin', () => Math.sin(1), /use dsin/],
    ['Math.cos', () => Math.cos(1), /use dcos/],
    ['Math.tan', () => Math.tan(1), /use dtan/],
    ['Math.atan2', () => Math.atan2(1, 2), /use datan2/],
    ['Math.exp', () => Math.exp(1), /use dexp/],
    ['Math.log', () => Math.log(2), /use dlog/],
    ['Math.pow', () => Math.pow(2, 0.5), /last bit of Math\.pow/],
    ['Math.hypot', () => Math.hypot(3, 4), /use dhypot/],
    ['Math.cbrt', () => Math.cbrt(8), /Math\.cbrt/],
    ['crypto.getRandomValues', () => crypto.getRandomValues(new Uint8Array(4)), /Random/],
    ['crypto.randomUUID', () => crypto.randomUUID(), /Random/],
  ])('traps %s', (call, fn, advice) => {
    const error = thrownBy(fn, 7);
    expect(error).toBeInstanceOf(DeterminismError);
    expect((error as DeterminismError).call).toBe(call);
    expect((error as Error).message).toMatch(advice);
    expect((error as Error).message).toContain(`${call} called during a simulation step (tick 7)`);
    expectRestored();
  });

  it('leaves deterministic arithmetic alone and returns the result of fn', () => {
    const result = withDeterminismGuard(() => [
      Math.sqrt(2),
      Math.floor(2.5),
      Math.round(2.5),
      Math.abs(-1),
      Math.min(1, 2),
      dsin(1),
      new Random(1).next(),
      2 ** 10,
    ]);
    expect(result).toEqual([Math.SQRT2, 2, 3, 1, 1, dsin(1), new Random(1).next(), 1024]);
  });

  it('restores everything when fn throws something else', () => {
    expect(() =>
      withDeterminismGuard(() => {
        throw new TypeError('boom');
      }),
    ).toThrow(TypeError);
    expectRestored();
  });

  it('rethrows a violation that fn swallowed', () => {
    let swallowed = false;
    const error = thrownBy(() => {
      try {
        Date.now();
      } catch {
        swallowed = true;
      }
      return 1;
    }, 3);
    expect(swallowed).toBe(true);
    expect(error).toBeInstanceOf(DeterminismError);
    expect((error as Error).message).toMatch(
      /^Date\.now called during a simulation step \(tick 3\)/,
    );
    expectRestored();
  });

  it('nests: inner guards name their tick, the traps stay until the outermost exits', () => {
    const seen: string[] = [];
    const record = (fn: () => unknown) => {
      try {
        fn();
      } catch (error) {
        seen.push((error as Error).message.split(':')[0]!);
      }
    };
    const outer = thrownBy(() => {
      record(() => withDeterminismGuard(() => Math.random(), 2));
      record(() => withDeterminismGuard(() => Math.random())); // no tick: the enclosing one is named
      seen.push(`active after the inner guards: ${isGuardActive()}`);
      record(() => Math.random());
    }, 1);
    expect(seen).toEqual([
      'Math.random called during a simulation step (tick 2)',
      'Math.random called during a simulation step (tick 1)',
      'active after the inner guards: true',
      'Math.random called during a simulation step (tick 1)',
    ]);
    // the outer function swallowed them all, so the outer guard rethrows the first
    expect((outer as Error).message).toMatch(/\(tick 2\)/);
    expectRestored();
  });

  it('a nested guard that throws still leaves the outer traps in place, then restores', () => {
    let trappedAfterInnerThrow = false;
    expect(() => {
      withDeterminismGuard(() => {
        try {
          withDeterminismGuard(() => {
            throw new Error('inner');
          });
        } catch {
          trappedAfterInnerThrow = thrownBy(() => Math.random()) instanceof DeterminismError;
        }
      });
    }).toThrow(DeterminismError);
    expect(trappedAfterInnerThrow).toBe(true);
    expectRestored();
  });
});

/** A toy simulation: a counter and a random walk, with a private field and an extra method. */
class Walk implements Simulation {
  #tick = 0;
  position = 0;
  readonly rng = new Random(9);
  cheat = false;

  get tick(): number {
    return this.#tick;
  }

  step(inputs: readonly number[]): void {
    this.position += (inputs[0] ?? 0) + this.rng.next() - (this.cheat ? Math.random() : 0.5);
    this.#tick++;
  }

  save(): Uint8Array {
    return new ByteWriter().u32(this.#tick).f64(this.position).ints(this.rng.getState()).finish();
  }

  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    this.#tick = r.u32();
    this.position = r.f64();
    const state = new Uint32Array(4);
    r.ints(state);
    this.rng.setState(state);
    r.end();
  }

  hash(): bigint {
    return fnv1a64(this.save());
  }

  describe(): string {
    return `walk at ${this.position.toFixed(3)} after ${this.#tick} ticks`;
  }
}

describe('guardStep and guardSimulation', () => {
  it('a step that calls Math.random throws naming the tick; the simulation can go on after', () => {
    const sim = new Walk();
    guardStep(sim, [1]);
    guardStep(sim, [1]);
    sim.cheat = true;
    expect(() => {
      guardStep(sim, [1]);
    }).toThrow(/^Math\.random called during a simulation step \(tick 2\)/);
    expectRestored();
    sim.cheat = false;
    guardStep(sim, [0]);
  });

  it('a guarded simulation behaves exactly as the bare one, keeps its own members, and traps', () => {
    const bare = new Walk();
    const guarded = guardSimulation(new Walk());
    for (let t = 0; t < 100; t++) {
      bare.step([t % 3]);
      guarded.step([t % 3]);
      expect(guarded.hash()).toBe(bare.hash());
    }
    expect(guarded.tick).toBe(100);
    expect(guarded.describe()).toBe(bare.describe());
    expect(guarded.position).toBe(bare.position);
    const copy = new Walk();
    copy.load(guarded.save());
    expect(copy.hash()).toBe(bare.hash());
    guarded.load(bare.save());
    expect(guarded.hash()).toBe(bare.hash());

    guarded.cheat = true;
    expect(() => {
      guarded.step([0]);
    }).toThrow(DeterminismError);
    expect(() => {
      guarded.step([0]);
    }).toThrow(/\(tick 100\)/);
    expectRestored();
    expect(() => {
      bare.cheat = true;
      bare.step([0]);
    }).not.toThrow();
  });

  it('guards skip() where the simulation has one, and adds none where it has not', () => {
    expect('skip' in guardSimulation(new Walk())).toBe(false);
    /** A walk that is over at once: skipping only counts ticks — unless it cheats. */
    class Finished extends Walk {
      ticks = 0;
      readonly frozen = true;
      skip(n: number): void {
        this.ticks += n + (this.cheat ? Math.random() : 0);
      }
    }
    const finished = new Finished();
    const guarded = guardSimulation(finished);
    guarded.skip(5);
    expect(finished.ticks).toBe(5);
    finished.cheat = true;
    expect(() => {
      guarded.skip(1);
    }).toThrow(DeterminismError);
    expectRestored();
  });
});
