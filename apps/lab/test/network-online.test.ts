import { describe, expect, it } from 'vitest';
import {
  EventScheduler,
  InputSampler,
  LockstepSession,
  Random,
  Relay,
  SimulatedLink,
  relayGameOf,
  type ButtonInput,
} from 'fixedstep';
import { CTF, CtfGame, ShooterButtons } from '@fixedstep/games';
import { gameDef, hashHex } from '../src/games-view/games.js';
import { watchEnd, type MatchEnd } from '../src/chapters/network/network-online-end.js';

const def = gameDef('ctf');
const TICKS_OF_CLOCK = CTF.timeLimit * def.info.tickRate; // 600 s at 60 Hz

describe('where an online match ends', () => {
  it('ends when the game does — at the first tick it is over — and says so once', () => {
    // Nobody presses anything; the game's own players (it fills the empty slots) play on until
    // a team reaches the capture limit or the clock runs out.
    const ends: MatchEnd[] = [];
    const game = watchEnd(def.create({ seed: 7, players: 2 }), Infinity, (e) => ends.push(e));
    const still = [0, 0];
    let firstOver = -1;
    while (firstOver < 0 && game.tick < TICKS_OF_CLOCK + 10) {
      game.step(still);
      if (game.over) firstOver = game.tick;
    }
    expect(ends).toHaveLength(1);
    const end = ends[0]!;
    expect(end.reason).toBe('game over');
    expect(end.tick).toBe(firstOver);
    const hud = game.hud();
    const byFlags = Math.max(hud.red ?? 0, hud.blue ?? 0) === CTF.captureLimit;
    expect(byFlags || (end.tick === TICKS_OF_CLOCK && hud.timeLeft === 0)).toBe(true);
    // Told once; the saved final state is the game's state there, byte for byte.
    game.step(still);
    expect(ends).toHaveLength(1);
    const final = def.create({ seed: 7, players: 2 });
    final.load(end.bytes);
    expect(final.over).toBe(true);
    expect(hashHex(final)).toBe(end.hash);
    expect(end.hash).toMatch(/^[0-9a-f]{16}$/);
  });

  it('ends at a shorter tick limit only when asked for one, with time left on the clock', () => {
    const ends: MatchEnd[] = [];
    const game = watchEnd(def.create({ seed: 7, players: 2 }), 600, (e) => ends.push(e));
    for (let i = 0; i < 600; i++) game.step([0, 0]);
    expect(ends.map((e) => [e.tick, e.reason])).toEqual([[600, 'tick limit']]);
    expect(ends[0]!.hash).toBe(hashHex(game));
    expect(game.hud().timeLeft).toBe(590);
  });

  it('wrapping a game does not change how it steps', () => {
    const plain = def.create({ seed: 3, players: 2 });
    const watched = watchEnd(def.create({ seed: 3, players: 2 }), Infinity, () => undefined);
    const random = new Random(11);
    for (let i = 0; i < 900; i++) {
      const inputs = [random.nextU32() & 0x3f, random.nextU32() & 0x3f];
      plain.step(inputs);
      watched.step(inputs);
    }
    expect(hashHex(watched)).toBe(hashHex(plain));
  });

  it('two people over the relay see the same end, the same final state, each with their own player', () => {
    // The panel's lockstep sessions on a virtual clock: each machine's InputSampler gets its
    // person's key presses at their times; 60 ± 20 ms links with 3 % loss.
    const scheduler = new EventScheduler(0);
    const clock = scheduler.clock;
    const random = new Random(5);
    const game = relayGameOf(def);
    const relay = new Relay({
      clock,
      randomU32: () => random.nextU32(),
      catalog: () => game,
    });
    scheduler.every(
      1000 / 120,
      () => {
        relay.update(clock.now());
      },
      1000 / 120,
    );
    const now = { isBeforeUpdateEnd: (t: number) => t <= clock.now() };
    const ticks = 300;
    const machines = [0, 1].map((i) => {
      const link = new SimulatedLink({
        scheduler,
        seed: 100 + i,
        latencyMs: 60,
        jitterMs: 20,
        loss: 0.03,
      });
      relay.accept(link.b);
      const sampler = new InputSampler<ButtonInput>(def.input);
      const m: { end?: MatchEnd; sampler: InputSampler; session?: LockstepSession } = {
        sampler,
      };
      m.session = new LockstepSession({
        transport: link.a,
        clock,
        room: 'people',
        game: def.info.id,
        gameVersion: def.info.version,
        input: def.input,
        players: 2,
        stopAt: ticks,
        createSimulation: (w) =>
          watchEnd(def.create(def.decodeConfig(w.config)), ticks, (e) => {
            m.end = e;
          }),
        localInput: () => sampler.sample(now, 0),
      });
      scheduler.every(
        1000 / 60,
        () => {
          m.session?.frame();
        },
        i * 7.3,
      );
      return m;
    });
    // Once both are in: the person of slot 0 (red, left base) holds right from 1.5 s to 3.5 s; the
    // person of slot 1 (blue, right base) holds left and fires from 2 s.
    const bySlot = (slot: number) => {
      const m = machines.find((x) => x.session?.welcome?.slot === slot);
      if (!m) throw new Error(`no machine has slot ${slot}`);
      return m;
    };
    scheduler.at(1500, () => {
      bySlot(0).sampler.push(clock.now(), ShooterButtons.right, true);
    });
    scheduler.at(3500, () => {
      bySlot(0).sampler.push(clock.now(), ShooterButtons.right, false);
    });
    scheduler.at(2000, () => {
      bySlot(1).sampler.push(clock.now(), ShooterButtons.left, true);
      bySlot(1).sampler.push(clock.now(), ShooterButtons.fire, true);
    });
    scheduler.runUntil(40_000);
    const [a, b] = machines as [(typeof machines)[0], (typeof machines)[0]];
    expect(new Set(machines.map((m) => m.session?.welcome?.slot))).toEqual(new Set([0, 1]));
    expect(a.end?.tick).toBe(ticks);
    expect(b.end?.tick).toBe(ticks);
    expect(a.end?.hash).toBe(b.end?.hash);
    expect(a.session?.desyncs).toEqual([]);
    // The people's keys moved their own players: red (slot 0) right, blue (slot 1) left.
    const final = new CtfGame({ seed: 0, players: 2 });
    final.load(a.end!.bytes);
    const start = new CtfGame({ seed: 0, players: 2 });
    expect(final.state.x[0]!).toBeGreaterThan(start.state.x[0]! + 50);
    expect(final.state.x[1]!).toBeLessThan(start.state.x[1]! - 50);
  });
});
