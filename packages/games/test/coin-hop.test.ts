/**
 * Coin hop (the guide's ray-cast and sensor snippet as a scene), played headless: the ground
 * check's answer tick by tick, the ticks the coins are collected, a crate that stops a player who
 * does not jump, a snapshot round trip in mid-air and a golden hash.
 */
import { describe, expect, it } from 'vitest';
import { CoinHop, COIN_HOP_JUMP, coinHopBot } from '@fixedstep/games';

interface Played {
  scene: CoinHop;
  /** Per tick (index 0 = after tick 1): the ground check after the step. */
  grounded: boolean[];
  /** The tick each coin was collected (0: never). */
  coinAt: number[];
  /** The ticks a jump was asked for while on the ground. */
  jumps: number[];
}

function play(ticks: number, input: (scene: CoinHop) => number): Played {
  const scene = new CoinHop();
  const grounded: boolean[] = [];
  const coinAt = [0, 0];
  const jumps: number[] = [];
  for (let t = 1; t <= ticks; t++) {
    const i = input(scene);
    if (i !== 0 && scene.onGround) jumps.push(t);
    scene.step([i]);
    grounded.push(scene.onGround);
    for (let k = 0; k < 2; k++) if (coinAt[k] === 0 && scene.collected(k)) coinAt[k] = t;
  }
  return { scene, grounded, coinAt, jumps };
}

/** The ticks (1-based) on which `grounded` changes, as [tick, now]. */
function changes(grounded: readonly boolean[]): [number, boolean][] {
  const out: [number, boolean][] = [];
  grounded.forEach((g, i) => {
    if (i === 0 || g !== grounded[i - 1]) out.push([i + 1, g]);
  });
  return out;
}

describe('CoinHop', () => {
  it('the ground check is true while standing and running, false from the jump to the landing', () => {
    const { grounded, jumps } = play(240, coinHopBot);
    expect(new CoinHop().onGround).toBe(true); // standing at tick 0
    expect(jumps).toEqual([95]); // the bot's forward ray saw the crate; one jump
    expect(changes(grounded)).toEqual([
      [1, true],
      [95, false],
      [180, true],
    ]);
  });

  it('collects the path coin at tick 38 and the coin above the crate at tick 114, mid-jump', () => {
    const { scene, coinAt } = play(240, coinHopBot);
    expect(coinAt).toEqual([38, 114]);
    expect(scene.score).toBe(2);
    expect(scene.world.x[scene.player]).toBeCloseTo(15.6815, 4);
    expect(scene.world.y[scene.player]).toBeCloseTo(0.495, 4);
  });

  it('without a jump the crate stops the player at its left face and the high coin stays', () => {
    const { scene, coinAt, grounded } = play(240, () => 0);
    expect(coinAt).toEqual([38, 0]);
    expect(grounded.every((g) => g)).toBe(true);
    // Crate's left face 7.5 m, player half width 0.3 m, resting overlap 5 mm (linear slop).
    expect(scene.world.x[scene.player]).toBeCloseTo(7.205, 6);
  });

  it('a jump asked for in the air does nothing', () => {
    const { jumps, coinAt } = play(240, (s) => (s.tick >= 95 && s.tick < 150 ? COIN_HOP_JUMP : 0));
    expect(jumps).toEqual([96]);
    expect(coinAt[0]).toBe(38);
  });

  it('snapshot round trip in mid-air: equal hashes every tick for 120 ticks', () => {
    const a = play(100, coinHopBot).scene;
    expect(a.onGround).toBe(false);
    const b = new CoinHop();
    b.load(a.save());
    expect(b.onGround).toBe(false);
    for (let t = 0; t < 120; t++) {
      a.step([coinHopBot(a)]);
      b.step([coinHopBot(b)]);
      expect(b.hash()).toBe(a.hash());
    }
    expect(b.score).toBe(2);
  });

  it('golden hash after 240 ticks of the bot', () => {
    const h = play(240, coinHopBot).scene.hash().toString(16).padStart(16, '0');
    if (h !== '86d47a03c17b77b8') console.log(`coin hop golden hash is now ${h}`);
    expect(h).toBe('86d47a03c17b77b8');
  });
});
