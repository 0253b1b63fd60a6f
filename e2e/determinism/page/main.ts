/**
 * The determinism page: computes the trace catalogue in this browser's JavaScript engine when the
 * test asks (`window.fixedstepDeterminism.run()`), with the very code Node runs.
 */
import { determinismScenes } from '../scenes.js';
import { runScenes, stateHex, type DeterminismPageApi } from '../run.js';

declare global {
  interface Window {
    fixedstepDeterminism?: DeterminismPageApi;
  }
}

const scenes = await determinismScenes();
const status = document.getElementById('status');

window.fixedstepDeterminism = {
  ready: true,
  ids: () => scenes.map((s) => s.id),
  run(ids) {
    const out = runScenes(scenes, ids);
    if (status)
      status.textContent = `traced ${String(out.scenes.length)} scenes in ${out.ms.toFixed(0)} ms`;
    return JSON.stringify(out);
  },
  state: (id, tick) => stateHex(scenes, id, tick),
};
if (status) status.textContent = `ready: ${String(scenes.length)} scenes`;
