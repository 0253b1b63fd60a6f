/**
 * What chapter 10 says: the lede, each section's intro, the verdicts (built from the model's
 * readouts), what the own world cannot, what Rapier costs (the measured numbers of docs/rapier.md,
 * with the command that gives them), and how the page works.
 */
import { h } from '../../ui/dom.js';
import { textSection } from '../../ui/prose.js';
import * as fmt from '../../ui/format.js';
import type {
  KnockReadouts,
  NetReadouts,
  ReplayReadouts,
  WorldReadouts,
  WorldsScene,
} from './rigid-bodies-lab.js';

export const LEDE =
  'The own physics world’s boxes never turn — by design. When a game needs boxes that tip over, Rapier’s deterministic build runs under fixedstep like any other simulation: the same fixed step, the same replays, the same rollback, the same hashes on every machine.';

export const KNOCK_INTRO =
  'Sixteen boxes that rotate, stepped by Rapier at 60 ticks a second. Fire — the button, the F key, or a tap on the tower — launches the ball at it; a box turns pink once it has turned more than 10° (a box rolled onto its side counts). The run is recorded as it goes: its inputs, and a state hash every second. Replay plays that recording back by re-simulation in a new Rapier world, and compares its hash after every tick with the hash the live tower had at that tick.';

export const LIVE_HEAD = 'Rapier’s tower, stepped by a FixedLoop; each press lands on one tick.';

export const REPLAY_HEAD = 'The recording so far, re-simulated from its inputs in a fresh world.';

export const NET_INTRO =
  'Two machines play the same tower through the relay, each with a rollback session over its own simulated link. Player 1 fires the blue ball from the left, player 2 the violet one from the right — the bots every 4 s, taking turns, and you with the buttons. A machine hears of the other’s shot late, after it has simulated past that tick: it loads its saved state of the tick and steps Rapier again up to now. That is a rollback.';

/** The one sentence of "What the own world cannot". */
export const CANNOT =
  'fixedstep’s own world cannot do this: its boxes are axis-aligned and never rotate, by design (the talk’s arcade world) — a knocked tower slides apart without one box turning, and a leaning tower whose centre of mass is 2 m past its base stays up.';

export const WORLDS_INTRO: Readonly<Record<WorldsScene, string>> = {
  knock:
    'The live tower’s scene in both worlds: the same boxes, ground and ball, the ball launched at 0.5 s with the same speed.',
  lean: 'Eleven boxes of 1 m × 0.5 m, each 0.5 m to the right of the one below (docs/physics-world.md’s leaning tower): the centre of mass is 2 m past the right edge of the base.',
};

export const WORLDS_TITLES: Readonly<Record<WorldsScene, string>> = {
  knock: 'Knocked tower',
  lean: 'Leaning tower',
};

/**
 * What docs/rapier.md measured (its tables), quoted with where they come from; the test keeps them
 * equal to the document's.
 */
export const MEASURED = {
  doc: 'docs/rapier.md',
  command: 'npm run bench -- rollback-budget',
  /** Bodies of the pile the bytes were measured on. */
  n: 100,
  ownBytesPerBody: 97,
  rapierBytesPerBody: 1579,
  /** The largest pile whose 8-tick rollback fit in 4 ms. */
  ownRollbackBodies: 2468,
  rapierRollbackBodies: 180,
} as const;

/** "What it costs": this scene's snapshots now (from the model), then the measured budget. */
export function costText(rapier: WorldReadouts, own: WorldReadouts): string {
  const m = MEASURED;
  return (
    `What rotation costs. A snapshot of this scene, now: Rapier ${fmt.count(rapier.snapshotBytes)} bytes ` +
    `(${fmt.count(rapier.bytesPerBody)} a body), the own world ${fmt.count(own.snapshotBytes)} bytes ` +
    `(${fmt.count(own.bytesPerBody)} a body). Rollback saves one every tick and loads one per correction. ` +
    `Measured in ${m.doc} (${m.command}: a pile of circles in a box, on a shared 2-CPU machine): ` +
    `${fmt.count(m.rapierBytesPerBody)} bytes a body against ${fmt.count(m.ownBytesPerBody)} at ${m.n} bodies, ` +
    `and the largest pile whose 8-tick rollback fits in 4 ms was about ${fmt.count(m.rapierRollbackBodies)} bodies ` +
    `in Rapier against about ${fmt.count(m.ownRollbackBodies)} in the own world. ` +
    'Use Rapier when the game needs rotation, polygons or joints, and keep what a rollback re-simulates small.'
  );
}

/** The live panel's line under its canvas. */
export function knockNote(r: KnockReadouts): string {
  if (r.shots === 0) return 'Waiting for Fire.';
  return `${fmt.plural(r.shots, 'shot')} · ${r.turned} of ${r.boxes} boxes turned past 10° · top ${r.top.toFixed(2)} m`;
}

/** The replay's verdict. */
export function replayVerdict(r: ReplayReadouts | undefined): string {
  if (r === undefined) return 'Press “Replay” to play the recording so far back by re-simulation.';
  if (r.different > 0) {
    return `The replay differs from the live run: first at tick ${r.firstDifferent} (${fmt.count(r.different)} of ${fmt.count(r.compared)} ticks).`;
  }
  if (r.mismatches > 0) return 'The re-simulation did not reproduce a checkpoint hash of the file.';
  if (r.ended) {
    return `Replayed all ${fmt.count(r.ticks)} ticks: every tick’s hash equal to the live run’s (${fmt.count(r.compared)} compared, tick 0 included), and ${fmt.plural(r.checkpoints, 'checkpoint hash', 'checkpoint hashes')} of the file reproduced.`;
  }
  return `Tick ${fmt.count(r.tick)} of ${fmt.count(r.ticks)}: ${fmt.count(r.compared)} ticks compared so far, each equal to the live run’s.`;
}

/** The network's verdict. */
export function netVerdict(r: NetReadouts): string {
  if (r.checkpoint < 0) return 'Connecting and syncing clocks…';
  const rollbacks = r.machines[0].rollbacks + r.machines[1].rollbacks;
  const depth = Math.max(r.machines[0].maxDepth, r.machines[1].maxDepth);
  if (r.equal) {
    return `Both machines computed the same world at tick ${fmt.count(r.checkpoint)}, after ${fmt.plural(rollbacks, 'rollback')} (the deepest ${fmt.plural(depth, 'tick')}).`;
  }
  if (r.desyncs > 0) return 'The relay saw the machines disagree: a desync.';
  return 'Waiting for both machines to confirm the checkpoint…';
}

/** A side's line under its canvas in the side-by-side. */
export function worldNote(r: WorldReadouts, rotates: boolean): string {
  const turned = rotates ? `${r.turned} of ${r.boxes} boxes turned past 10°` : 'no box can turn';
  return `${turned} · top ${r.top.toFixed(2)} m`;
}

/** "How this page works". */
export function howItWorks(): HTMLElement {
  const li = (...parts: (string | HTMLElement)[]) => h('li', {}, ...parts);
  const c = (text: string) => h('code', {}, text);
  return textSection(
    'how',
    'rigid-how-title',
    'How this page works',
    h(
      'ul',
      {},
      li(
        'The tower is ',
        c('towerScene()'),
        ' of ',
        c('@fixedstep/rapier'),
        ' — the scene the four-engine determinism suite checks — as a ',
        c('RapierSimulation'),
        ', stepped by a ',
        c('FixedLoop'),
        ' on a simulated 60 Hz display (or your display’s frames, with Real clock). Fire goes through the library’s input pipeline: ',
        c('attachButtons'),
        ' and ',
        c('attachKeyboard'),
        ' push each press into an ',
        c('InputSampler'),
        ' with its time, so it lands on exactly one tick. An ',
        c('InterpolationBuffer'),
        ' with an angle field draws every body between its last two ticks, positions and angles.',
      ),
      li(
        'The recording is ',
        c('ReplayRecorder.forGame(rapierGame(…))'),
        ': the inputs and a hash every 60 ticks, no state. The replay is a ',
        c('ReplayPlayer'),
        ' that builds a fresh Rapier world and re-simulates; every tick’s ',
        c('hash()'),
        ' (FNV-1a 64 of every body’s pose and velocities) is compared with the live run’s.',
      ),
      li(
        'The network is the relay core and two ',
        c('RollbackSession'),
        's on ',
        c('SimulatedLink'),
        's (seeded delays and losses) on a virtual clock. A session saves Rapier’s snapshot every tick and loads one per rollback; the hashes compared are FNV-1a 64 of ',
        c('save()'),
        ' at the newest confirmed checkpoint — Rapier’s snapshot included.',
      ),
      li(
        'The side-by-side builds the same sizes in fixedstep’s ',
        c('PhysicsWorld'),
        ', which has no angle to turn (docs/physics-world.md, “Limits, measured”).',
      ),
      li(
        'Rapier’s WebAssembly is about 2 MB of JavaScript, bundled into this chapter’s own chunk (no network request) and loaded only when the chapter opens; no other chapter carries it.',
      ),
    ),
  );
}
