/**
 * @fixedstep/games — the talk's demo scenes and games, each a deterministic simulation.
 * @packageDocumentation
 * @module @fixedstep/games
 */
export { BallScene, BallButtons, defaultBallConfig } from './scenes/ball.js';
export type { BallConfig } from './scenes/ball.js';
export { LoopRig, makeLoop, defaultBallScript } from './scenes/loop-rig.js';
export type { LoopRigOptions, LoopSpec, ScriptedInput } from './scenes/loop-rig.js';
export { measureTunnelling } from './scenes/tunnel.js';
export type { TunnelSetting, TunnelResult } from './scenes/tunnel.js';
export type { Game, GameInfo, GameConfig, RegisteredGame, Bot } from './games/game.js';
export { encodeGameConfig, decodeGameConfig } from './games/config.js';
export { GAMES, findGame } from './games/registry.js';
export { replayOptionsFor, gameFromReplayHeader } from './games/replay.js';
export * from './games/runner/index.js';
export {
  WallRange,
  WallRangeRig,
  ShotStatus,
  RANGE_HALF_WIDTH,
  RANGE_HALF_HEIGHT,
  wallRangeConfig,
  wallRule,
} from './scenes/collisions.js';
export type {
  WallRangeOptions,
  WallRangeConfig,
  WallRangeRigOptions,
  WallRule,
  RangeLoopKind,
} from './scenes/collisions.js';
export {
  OscillatorRace,
  TALK_INTEGRATOR_EXPERIMENT,
  TalkSpring,
  isStable,
  runIntegratorExperiment,
} from './scenes/physics.js';
export type {
  OscillatorRaceOptions,
  RaceLane,
  IntegratorExperimentOptions,
  IntegratorResult,
  IntegratorExperiment,
} from './scenes/physics.js';
export {
  Rope,
  ropeConfig,
  ropeSystemDef,
  ropeOmegaMax,
  ropeRestPositions,
} from './scenes/springs.js';
export type { RopeOptions, RopeConfig, RopePoke } from './scenes/springs.js';
export { SceneRig } from './scenes/movement-rig.js';
export type { SteppedScene, SceneRigOptions } from './scenes/movement-rig.js';
export {
  JumperScene,
  JumperButtons,
  JumpMeter,
  defaultJumperConfig,
  MOVEMENT_PERIOD_MS,
  movementRound,
  movementScript,
  runMovement,
  jitterSeed,
  loopKindOf,
} from './scenes/movement.js';
export type {
  JumperConfig,
  Jump,
  MovementLoop,
  MovementRunOptions,
  MovementRun,
} from './scenes/movement.js';
export {
  debugSceneConfig,
  demoRecording,
  recordingLength,
  InputRecorder,
  TickHashes,
  runRecording,
} from './scenes/debugging.js';
export type { RecordingRunOptions, RecordingRun } from './scenes/debugging.js';
export {
  FINAL_STEP_MS,
  STALL_WORK_MS,
  spiralLoopSpec,
  backwardsLoopSpec,
  repeatedBallScript,
  jumpingClock,
  spiralRig,
  backwardsRig,
} from './scenes/final-fixes.js';
export type {
  SpiralLoop,
  BackwardsLoop,
  SpiralOptions,
  BackwardsOptions,
} from './scenes/final-fixes.js';
export * from './games/arena/index.js';
export * from './games/ctf/index.js';
export * from './games/survival/index.js';
export * from './determinism/index.js';
export {
  JostleScene,
  JOSTLE_SCHEMA,
  JOSTLE_SIZE,
  JOSTLE_MAX_SPEED,
  jostleGame,
} from './scenes/jostle.js';
export {
  StirredPile,
  STIRRED_PILE_SCHEMA,
  STIRRED_PILE_POSITIONS_SCHEMA,
  stirredPileGame,
} from './scenes/stirred-pile.js';
export {
  Gallery,
  GALLERY_INPUT,
  GALLERY_SCHEMA,
  GALLERY_LANES,
  GALLERY_WIDTH,
  GALLERY_HIT_RADIUS,
  GALLERY_MAX_REWIND,
  galleryGame,
} from './scenes/gallery.js';
export type { GalleryShot } from './scenes/gallery.js';
export { runGalleryMatch } from './scenes/gallery-match.js';
export type { GalleryMatchOptions, GalleryMatchResult } from './scenes/gallery-match.js';
export {
  CoinHop,
  coinHopBot,
  COIN_HOP_JUMP,
  COIN_HOP_JUMP_SPEED,
  COIN_HOP_RUN_SPEED,
} from './scenes/coin-hop.js';
