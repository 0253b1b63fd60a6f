/**
 * The lab's three-model comparison (chapter 6: state sync, lockstep, rollback) measured over a real
 * transport instead of the simulated link, in real time: one machine runs the room (a relay or a
 * state-sync room) and plays player 1 on an in-memory pipe; player 2 joins over the impaired link
 * (WebRTC through coturn behind the UDP proxy, or the kernel's TCP through the TUN link) — the
 * peer-to-peer shape of docs/webrtc.md. Capture the flag, bots re-deciding every 100 ms.
 *
 * It measures what the lab's table does (network-model.ts), for player 2, the impaired player:
 * protocol bytes a second each way, the mean time from its input to its own screen and to player
 * 1's (the lab's `LatencyProbe`), the corrections either machine showed (0.5–40 units), and the
 * state-sync render delay — plus the link's bytes on the wire.
 */
import {
  LockstepSession,
  Relay,
  Random,
  RollbackSession,
  StateSyncRoom,
  StateSyncSession,
  memoryPair,
  performanceClock,
  relayGameOf,
  type ButtonInput,
  type Correction,
  type NetSession,
  type Transport,
} from 'fixedstep';
import type { Game, RegisteredGame } from '@fixedstep/games';
import { gameDef } from '../../apps/lab/src/games-view/games.js';
import {
  BOT_EVERY,
  LatencyProbe,
  playerShift,
  visibleCorrection,
} from '../../apps/lab/src/chapters/network/network-model.js';
import { arenaRender } from '../../apps/lab/src/chapters/network/network-state.js';
import type { WireCounts } from './probe.js';

export type Model = 'statesync' | 'lockstep' | 'rollback';
export const MODELS: readonly Model[] = ['statesync', 'lockstep', 'rollback'];

/** Player 2's link: made for one match, after the room exists. */
export interface ImpairedLink {
  /** Player 2's transport to the room. */
  joiner: Transport;
  /** Start the link's conditions (the handshake ran on a clean link). */
  impair(): void;
  /** What crossed the link so far. */
  wire(): WireCounts | Promise<WireCounts>;
  close(): Promise<void> | void;
}

/** One row of the comparison, measured. */
export interface ModelRow {
  model: Model;
  /** Player 2's protocol bytes a second, to the room and back. */
  upBytesPerSecond: number;
  downBytesPerSecond: number;
  /** Player 2's link on the wire, bytes a second each way (up: from player 2). */
  wireUpBytesPerSecond: number;
  wireDownBytesPerSecond: number;
  /** Mean ms from player 2's input being sampled to its own screen and to player 1's. */
  ownLatencyMs: number;
  otherLatencyMs: number;
  /** Corrections either machine showed (0.5–40 units), and the largest, units. */
  corrections: number;
  largestCorrection: number;
  /** State sync: player 2's render delay, ms (0 for the input-sync models). */
  renderDelayMs: number;
  /** Lockstep: player 2's input delay, ticks; rollback: its lead, ticks. */
  delayTicks: number;
  /**
   * State sync: player 2's inputs that reached the room after their tick was stepped, per input
   * it issued while measured, and its lead at the end (ticks). Absent for the other models.
   */
  lateShare?: number;
  lead?: number;
  /** Seconds played (measured from the first tick). */
  seconds: number;
}

const clock = performanceClock();

/** Plays `seconds` of one model with player 2 on `connect`'s link; returns its row. */
export async function runModelMatch(o: {
  model: Model;
  seconds: number;
  seed?: number;
  connect: (accept: (t: Transport) => void) => Promise<ImpairedLink>;
}): Promise<ModelRow> {
  const def: RegisteredGame = gameDef('ctf');
  const seed = o.seed ?? 7;
  const probe = new LatencyProbe();
  let corrections = 0;
  let largest = 0;
  const note = (units: number) => {
    if (!visibleCorrection(units)) return;
    corrections++;
    largest = Math.max(largest, units);
  };
  const before = def.create({ seed, players: 2 });
  const after = def.create({ seed, players: 2 });
  const onCorrection = (c: Correction) => {
    try {
      before.load(c.before);
      after.load(c.after);
    } catch {
      return;
    }
    note(playerShift(before, after));
  };
  const timers: ReturnType<typeof setInterval>[] = [];
  const random = new Random(seed);
  let accept: (t: Transport) => void;
  let close: () => void;
  if (o.model === 'statesync') {
    const room = new StateSyncRoom<Game>({
      game: def,
      name: 'netem',
      clock,
      players: 2,
      seed,
      randomU32: () => random.nextU32(),
    });
    timers.push(setInterval(() => room.update(clock.now()), 4));
    accept = (t) => {
      room.accept(t);
    };
    close = () => undefined;
  } else {
    const game = relayGameOf(def);
    const relay = new Relay({
      clock,
      randomU32: () => random.nextU32(),
      catalog: (id, version) =>
        id === game.id && version === game.version
          ? game
          : { code: 'UNKNOWN_GAME', message: `no game "${id}" v${version} here` },
    });
    timers.push(
      setInterval(() => {
        relay.update();
      }, 4),
    );
    accept = (t) => relay.accept(t);
    close = () => {
      relay.close();
    };
  }
  let link: ImpairedLink;
  try {
    link = await o.connect(accept);
  } catch (error) {
    for (const t of timers) clearInterval(t);
    close();
    throw error;
  }
  try {
    const [hostSide, roomSide] = memoryPair();
    accept(roomSide);
    const slots = [0, 1];
    const bot = (i: number) => {
      let held = 0;
      return (tick: number, sim: object) => {
        if (tick % BOT_EVERY === 0) held = def.bot(sim as Game, slots[i]!);
        if (i === 1) probe.sample(tick, clock.now());
        return held;
      };
    };
    const transports = [hostSide, link.joiner];
    const common = (i: number) => ({
      transport: transports[i]!,
      clock,
      room: 'netem',
      players: 2,
      seed,
      name: `p${i + 1}`,
    });
    interface Machine {
      frame(now: number): void;
      tick: () => number;
      shownTick: () => number;
      bytes: () => [number, number];
      delay: () => number;
      /** Inputs issued and late so far, and the lead (state sync). */
      inputs?: () => { issued: number; late: number; lead: number };
    }
    const machines: Machine[] = [0, 1].map((i): Machine => {
      if (o.model === 'statesync') {
        const s = new StateSyncSession<ButtonInput, Game>({
          ...common(i),
          game: def,
          render: arenaRender(def),
          onCorrection: (c) => {
            note(c.size);
          },
          onEvent: (e) => {
            if (e.type === 'welcome') slots[i] = e.welcome.slot;
          },
          localInput: bot(i),
        });
        return {
          frame(now) {
            s.frame(now);
            s.render(now);
          },
          tick: () => (s.simulation ? s.tick : 0),
          shownTick: () => Math.floor(s.renderTick),
          bytes: () => [s.stats.bytesSent, s.stats.bytesReceived],
          delay: () => s.renderDelayMs,
          inputs: () => ({
            issued: s.stats.issuedInputs,
            late: s.stats.lateInputs,
            lead: s.stats.lead,
          }),
        };
      }
      const options = {
        ...common(i),
        game: def.info.id,
        gameVersion: def.info.version,
        input: def.input,
        createSimulation: (w: { config: Uint8Array; slot: number }) => {
          slots[i] = w.slot;
          return def.create(def.decodeConfig(w.config));
        },
        localInput: bot(i),
        onCorrection,
      };
      const s: NetSession =
        o.model === 'lockstep' ? new LockstepSession(options) : new RollbackSession(options);
      return {
        frame(now) {
          s.frame(now);
        },
        tick: () => s.tick,
        shownTick: () => (o.model === 'lockstep' ? s.tick : s.confirmedStateTick()),
        bytes: () => [s.stats.bytesSent, s.stats.bytesReceived],
        delay: () => (o.model === 'lockstep' ? s.stats.inputDelay : s.stats.lead),
      };
    });
    // Until both play, on a clean link; then the link's conditions and the counters start.
    await frames(machines, () => machines.every((m) => m.tick() > 0), 20_000);
    link.impair();
    const wire0 = await link.wire();
    const bytes0 = machines[1]!.bytes();
    const inputs0 = machines[1]!.inputs?.();
    const t0 = clock.now();
    await frames(
      machines,
      () => clock.now() - t0 >= o.seconds * 1000,
      o.seconds * 1000 + 5000,
      () => {
        probe.frame(clock.now(), machines[1]!.tick(), machines[0]!.shownTick());
      },
    );
    const seconds = (clock.now() - t0) / 1000;
    const wire = await link.wire();
    const bytes = machines[1]!.bytes();
    const inputs = machines[1]!.inputs?.();
    const late =
      inputs && inputs0
        ? {
            lateShare: (inputs.late - inputs0.late) / Math.max(1, inputs.issued - inputs0.issued),
            lead: inputs.lead,
          }
        : {};
    return {
      ...late,
      model: o.model,
      upBytesPerSecond: (bytes[0] - bytes0[0]) / seconds,
      downBytesPerSecond: (bytes[1] - bytes0[1]) / seconds,
      wireUpBytesPerSecond: (wire.up - wire0.up) / seconds,
      wireDownBytesPerSecond: (wire.down - wire0.down) / seconds,
      ownLatencyMs: probe.ownMs,
      otherLatencyMs: probe.otherMs,
      corrections,
      largestCorrection: largest,
      renderDelayMs: o.model === 'statesync' ? machines[1]!.delay() : 0,
      delayTicks: o.model === 'statesync' ? 0 : machines[1]!.delay(),
      seconds,
    };
  } finally {
    for (const t of timers) clearInterval(t);
    close();
    await link.close();
  }
}

/** Display frames at 60 Hz for both machines until `done` (rejects after `limitMs`). */
function frames(
  machines: readonly { frame(now: number): void }[],
  done: () => boolean,
  limitMs: number,
  after?: () => void,
): Promise<void> {
  const start = clock.now();
  return new Promise((resolve, reject) => {
    let next = clock.now();
    const frame = () => {
      const now = clock.now();
      for (const m of machines) m.frame(now);
      after?.();
      if (done()) {
        resolve();
        return;
      }
      if (now - start > limitMs) {
        reject(new Error(`runModelMatch: not done within ${limitMs} ms`));
        return;
      }
      next += 1000 / 60;
      setTimeout(frame, Math.max(0, next - clock.now()));
    };
    frame();
  });
}
