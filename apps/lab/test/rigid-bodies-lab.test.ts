/**
 * Chapter 10's model, headless: the live tower knocked over through the input sampler, its replay
 * re-simulated with every tick's hash equal to the live run's, the two network machines agreeing
 * after rollbacks (and with the offline run), the own world beside Rapier's, and the chapter's
 * sentences built from those numbers.
 */
import { readFileSync } from 'node:fs';
import { beforeAll, describe, expect, it } from 'vitest';
import { fnv1a64, gameSetup, hex64, packButtons, readReplay } from 'fixedstep';
import { loadRapier, type RapierModule } from '@fixedstep/rapier';
import {
  BodyTrack,
  DUEL_GAME,
  FIRE,
  KnockOver,
  ReplayRun,
  RigidLab,
  TURNED_RAD,
  botFires,
  openRigidLab,
  towerShape,
  type WorldReadouts,
} from '../src/chapters/rigid-bodies/rigid-bodies-lab.js';
import {
  MEASURED,
  costText,
  knockNote,
  netVerdict,
  replayVerdict,
  worldNote,
} from '../src/chapters/rigid-bodies/rigid-bodies-text.js';

let rapier: RapierModule;
beforeAll(async () => {
  rapier = await loadRapier();
});

/** A fresh lab with FIRE pressed at `atMs` for 60 ms, run to `untilMs`. */
function knocked(atMs: number, untilMs: number): RigidLab {
  const lab = new RigidLab(rapier);
  lab.advanceTo(atMs);
  lab.fire(atMs, true);
  lab.fire(atMs + 60, false);
  lab.advanceTo(untilMs);
  return lab;
}

/** The golden hash of the live tower at tick 240, fired at 0.5 s (printed when it differs). */
const KNOCKED_AT_240 = '843ff45b5684bd71';

describe('the live tower', () => {
  it('stands until Fire; one press at 0.5 s knocks it over (boxes turned, the top falls)', () => {
    const lab = new RigidLab(rapier);
    lab.advanceTo(400);
    const standing = lab.knock.readouts();
    expect(standing.shots).toBe(0);
    expect(standing.turned).toBe(0);
    expect(standing.boxes).toBe(16);
    // 8 rows of 0.5 m boxes, 1 mm apart, minus their 1 % margin: 4.0 m.
    expect(standing.top).toBeGreaterThan(3.9);
    lab.fire(500, true);
    lab.fire(560, false);
    lab.advanceTo(4000);
    const r = lab.knock.readouts();
    expect(r.tick).toBe(240);
    expect(r.shots).toBe(1);
    expect({ turned: r.turned, fell: r.top < 2 }).toEqual({ turned: 9, fell: true });
    expect(r.maxTurnDeg).toBeGreaterThan(80);
    expect(r.hash, `golden hash at tick 240 (actual ${r.hash})`).toBe(KNOCKED_AT_240);
    lab.dispose();
  });

  it('a press lands on the tick whose span holds it, whatever the frames: held keys fire once', () => {
    // Pressed at 500 ms: tick 30 (500 × 60 / 1000) takes it. Held for 2 s, still one shot.
    const lab = new RigidLab(rapier);
    lab.advanceTo(100);
    lab.fire(500, true);
    lab.advanceTo(499);
    expect(lab.knock.readouts().shots).toBe(0);
    lab.advanceTo(520);
    expect(lab.knock.readouts().shots).toBe(1);
    lab.advanceTo(2500);
    lab.fire(2500, false);
    lab.advanceTo(4000);
    expect(lab.knock.readouts().shots).toBe(1);
    // The replay file holds that press on tick 30 only, held down to the tick of the release
    // (2500 ms: tick 150, which it was down for the start of).
    const replay = readReplay(lab.knock.replayFile());
    const ticks = Array.from({ length: replay.tickCount }, (_, t) => t);
    expect(ticks.filter((t) => replay.input(t, 0) >>> 16 !== 0)).toEqual([30]);
    expect(ticks.filter((t) => (replay.input(t, 0) & 1) !== 0)).toEqual(ticks.slice(30, 151));
    lab.dispose();
  });

  it('repeats exactly: two labs driven the same way have the same hash at every tick', () => {
    const a = knocked(500, 3000);
    const b = knocked(500, 3000);
    for (let t = 0; t <= 180; t++) expect(a.knock.hashAt(t)).toBe(b.knock.hashAt(t));
    expect(a.knock.hashAt(181)).toBeUndefined();
    a.dispose();
    b.dispose();
  });

  it('restart goes back to tick 0 and the same run', () => {
    const lab = knocked(500, 4000);
    lab.restart();
    expect(lab.timeMs).toBe(0);
    expect(lab.knock.tick).toBe(0);
    expect(lab.replay).toBeUndefined();
    lab.advanceTo(500);
    lab.fire(500, true);
    lab.fire(560, false);
    lab.advanceTo(4000);
    expect(lab.knock.readouts().hash).toBe(KNOCKED_AT_240);
    lab.dispose();
  });
});

describe('the replay', () => {
  it('re-simulates the recording with every tick’s hash equal to the live run’s', () => {
    const lab = knocked(500, 4000);
    const run = lab.startReplay();
    expect(run.readouts().tick).toBe(0);
    // 2 s of the 60 Hz display (5 ms more, so the frame at 2 s is surely in): 120 ticks.
    lab.advanceBy(2005);
    const half = run.readouts();
    expect(half.ended).toBe(false);
    expect(half.tick).toBe(120);
    expect(half.hash).toBe(half.liveHash);
    lab.advanceBy(3000);
    const r = run.readouts();
    expect(r).toMatchObject({
      tick: 240,
      ticks: 240,
      ended: true,
      compared: 241, // ticks 0 … 240
      different: 0,
      firstDifferent: -1,
      checkpoints: 5, // the file's hashes at ticks 0, 60, 120, 180, 240
      mismatches: 0,
      shots: 1,
      hash: KNOCKED_AT_240,
      liveHash: KNOCKED_AT_240,
    });
    // Inputs and five hashes: a few hundred bytes for 4 s, no state.
    expect(r.bytes).toBeLessThan(400);
    expect(replayVerdict(r)).toBe(
      'Replayed all 240 ticks: every tick’s hash equal to the live run’s (241 compared, tick 0 included), and 5 checkpoint hashes of the file reproduced.',
    );
    lab.dispose();
  });

  it('the comparison can fail: another run’s recording differs from the first tick after its shot', () => {
    const live = new KnockOver(rapier);
    const other = new KnockOver(rapier);
    for (const k of [live, other]) {
      k.press(500, true);
      k.press(560, false);
    }
    // The other run fires again at 1 s; the live one does not.
    other.press(1000, true);
    other.press(1060, false);
    for (let t = 1000 / 60; t <= 3000; t += 1000 / 60) {
      live.frame(t);
      other.frame(t);
    }
    const run = new ReplayRun(other.replayFile(), live, rapier, 3000);
    run.player.advance(180);
    const r = run.readouts();
    expect(r.different).toBeGreaterThan(0);
    expect(r.firstDifferent).toBe(61); // the second shot went in at tick 60
    expect(r.mismatches).toBe(0); // the file itself is sound
    expect(replayVerdict(r)).toMatch(/^The replay differs from the live run: first at tick 61 /);
    for (const k of [live, other]) k.dispose();
    run.dispose();
  });
});

describe('the network', () => {
  it('two machines, 80 ± 20 ms and 2 % loss: rollbacks happen and the hashes agree', () => {
    const lab = new RigidLab(rapier);
    lab.advanceTo(6000);
    const r = lab.net.readouts();
    expect(r.machines.map((m) => m.slot)).toEqual([0, 1]);
    expect(r.checkpoint).toBe(300);
    expect(r.equal).toBe(true);
    expect(r.hashes[0]).toBe(r.hashes[1]);
    expect(r.desyncs).toBe(0);
    expect(r.lost).toBeGreaterThan(0);
    const rollbacks = r.machines[0].rollbacks + r.machines[1].rollbacks;
    expect(rollbacks).toBeGreaterThan(0);
    expect(Math.max(r.machines[0].maxDepth, r.machines[1].maxDepth)).toBeGreaterThanOrEqual(4);
    // The bots fired at 1 s (player 1), 3 s (player 2) and 5 s (player 1): both machines know.
    for (const m of r.machines) expect(m.shots).toEqual([2, 1]);
    // The relay filled no input after a deadline, so the room played exactly the bots' script:
    // its state at the checkpoint is the offline run's.
    expect(lab.net.relay.stats.filledInputs).toBe(0);
    const offline = DUEL_GAME.create(gameSetup(DUEL_GAME, 2, 1));
    const row = [0, 0];
    for (let t = 0; t < r.checkpoint; t++) {
      for (const p of [0, 1]) row[p] = botFires(t, p) ? packButtons(1 << FIRE, 1 << FIRE) : 0;
      offline.step(row);
    }
    expect(r.hashes[0]).toBe(hex64(fnv1a64(offline.save())));
    offline.dispose();
    expect(netVerdict(r)).toBe(
      `Both machines computed the same world at tick 300, after ${rollbacks} rollbacks (the deepest ${Math.max(r.machines[0].maxDepth, r.machines[1].maxDepth)} ticks).`,
    );
    lab.dispose();
  });

  it('each machine fires from its side: a press on player 2’s button reaches both machines', () => {
    const lab = new RigidLab(rapier);
    lab.setBots(false);
    lab.advanceTo(2000);
    lab.net.press(1, 2000, true);
    lab.net.press(1, 2050, false);
    lab.advanceTo(4000);
    const r = lab.net.readouts();
    for (const m of r.machines) expect(m.shots).toEqual([0, 1]);
    // Player 1's machine learnt of it late: it rolled back.
    expect(r.machines[0].rollbacks).toBeGreaterThan(0);
    expect(r.machines[1].rollbacks).toBe(0);
    expect(r.equal).toBe(true);
    // Player 2's ball left from the right, towards the tower.
    const ball = lab.net.machine(0)!.sim;
    expect(ball.world.getRigidBody(ball.scene.balls[1]).translation().x).toBeLessThan(6);
    lab.dispose();
  });

  it('a terrible link (250 ± 100 ms, 20 % loss): deeper rollbacks, the same hashes', () => {
    const lab = new RigidLab(rapier);
    lab.setLink({ latencyMs: 250, jitterMs: 100, loss: 0.2 });
    lab.advanceTo(10_000);
    const r = lab.net.readouts();
    expect(r.equal).toBe(true);
    expect(r.checkpoint).toBeGreaterThanOrEqual(420);
    expect(Math.max(r.machines[0].maxDepth, r.machines[1].maxDepth)).toBeGreaterThanOrEqual(15);
    lab.dispose();
  });

  it('repeats exactly', () => {
    const run = () => {
      const lab = new RigidLab(rapier);
      lab.advanceTo(3000);
      lab.setLink({ latencyMs: 150 });
      lab.advanceTo(5000);
      const r = lab.net.readouts();
      lab.dispose();
      return r;
    };
    expect(run()).toEqual(run());
  });
});

/** Rapier's side of the two worlds after 300 ticks: fallen, most of its boxes turned. */
function expectToppled(side: WorldReadouts): void {
  expect(side.tick).toBe(300);
  expect(side.turned).toBeGreaterThanOrEqual(8);
  expect(side.top).toBeLessThan(2);
}

describe('the two worlds', () => {
  it('the knocked tower: Rapier’s boxes turn and fall, the own world’s slide without turning', () => {
    const lab = new RigidLab(rapier);
    lab.advanceTo(5005);
    const [rapierSide, own] = lab.worlds.readouts();
    expectToppled(rapierSide);
    expect(own.tick).toBe(300);
    expect(own.turned).toBe(0);
    expect(own.maxTurnDeg).toBe(0);
    expect(own.top).toBeGreaterThan(rapierSide.top + 1);
    // A snapshot of the same 17 bodies: Rapier's is more than ten times the own world's.
    expect(rapierSide.bodies).toBe(17);
    expect(own.bodies).toBe(17);
    expect(rapierSide.bytesPerBody).toBeGreaterThan(10 * own.bytesPerBody);
    expect(worldNote(own, false)).toBe(`no box can turn · top ${own.top.toFixed(2)} m`);
    lab.dispose();
  });

  it('the leaning tower: Rapier’s topples, the own world’s stays up where it was', () => {
    const lab = new RigidLab(rapier);
    lab.advanceTo(1000);
    lab.setWorldsScene('lean');
    expect(lab.worlds.tick).toBe(0);
    lab.advanceTo(6005);
    const [rapierSide, own] = lab.worlds.readouts();
    expectToppled(rapierSide);
    // 11 boxes, 5.5 m: it only sags, about one 5 mm slop per contact (docs/physics-world.md).
    expect(own.turned).toBe(0);
    expect(5.5 - own.top).toBeGreaterThan(0.04);
    expect(5.5 - own.top).toBeLessThan(0.07);
    for (let k = 0; k < 11; k++) expect(lab.worlds.own.x[k]).toBe(0.5 * k);
    expect(worldNote(rapierSide, true)).toBe(
      `${rapierSide.turned} of 11 boxes turned past 10° · top ${rapierSide.top.toFixed(2)} m`,
    );
    lab.dispose();
  });
});

describe('drawing between ticks', () => {
  it('blends positions linearly and angles the shorter way round', () => {
    const track = new BodyTrack([{ kind: 'box', halfWidth: 0.5, halfHeight: 0.5, owner: -1 }]);
    track.record(() => [0, 0, 3.1]);
    track.record(() => [1, 2, -3.1]);
    const p = track.poses(0.5);
    expect([p[0], p[1]]).toEqual([0.5, 1]);
    // From 3.1 to −3.1 through π (0.083 rad), not back through 0 (6.2 rad).
    expect(Math.abs(Math.abs(p[2]!) - Math.PI)).toBeLessThan(1e-9);
  });

  it('counts a box turned past 10° and finds the highest corner', () => {
    const shapes = [{ kind: 'box', halfWidth: 0.5, halfHeight: 0.25, owner: -1 }] as const;
    expect(towerShape(shapes, () => [0, 1, 0])).toEqual({
      boxes: 1,
      turned: 0,
      maxTurnDeg: 0,
      top: 1.25,
    });
    const quarter = towerShape(shapes, () => [0, 1, Math.PI / 2]);
    expect(quarter.turned).toBe(1);
    expect(quarter.top).toBeCloseTo(1.5, 12);
    expect(towerShape(shapes, () => [0, 1, TURNED_RAD * 0.99]).turned).toBe(0);
  });
});

describe('the words', () => {
  it('quotes docs/rapier.md’s measured numbers exactly', () => {
    const doc = readFileSync(new URL('../../../docs/rapier.md', import.meta.url), 'utf8');
    const g = (n: number) => n.toLocaleString('en-US').replace(/,/g, ' ');
    expect(doc).toContain(
      `| ${MEASURED.n} | fixedstep PhysicsWorld | ${g(MEASURED.ownBytesPerBody)} |`,
    );
    expect(doc).toContain(
      `| ${MEASURED.n} | Rapier (deterministic) | ${g(MEASURED.rapierBytesPerBody)} |`,
    );
    expect(doc).toContain(
      `fixedstep's own world ≈ ${g(MEASURED.ownRollbackBodies)} bodies, Rapier ≈ ${g(MEASURED.rapierRollbackBodies)}`,
    );
    expect(doc).toContain(MEASURED.command);
    expect(doc).toContain('apps/lab/src/chapters/rigid-bodies');
  });

  it('the cost sentence reads this scene’s snapshots from the model', () => {
    const lab = new RigidLab(rapier);
    lab.advanceTo(1000);
    const [rapierSide, own] = lab.worlds.readouts();
    const text = costText(rapierSide, own);
    expect(text).toContain(
      `Rapier ${rapierSide.snapshotBytes.toLocaleString('en-US').replace(/,/g, '\u202f')} bytes`,
    );
    expect(text).toContain('1\u202f579 bytes a body against 97 at 100 bodies');
    expect(text).toContain('about 180 bodies in Rapier against about 2\u202f468');
    lab.dispose();
  });

  it('the live note and the verdicts before anything happened', async () => {
    const lab = await openRigidLab();
    expect(knockNote(lab.knock.readouts())).toBe('Waiting for Fire.');
    expect(replayVerdict(undefined)).toBe(
      'Press “Replay” to play the recording so far back by re-simulation.',
    );
    expect(netVerdict(lab.net.readouts())).toBe('Connecting and syncing clocks…');
    lab.dispose();
  });
});
