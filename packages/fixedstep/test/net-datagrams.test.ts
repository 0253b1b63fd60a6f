/**
 * The relay protocol over a datagram transport (WebRTC's unreliable channel; here the simulated
 * lossy link): new ticks go in paced groups, a changed input at once and again with the next tick,
 * each message repeats a bounded window of unacknowledged ticks, and a frame's messages travel as
 * one datagram. Every input still arrives: the room plays exactly what each player issued.
 */
import { describe, expect, it } from 'vitest';
import {
  BUTTON_WORD,
  CONFIRMED_DATAGRAM_EVERY,
  INPUT_DATAGRAM_EVERY,
  EventScheduler,
  REDUNDANT_TICKS,
  RELAY_PROTOCOL,
  Random,
  Relay,
  RollbackSession,
  SimulatedLink,
  decodeMessage,
  fnv1a64,
  gameCatalog,
  type Transport,
} from 'fixedstep';
import { Toy } from './toy-game.js';

const catalog = gameCatalog([
  {
    id: 'toy',
    version: 1,
    tickRate: 60,
    minPlayers: 2,
    maxPlayers: 2,
    input: BUTTON_WORD,
    options: (players, seed) => Uint8Array.of(players, seed & 0xff),
  },
]);

/** What one side put on the wire: datagrams, their bytes, and each input message's ticks. */
interface Wire {
  datagrams: number;
  bytes: number;
  /** Per input message: its first tick and how many ticks it carries. */
  inputRuns: [tick: number, ticks: number][];
  /** Per confirmed message: its first tick and how many ticks it carries. */
  confirmedRuns: [tick: number, ticks: number][];
}

/** `t`, recording every frame sent through it. */
function recorded(t: Transport, wire: Wire): Transport {
  return {
    send(bytes) {
      wire.datagrams++;
      wire.bytes += bytes.length;
      for (const part of RELAY_PROTOCOL.split(bytes)) {
        const m = decodeMessage(part);
        if (m.type === 'input') wire.inputRuns.push([m.tick, m.inputs.length / m.words]);
        if (m.type === 'confirmed') {
          wire.confirmedRuns.push([m.tick, m.inputs.length / (m.players * m.words)]);
        }
      }
      t.send(bytes);
    },
    onMessage: (h) => {
      t.onMessage(h);
    },
    onClose: (h) => {
      t.onClose(h);
    },
    close: (reason) => {
      t.close(reason);
    },
    get isOpen() {
      return t.isOpen;
    },
    get reliable() {
      return t.reliable;
    },
  };
}

const emptyWire = (): Wire => ({ datagrams: 0, bytes: 0, inputRuns: [], confirmedRuns: [] });

/**
 * Two rollback players over 100 ± 30 ms, 5 % loss each way, 60 Hz, `ticks` ticks. Player p's input
 * changes every `changeEvery` ticks (Infinity: held all match).
 */
function play(ticks: number, changeEvery: number) {
  const scheduler = new EventScheduler();
  const rng = new Random(3);
  // A generous deadline: an input the relay fills in would not be "arrived"; here every one must.
  const relay = new Relay({
    clock: scheduler.clock,
    catalog,
    randomU32: () => rng.nextU32(),
    deadlineMs: 400,
  });
  scheduler.every(1000 / 120, () => {
    relay.update();
  });
  const input = (tick: number, slot: number) =>
    Number.isFinite(changeEvery) ? (Math.floor(tick / changeEvery) + slot) & 3 : 1 + slot;
  const up = [emptyWire(), emptyWire()];
  const down = [emptyWire(), emptyWire()];
  const sessions: RollbackSession[] = [];
  for (let p = 0; p < 2; p++) {
    const link = new SimulatedLink({
      scheduler,
      seed: 10 + p,
      latencyMs: 100,
      jitterMs: 30,
      loss: 0.05,
    });
    relay.accept(recorded(link.b, down[p]!));
    let slot = -1;
    const s = new RollbackSession({
      transport: recorded(link.a, up[p]!),
      clock: scheduler.clock,
      room: 'r',
      game: 'toy',
      gameVersion: 1,
      players: 2,
      seed: 5,
      stopAt: ticks,
      createSimulation: (w) => {
        slot = w.slot;
        return new Toy(w.config[0]!, w.config[1]!);
      },
      localInput: (tick) => input(tick, slot),
    });
    sessions.push(s);
    scheduler.every(1000 / 60, () => {
      if (s.phase !== 'closed') s.frame();
    });
  }
  const finished = scheduler.runUntilDone(() => sessions.every((s) => s.isFinished), 120_000);
  const truth = new Toy(2, 5);
  for (let t = 0; t < ticks; t++) truth.step([input(t, 0), input(t, 1)]);
  return { finished, relay, sessions, up, down, truth: fnv1a64(truth.save()) };
}

/** How many messages carried each tick (ticks 0 … ticks − 1). */
function copies(runs: readonly [number, number][], ticks: number): number[] {
  const n = new Array<number>(ticks).fill(0);
  for (const [from, count] of runs) for (let t = from; t < from + count && t < ticks; t++) n[t]!++;
  return n;
}

describe('the relay protocol over datagrams (100 ± 30 ms, 5 % loss)', () => {
  const ticks = 1800;
  // Two players who hold one input all match, and two whose inputs change every 6 ticks (a bot).
  const held = play(ticks, Infinity);
  const busy = play(ticks, 6);

  it('every input arrives exactly once: the room plays what each player issued, on every machine', () => {
    for (const run of [held, busy]) {
      expect(run.finished).toBe(true);
      // No input was filled in for a missing one, and none that a player issued was replaced.
      expect(run.relay.stats.filledInputs).toBe(0);
      for (const s of run.sessions) {
        expect(s.stats.replacedInputs).toBe(0);
        expect(s.hashAt(ticks)).toBe(run.truth);
        expect(s.desyncs).toEqual([]);
      }
    }
  });

  it('each message repeats a bounded window: every tick in a few datagrams, none in more than the window allows', () => {
    for (const run of [held, busy]) {
      for (const wire of run.up) {
        const n = copies(wire.inputRuns, ticks);
        // Every tick went at least twice (a lost datagram is covered by the next) …
        expect(Math.min(...n)).toBeGreaterThanOrEqual(2);
        // … in messages of the new ticks and at most REDUNDANT_TICKS sent before; a longer one
        // only when the relay's ack stopped moving for 250 ms (a rewind to it), rarely.
        const long = wire.inputRuns.filter(([, n]) => n > REDUNDANT_TICKS + INPUT_DATAGRAM_EVERY);
        expect(long.length / wire.inputRuns.length).toBeLessThan(0.01);
        // About REDUNDANT_TICKS / INPUT_DATAGRAM_EVERY + 1 copies of each tick; protocol 5 sent
        // every unacknowledged tick every tick: ~13 copies at this round trip.
        const mean = n.reduce((a, b) => a + b, 0) / ticks;
        expect(mean).toBeGreaterThan(REDUNDANT_TICKS / INPUT_DATAGRAM_EVERY);
        expect(mean).toBeLessThan(REDUNDANT_TICKS / INPUT_DATAGRAM_EVERY + 1.5);
      }
      for (const wire of run.down) {
        for (const [, count] of wire.confirmedRuns) {
          expect(count).toBeLessThanOrEqual(REDUNDANT_TICKS + 2 * CONFIRMED_DATAGRAM_EVERY);
        }
      }
    }
  });

  it('datagrams and bytes per tick fall: a group per datagram, a changed input at once', () => {
    // Protocol 5 sent a datagram every tick each way, plus clock probes and hash reports alone: on
    // these seeds 1.10 datagrams and 23.7 bytes a tick up, 0.76 and 23.6 down, whatever the inputs.
    for (const run of [held, busy]) {
      for (const wire of run.up) {
        // One datagram per group of ticks; probes and hash reports ride in it.
        const perTick = wire.datagrams / ticks;
        expect(perTick).toBeGreaterThanOrEqual(1 / INPUT_DATAGRAM_EVERY);
        expect(perTick).toBeLessThan(1 / INPUT_DATAGRAM_EVERY + 0.1);
        expect(wire.bytes / ticks).toBeLessThan(23.7 / 1.6);
      }
    }
    for (const wire of held.down) {
      // Unchanged ticks a group a datagram, and the answers to 4 clock probes a second.
      const perTick = wire.datagrams / ticks;
      expect(perTick).toBeGreaterThanOrEqual(1 / CONFIRMED_DATAGRAM_EVERY);
      expect(perTick).toBeLessThan(1 / CONFIRMED_DATAGRAM_EVERY + 4 / 60 + 0.02);
      expect(wire.bytes / ticks).toBeLessThan(23.6 / 2);
    }
    for (const wire of busy.down) {
      // A change every 6 ticks: it, its repeat and at most one group between, of 6 ticks.
      expect(wire.datagrams / ticks).toBeLessThan(3 / 6 + 4 / 60);
      expect(wire.bytes / ticks).toBeLessThan(23.6 / 1.6);
    }
  });
});
