/**
 * The Rapier scenes of the determinism suite (`@fixedstep/rapier`): kept out of
 * `@fixedstep/games`'s catalogue so a games user never loads Rapier's WebAssembly. Node and the
 * browser page both call {@link rapierScenes} (which loads the WebAssembly from the bundle first),
 * so every engine runs the very same code and the very same WebAssembly.
 *
 * A trace is the FNV-1a 64 of the canonical state (`RapierSimulation.canonicalState()`: every
 * body's handle, pose and velocities) after every tick, so a difference names the body and the
 * value (`body[12].angle`). The `/reloaded` scene also moves the world through Rapier's own
 * snapshots (`save()` → `load()` into a fresh simulation), and the display-rate scenes drive it
 * through `FixedLoop` from timestamped presses.
 */
import { circlesInBoxScene, packButtons, Timestep } from 'fixedstep';
import {
  TRACE_DISPLAY_RATES,
  displayRun,
  inputsToScript,
  rateLabel,
  traceDisplay,
  type StateField,
  type TraceRun,
  type TraceScene,
} from '@fixedstep/games';
import {
  JointsButtons,
  RapierSimulation,
  TowerButtons,
  canonicalFields,
  jointsScene,
  loadRapier,
  physicsSceneDef,
  towerScene,
  type RapierSceneDef,
  type Tower,
} from '@fixedstep/rapier';

/** Ticks of each Rapier scene. */
export const RAPIER_TRACE_TICKS = 600;
/** Ticks of the piles (fewer: they cost the most). */
const PILE_TICKS = 400;
/** Moves the `/reloaded` scene into a fresh simulation every this many ticks. */
const RELOAD_EVERY = 100;

const FIRE = packButtons(1 << TowerButtons.FIRE, 1 << TowerButtons.FIRE);

/** The tower's inputs: FIRE at ticks 30, 200 and 400 (held 4 ticks each, like a key). */
function towerInputs(ticks: number): Uint32Array {
  const out = new Uint32Array(ticks);
  for (const at of [30, 200, 400]) {
    for (let t = at; t < Math.min(ticks, at + 4); t++)
      out[t] = packButtons(1 << TowerButtons.FIRE, 0);
    if (at < ticks) out[at] = FIRE;
  }
  return out;
}

/** The joints' inputs: the slider right for a second, then left for a second, and so on. */
function jointsInputs(ticks: number): Uint32Array {
  return Uint32Array.from({ length: ticks }, (_, t) =>
    packButtons(1 << (Math.floor(t / 60) % 2 === 0 ? JointsButtons.RIGHT : JointsButtons.LEFT), 0),
  );
}

const fields = (state: Uint8Array): readonly StateField[] | undefined => canonicalFields(state);

/**
 * A run of `def`: steps with `input(tick)`, returns the canonical state, and frees Rapier's memory
 * after the scene's last tick (a trace calls `next()` exactly `ticks` times). `tamper` (tests
 * only) may change the world after a step, as an engine that computed differently would.
 */
function steppedRun<S>(
  def: RapierSceneDef<number, S>,
  ticks: number,
  input: (t: number) => number,
  tamper?: (sim: RapierSimulation<number, S>) => void,
): TraceRun {
  const sim = new RapierSimulation(def);
  const row = [0];
  return {
    next(): Uint8Array {
      row[0] = input(sim.tick);
      sim.step(row);
      tamper?.(sim);
      const state = sim.canonicalState();
      if (sim.tick >= ticks) sim.dispose();
      return state;
    },
  };
}

/** A Rapier scene of the catalogue: `def()` stepped with `inputs`, traced on its canonical state. */
export function rapierTraceScene<S>(
  id: string,
  title: string,
  ticks: number,
  def: () => RapierSceneDef<number, S>,
  inputs: Uint32Array,
  tamper?: (sim: RapierSimulation<number, S>) => void,
): TraceScene {
  return {
    id,
    title,
    ticks,
    start: () => steppedRun(def(), ticks, (t) => inputs[t] ?? 0, tamper),
    fields,
  };
}

/** The tower scene of the catalogue (see {@link rapierTraceScene} for `tamper`). */
export function towerTraceScene(
  ticks = RAPIER_TRACE_TICKS,
  tamper?: (sim: RapierSimulation<number, Tower>) => void,
): TraceScene {
  return rapierTraceScene(
    'rapier/tower',
    'Rapier: a tower of 16 rotating boxes knocked over by a ball fired 3 times',
    ticks,
    () => towerScene(),
    towerInputs(ticks),
    tamper,
  );
}

/**
 * The Rapier scenes, after loading Rapier's WebAssembly: the tower knocked over (plus its snapshot
 * round trips and every display rate), the joints, and 250 rotating circles in a box.
 */
export async function rapierScenes(ticks = RAPIER_TRACE_TICKS): Promise<TraceScene[]> {
  await loadRapier();
  const tower = towerInputs(ticks);
  const reloaded: TraceScene = {
    id: 'rapier/tower/reloaded',
    title: `Rapier: the tower, moved every ${RELOAD_EVERY} ticks into a fresh simulation by save() → load() (Rapier’s snapshots)`,
    ticks,
    sameAs: 'rapier/tower',
    start(): TraceRun {
      let sim = new RapierSimulation(towerScene());
      const row = [0];
      return {
        next(): Uint8Array {
          row[0] = tower[sim.tick] ?? 0;
          sim.step(row);
          if (sim.tick % RELOAD_EVERY === 0) {
            const bytes = sim.save();
            sim.dispose();
            sim = new RapierSimulation(towerScene());
            sim.load(bytes);
          }
          const state = sim.canonicalState();
          if (sim.tick >= ticks) sim.dispose();
          return state;
        },
      };
    },
    fields,
  };
  const stepMs = 1000 / 60;
  const script = inputsToScript(tower, stepMs);
  const displays = TRACE_DISPLAY_RATES.map((hz): TraceScene => ({
    id: `rapier/tower@${rateLabel(hz)}`,
    title: `Rapier: the tower through FixedLoop on a jittery, hitching ${String(hz)} Hz display, FIRE as timestamped presses`,
    ticks,
    sameAs: 'rapier/tower',
    start(): TraceRun {
      const sim = new RapierSimulation(towerScene());
      return displayRun({
        step: Timestep.fromHz(60),
        display: traceDisplay(hz),
        scripts: [script],
        // A copy: the loop may run several ticks in a frame before the trace reads them. The
        // simulation is not disposed here (the last frame may run past `ticks`): Rapier's
        // finalizers free it once it is garbage.
        advance(inputs) {
          sim.step(inputs);
          return sim.canonicalState().slice();
        },
      });
    },
    fields,
  }));
  // A pile of 150 (not the own world's 250): Rapier's scenes cost ~10 s per engine as it is.
  const circles = circlesInBoxScene(150, 7);
  const pileTicks = Math.min(ticks, PILE_TICKS);
  return [
    towerTraceScene(ticks),
    reloaded,
    ...displays,
    rapierTraceScene(
      'rapier/joints',
      'Rapier: a 10-link chain on revolute joints, a motorised prismatic slider, a wheel on a motor spring',
      ticks,
      () => jointsScene(10),
      jointsInputs(ticks),
    ),
    rapierTraceScene(
      'rapier/circles-150',
      `Rapier: circlesInBoxScene(150, 7) for ${String(pileTicks)} ticks, rotation unlocked, no sleeping`,
      pileTicks,
      () => physicsSceneDef(circles, { id: 'rapier-circles-150' }),
      new Uint32Array(pileTicks),
    ),
    rapierTraceScene(
      'rapier/boxes-150',
      `Rapier: the same 150 bodies as rotating boxes for ${String(pileTicks)} ticks, sleeping allowed`,
      pileTicks,
      () => physicsSceneDef(circles, { id: 'rapier-boxes-150', boxes: true, sleep: true }),
      new Uint32Array(pileTicks),
    ),
  ];
}
