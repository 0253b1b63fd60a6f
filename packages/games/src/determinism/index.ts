/**
 * The trace catalogue: per-tick state hashes of every scene and game, computed by the same code in
 * Node and in every browser, to prove that the simulation behaves the same everywhere and at every
 * display rate. See docs/determinism.md.
 * @module
 */
export { traceCatalogue, TRACE_TICKS } from './catalogue.js';
export type { TraceCatalogueOptions } from './catalogue.js';
export {
  traceScene,
  sceneStateAt,
  traceLength,
  traceHashAt,
  firstDifferentTick,
  bytesToHex,
  hexToBytes,
  TRACE_HASH_DIGITS,
} from './trace.js';
export type { TraceScene, TraceRun } from './trace.js';
export {
  StateLayout,
  stateFieldAt,
  stateFieldSize,
  readStateField,
  hexFloat,
  formatStateValue,
  diffStates,
} from './state-fields.js';
export type { StateField, StateFieldType, StateDiff } from './state-fields.js';
export {
  physicsWorldFields,
  filtersSensorsFields,
  springSystemFields,
  ballFields,
  gameFields,
} from './layouts.js';
export type { DescribesState } from './layouts.js';
export {
  TRACE_DISPLAY_RATES,
  TRACE_DISPLAY_JITTER,
  TRACE_DISPLAY_HITCHES,
  TRACE_MAX_ACCUMULATOR_MS,
  traceDisplay,
  displayRun,
  inputsToScript,
  sampledInputs,
  timestepOf,
  rateLabel,
} from './display.js';
export type { TraceButtonEvent, DisplayRunOptions } from './display.js';
export {
  functionProbeScene,
  randomDouble,
  angleInput,
  unaryProbe,
  binaryProbe,
  SPECIAL_DOUBLES,
  DET_MATH_PROBES,
  detMathScene,
} from './probes.js';
export type { FunctionProbe, FunctionProbeSceneOptions } from './probes.js';
export {
  randomScene,
  ballTraceScript,
  ballScenes,
  circlesScene,
  bulletsScenes,
  filtersSensorsWorld,
  filtersSensorsScene,
  materialsWorld,
  materialsScene,
  ropeDef,
  ropeScenes,
} from './scenes.js';
export { gameScenes, recordBotMatch, tracePlayers, TRACE_GAME_SEED } from './games.js';
export type { BotRecording } from './games.js';
