/**
 * A Rapier world under the rest of fixedstep: the loop on any display, replays, lockstep and
 * rollback over the simulated network.
 */
import { beforeAll, describe, expect, it } from 'vitest';
import {
  ButtonSampler,
  FixedLoop,
  ReplayRecorder,
  SimulatedDisplay,
  SimulatedMatch,
  fnv1a64,
  hex64,
  packButtons,
  verifyReplay,
  type DisplayEvent,
} from 'fixedstep';
import {
  RapierSimulation,
  TowerButtons,
  loadRapier,
  rapierGame,
  towerScene,
} from '@fixedstep/rapier';

const FIRE = 1 << TowerButtons.FIRE;
const TICKS = 480;
/** Presses of FIRE by the player, ms (each held for {@link HOLD_MS}): three shots. */
const PRESSES_MS = [510, 2610, 5010];
const HOLD_MS = 70;
/** The tick a time falls in. */
const tickOf = (ms: number): number => Math.floor((ms * 60) / 1000);
/** The per-tick inputs those presses give: pressed in the first tick, down until the release's. */
function tickInputs(): number[] {
  const out = new Array<number>(TICKS).fill(0);
  for (const ms of PRESSES_MS) {
    for (let t = tickOf(ms); t <= tickOf(ms + HOLD_MS); t++) out[t] = packButtons(FIRE, 0);
    out[tickOf(ms)] = packButtons(FIRE, FIRE);
  }
  return out;
}

beforeAll(async () => {
  await loadRapier();
});

/** The per-tick hashes of the tower driven by FixedLoop on a simulated display of `hz`. */
function onDisplay(hz: number, hitches: readonly DisplayEvent[]): bigint[] {
  const sim = new RapierSimulation(towerScene());
  const loop = new FixedLoop({ step: 60 });
  const display = new SimulatedDisplay({ hz, jitter: 0.3, seed: hz, events: hitches });
  const sampler = new ButtonSampler();
  const events = PRESSES_MS.flatMap((ms) => [
    { ms, down: true },
    { ms: ms + HOLD_MS, down: false },
  ]);
  const hashes: bigint[] = [];
  let next = 0;
  loop.frame(display.next().time);
  while (sim.tick < TICKS) {
    const now = display.next().time;
    // Key events reach the page with their timestamps, before the frame that follows them.
    while (next < events.length && events[next]!.ms <= now) {
      const e = events[next++]!;
      sampler.push(e.ms, TowerButtons.FIRE, e.down);
    }
    const steps = loop.frame(now);
    for (let j = 0; j < steps && sim.tick < TICKS; j++) {
      sim.step([sampler.sample(loop, j)]);
      hashes.push(sim.hash());
    }
  }
  expect(loop.droppedMs(), `${hz} Hz dropped time`).toBe(0);
  sim.dispose();
  return hashes;
}

describe('FixedLoop: the same world at every display rate', () => {
  it('30, 60, 144 and 240 Hz displays with ±30 % jitter and a 200 ms hitch: equal hashes every tick', () => {
    const hitches: DisplayEvent[] = [{ kind: 'hitch', atMs: 1500, durationMs: 200 }];
    // The reference: the per-tick inputs stepped directly, no loop at all.
    const direct = new RapierSimulation(towerScene());
    const reference = tickInputs().map((input) => {
      direct.step([input]);
      return direct.hash();
    });
    expect(direct.scene.shots).toBe(3);
    direct.dispose();
    for (const hz of [30, 60, 144, 240]) {
      const hashes = onDisplay(hz, hitches);
      const first = hashes.findIndex((h, i) => h !== reference[i]);
      expect(first, `${hz} Hz: first tick whose hash differs`).toBe(-1);
      expect(hashes).toHaveLength(TICKS);
    }
  });
});

describe('replays', () => {
  it('a replay recorded with ReplayRecorder verifies; an edited input does not, at its tick', () => {
    const inputs = tickInputs();
    const record = (edit?: number): Uint8Array => {
      const sim = new RapierSimulation(towerScene());
      const rec = new ReplayRecorder({
        gameId: 'rapier-tower-8x2',
        gameVersion: '1',
        tickRate: 60,
        players: ['ann'],
        tickHashes: true,
        checkpointEvery: 60,
        keyframeEvery: 120,
      });
      rec.start(sim);
      for (let t = 0; t < TICKS; t++) {
        const row = [inputs[t]!];
        sim.step(row);
        rec.record(t === edit ? [0] : row, sim);
      }
      const file = rec.finish();
      sim.dispose();
      return file;
    };
    const factory = () => new RapierSimulation(towerScene());
    const good = verifyReplay(record(), factory, { gameId: 'rapier-tower-8x2' });
    expect(good.ok).toBe(true);
    expect(good.ticks).toBe(TICKS);
    // The second shot (tick 156) left out of the file: the replay no longer reproduces the run.
    const shot = tickOf(PRESSES_MS[1]!);
    const bad = verifyReplay(record(shot), factory, { gameId: 'rapier-tower-8x2' });
    expect(bad.ok).toBe(false);
    expect(bad.exact).toBe(true);
    expect(bad.firstMismatchTick).toBe(shot + 1);
  });
});

/** Player `slot` fires at tick 40 + 150·k + 75·slot: a script of the tick only, for the offline truth. */
const scripted = (tick: number, slot: number): number =>
  tick % 150 === 40 + 75 * slot ? packButtons(FIRE, FIRE) : 0;

const tower = rapierGame({
  id: 'rapier-tower',
  minPlayers: 1,
  maxPlayers: 4,
  scene: () => towerScene({ players: 2 }),
});

/** The FNV-1a 64 of `save()` after `ticks` ticks of the script, stepped offline. */
function offline(players: number, ticks: number): string {
  const sim = tower.create({ seed: 1, players, options: new Uint8Array(0) });
  const row = new Array<number>(players);
  for (let t = 0; t < ticks; t++) {
    for (let p = 0; p < players; p++) row[p] = scripted(t, p);
    sim.step(row);
  }
  const h = hex64(fnv1a64(sim.save()));
  sim.dispose();
  return h;
}

describe('over the simulated network', () => {
  for (const kind of ['rollback', 'lockstep'] as const) {
    it(`${kind}: two players and a spectator, 80 ± 20 ms and 2 % loss, end on the offline state`, () => {
      const ticks = 600;
      const match = new SimulatedMatch({
        game: tower,
        seed: 1,
        ticks,
        link: { latencyMs: 80, jitterMs: 20, loss: 0.02 },
        relay: { deadlineMs: 400 },
        clients: [
          { kind, input: (tick, _sim, slot) => scripted(tick, slot) },
          { kind, input: (tick, _sim, slot) => scripted(tick, slot) },
          { kind: 'spectator' },
        ],
      });
      const result = match.run(120_000);
      expect(result.finished).toBe(true);
      expect(result.hashesAgree).toBe(true);
      // Nothing was filled after a deadline, so the room played exactly the script.
      expect(result.relay.filledInputs).toBe(0);
      const truth = offline(2, ticks);
      for (const c of result.clients) expect(c.finalHash).toBe(truth);
      expect(result.room?.desyncs ?? []).toHaveLength(0);
      const players = result.clients.filter((c) => c.kind !== 'spectator');
      // Rollback: Rapier was rolled back and re-simulated, and still agreed with the offline run.
      const rollbacks = players.map((c) => c.stats.rollbacks);
      const depth = Math.max(...players.map((c) => c.stats.maxRollbackDepth));
      // (Relay protocol 6 sends inputs two ticks a datagram over lossy links: fewer, deeper
      // rollbacks — 5 and 8 here, 12 ticks deep.)
      expect({ some: Math.min(...rollbacks) >= 3, deep: depth >= 4 }).toEqual(
        kind === 'rollback' ? { some: true, deep: true } : { some: false, deep: false },
      );
      for (const s of match.sessions) (s?.simulation as RapierSimulation | undefined)?.dispose();
    });
  }
});
