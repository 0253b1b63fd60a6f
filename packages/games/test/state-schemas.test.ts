/**
 * The games' state schemas (state sync's schema codec): each describes its game's `save()` bytes
 * exactly, a snapped state loads and quantises to the same words, and a room with the schema codec
 * keeps every client on the server's words through a lossy link — for fewer bytes than byte deltas.
 */
import { describe, expect, it } from 'vitest';
import {
  EventScheduler,
  Random,
  SimulatedLink,
  StateSyncRoom,
  StateSyncSession,
  decodeStateSyncMessage,
  peekStateSyncType,
  type AnyGameDefinition,
  type ButtonInput,
  type Simulation,
  type StateSnapshotMessage,
  type Transport,
} from 'fixedstep';
import { ctfGame, jostleGame, stirredPileGame, survivalGame, type Game } from '@fixedstep/games';

interface Case {
  game: AnyGameDefinition;
  players: number;
  ticks: number;
  bot?: (sim: Simulation, slot: number) => ButtonInput;
}

const CASES: Case[] = [
  { game: ctfGame, players: 4, ticks: 1200, bot: (s, p) => ctfGame.bot(s as Game, p) },
  { game: survivalGame, players: 2, ticks: 1200, bot: (s, p) => survivalGame.bot(s as Game, p) },
  { game: jostleGame(11), players: 1, ticks: 600 },
  { game: stirredPileGame(120), players: 1, ticks: 600 },
];

describe('game state schemas', () => {
  it('describe every byte of the state, and a snapped state quantises to what was sent', () => {
    for (const c of CASES) {
      const schema = c.game.stateSchema!;
      const options = c.game.options?.(c.players, 9);
      const sim = c.game.create({
        seed: 9,
        players: c.players,
        options: options ?? new Uint8Array(0),
      });
      const report = { maxError: 0, clamped: 0 };
      for (let t = 0; t < c.ticks; t++) {
        const row = Array.from({ length: c.players }, (_, p) =>
          c.bot ? c.bot(sim as Simulation, p) : 0,
        );
        sim.step(row);
        if (t % 3 !== 0) continue;
        const own = sim.save();
        const words = schema.quantise(own, report);
        sim.load(schema.merge(own, words));
        expect({
          game: c.game.id,
          tick: sim.tick,
          words: Array.from(schema.quantise(sim.save())),
        }).toEqual({
          game: c.game.id,
          tick: sim.tick,
          words: Array.from(words),
        });
      }
      expect({ game: c.game.id, clamped: report.clamped }).toEqual({ game: c.game.id, clamped: 0 });
      expect(report.maxError).toBeLessThan(1);
    }
  });

  it('keep every client on the server’s words through 100 ± 30 ms and 5 % loss, for fewer bytes than byte deltas', () => {
    for (const c of CASES.slice(0, 3)) {
      const schemaRun = run(c, 'schema');
      const bytesRun = run(c, 'bytes');
      const id = c.game.id;
      expect(schemaRun.checked).toBeGreaterThan(50);
      expect({ id, mismatches: schemaRun.mismatches, bad: schemaRun.bad }).toEqual({
        id,
        mismatches: 0,
        bad: 0,
      });
      expect({ id, mismatches: bytesRun.mismatches }).toEqual({ id, mismatches: 0 });
      // The schema codec sends less than a third (the game is named on failure).
      expect({ id, underAThird: schemaRun.bytes < bytesRun.bytes / 3 }).toEqual({
        id,
        underAThird: true,
      });
    }
  });

  it('let a client of a physics world keep its own warm-start cache and still load every snapshot', () => {
    const r = run(CASES[3]!, 'schema');
    expect(r.checked).toBeGreaterThan(50);
    expect(r.mismatches).toBe(0);
    expect(r.bad).toBe(0);
  });

  it('over a stream, code each snapshot against the one before it; over datagrams, against the acknowledged one', () => {
    const stream = run(CASES[3]!, 'schema', 'stream');
    const datagrams = run(CASES[3]!, 'schema', 'datagrams');
    for (const r of [stream, datagrams]) {
      expect(r.checked).toBeGreaterThan(50);
      expect({ mismatches: r.mismatches, bad: r.bad }).toEqual({ mismatches: 0, bad: 0 });
    }
    // 60 Hz and a snapshot every 3 ticks: one interval back over the stream (less only right
    // after the full snapshot a join brings, sent at once)…
    expect(Math.max(...stream.baseAges)).toBe(3);
    expect(stream.baseAges.filter((a) => a === 3).length).toBeGreaterThan(
      stream.baseAges.length - 3,
    );
    // …a round trip or more back over datagrams (100 ± 30 ms each way: ≥ 6 intervals).
    expect(Math.min(...datagrams.baseAges)).toBeGreaterThanOrEqual(6);
    // A nearer base costs fewer bytes.
    expect(stream.bytes).toBeLessThan(datagrams.bytes);
  });

  it('extrapolate positions from two snapshots when velocities are not sent, and stay on the server’s words', () => {
    const positions: Case = { ...CASES[3]!, game: stirredPileGame(120, 'local') };
    for (const link of ['stream', 'datagrams'] as const) {
      const r = run(positions, 'schema', link);
      const withVelocities = run(CASES[3]!, 'schema', link);
      expect(r.checked).toBeGreaterThan(50);
      expect({ link, mismatches: r.mismatches, bad: r.bad }).toEqual({
        link,
        mismatches: 0,
        bad: 0,
      });
      // Deltas name an older snapshot, and positions alone cost less than positions and velocities.
      expect(r.olders).toBeGreaterThan(r.checked / 2);
      expect(withVelocities.olders).toBe(0);
      expect({ link, fewer: r.bytes < withVelocities.bytes }).toEqual({ link, fewer: true });
    }
  });
});

/**
 * A room of `c` with a client per player over links of 100 ± 30 ms and 5 % loss for 6 simulated
 * seconds: datagrams (lost ones are lost), or a stream (lost ones sent again, everything in order:
 * TCP's model). Also the deltas' base ages (ticks) and how many named an older snapshot.
 */
function run(
  c: Case,
  codec: 'schema' | 'bytes',
  kind: 'datagrams' | 'stream' = 'datagrams',
): {
  checked: number;
  mismatches: number;
  bad: number;
  bytes: number;
  baseAges: number[];
  olders: number;
} {
  const scheduler = new EventScheduler(0);
  const clock = scheduler.clock;
  const rng = new Random(4);
  const room = new StateSyncRoom({
    game: c.game,
    name: 't',
    clock,
    players: c.players,
    seed: 9,
    codec,
    randomU32: () => rng.nextU32(),
  });
  const schema = c.game.stateSchema!;
  const history = new Map<number, Int32Array>();
  scheduler.every(4, () => {
    const before = room.tick;
    room.update(clock.now());
    if (room.tick !== before) history.set(room.tick, schema.quantise(room.simulation.save()));
  });
  let bytes = 0;
  const baseAges: number[] = [];
  let olders = 0;
  const sessions: StateSyncSession<ButtonInput, Simulation>[] = [];
  let checked = 0;
  let mismatches = 0;
  for (let i = 0; i < c.players; i++) {
    const link = new SimulatedLink({
      scheduler,
      seed: 31 + i,
      latencyMs: 100,
      jitterMs: 30,
      loss: 0.05,
      ordered: kind === 'stream',
      retransmit: kind === 'stream',
    });
    const end: Transport = link.b;
    const counted: Transport = {
      send: (b) => {
        bytes += b.length;
        if (peekStateSyncType(b) === 'snapshot') {
          const m = decodeStateSyncMessage(b) as StateSnapshotMessage;
          if (m.base >= 0) baseAges.push(m.tick - m.base);
          if (m.older >= 0) olders++;
        }
        end.send(b);
      },
      get reliable() {
        return end.reliable;
      },
      onMessage: (h) => {
        end.onMessage(h);
      },
      onClose: (h) => {
        end.onClose(h);
      },
      close: (r) => {
        end.close(r);
      },
      get isOpen() {
        return end.isOpen;
      },
    };
    room.accept(counted);
    let held: ButtonInput = 0;
    const bot = c.bot;
    const session = new StateSyncSession<ButtonInput, Simulation>({
      transport: link.a,
      clock,
      room: 't',
      game: c.game as never,
      localInput: bot
        ? (tick, sim) => {
            if (tick % 6 === 0) held = bot(sim, session.welcome?.slot ?? 0);
            return held;
          }
        : undefined,
    });
    sessions.push(session);
    let seen = -1;
    scheduler.every(
      1000 / 60,
      () => {
        session.frame(clock.now());
        const state = session.snapshotState;
        if (state === undefined || session.snapshotTick === seen) return;
        seen = session.snapshotTick;
        const want = history.get(seen);
        const got = schema.quantise(state);
        checked++;
        if (want?.length !== got.length || got.some((v, k) => v !== want[k])) {
          mismatches++;
        }
      },
      1 + i * 3.7,
    );
  }
  scheduler.runUntil(6000);
  return {
    checked,
    mismatches,
    bad: sessions.reduce((a, s) => a + s.stats.badSnapshots, 0),
    bytes,
    baseAges,
    olders,
  };
}

describe('late inputs in state sync', () => {
  /**
   * Four CTF bots over a 100 ± 30 ms, 5 % loss stream (TCP's head-of-line blocking) for `seconds`;
   * `share`: late inputs per input issued after the first 10 s.
   */
  function lateness(
    lead: 'auto' | number,
    seconds = 20,
  ): {
    late: number;
    issued: number;
    share: number;
    events: number;
    lead: number;
    roomLate: number;
  } {
    const scheduler = new EventScheduler(0);
    const clock = scheduler.clock;
    const rng = new Random(6);
    const room = new StateSyncRoom({
      game: ctfGame,
      name: 'late',
      clock,
      players: 4,
      seed: 3,
      randomU32: () => rng.nextU32(),
    });
    scheduler.every(4, () => room.update(clock.now()));
    const sessions: StateSyncSession<ButtonInput, Game>[] = [];
    let events = 0;
    for (let i = 0; i < 4; i++) {
      const link = new SimulatedLink({
        scheduler,
        seed: 40 + i,
        latencyMs: 100,
        jitterMs: 30,
        loss: 0.05,
        ordered: true,
        retransmit: true,
      });
      room.accept(link.b);
      const own: { session?: StateSyncSession<ButtonInput, Game> } = {};
      const session = new StateSyncSession<ButtonInput, Game>({
        transport: link.a,
        clock,
        room: 'late',
        game: ctfGame,
        lead,
        localInput: (_t, sim) => ctfGame.bot(sim, own.session?.welcome?.slot ?? 0),
        onEvent: (e) => {
          if (e.type === 'late-inputs') events++;
        },
      });
      own.session = session;
      sessions.push(session);
      scheduler.every(1000 / 60, () => session.frame(clock.now()), 1 + i * 3.7);
    }
    const sum = (k: 'lateInputs' | 'issuedInputs'): number =>
      sessions.reduce((a, s) => a + s.stats[k], 0);
    scheduler.runUntil(10_000);
    const at10 = { late: sum('lateInputs'), issued: sum('issuedInputs') };
    scheduler.runUntil(seconds * 1000);
    return {
      late: sum('lateInputs'),
      issued: sum('issuedInputs'),
      share: (sum('lateInputs') - at10.late) / (sum('issuedInputs') - at10.issued),
      events,
      lead: Math.max(...sessions.map((s) => s.stats.lead)),
      roomLate: room.stats.lateInputs,
    };
  }

  it('are counted per client, reported as events, and an automatic lead cuts them to a fraction of a fixed one', () => {
    const fixed = lateness(8);
    const auto = lateness('auto');
    // The server's per-seat count reaches the client: every late input is an event's worth.
    expect(fixed.late).toBeGreaterThan(0.2 * fixed.issued);
    expect(fixed.events).toBeGreaterThan(10);
    expect(auto.late).toBeLessThan(fixed.late / 5);
    expect(auto.lead).toBeGreaterThan(8);
    // The room's count (what /metrics adds up) is the clients' sum, but for the last snapshot's news.
    expect(fixed.roomLate).toBeGreaterThanOrEqual(fixed.late);
    expect(fixed.roomLate - fixed.late).toBeLessThan(0.05 * fixed.late);
  });

  it('stay at most 1 % over the stream (four simulated minutes)', () => {
    // The lead keeps the largest need of the last 2 minutes (NeededLead): a retransmission stall
    // raises it at once and it stays up while stalls that long keep coming. The old rule — a
    // tick more per late report, a tick less after 5 quiet seconds — left 2.6 % late here.
    const r = lateness('auto', 250);
    expect(r.share).toBeLessThanOrEqual(0.01);
    expect(r.share).toBeGreaterThan(0); // a stall longer than any before still comes late
  });
});
