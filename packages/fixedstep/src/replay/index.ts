/**
 * Replays from inputs and seeds alone: a versioned, checksummed, seekable binary format
 * (docs/replay-format.md), a recorder, a reader with strict validation and limits, a player
 * (play, pause, speed, seek, step back) and a verifier.
 * @module
 */
export { ReplayError, isReplayError } from './errors.js';
export type { ReplayErrorCode } from './errors.js';
export {
  Replay,
  ReplayInputCursor,
  readReplay,
  replayTimestep,
  DEFAULT_REPLAY_LIMITS,
} from './format.js';
export type {
  ReplayHeader,
  ReplayLimits,
  ReadReplayOptions,
  ReplaySectionInfo,
  ReplayKeyframe,
} from './format.js';
export { ReplayRecorder } from './recorder.js';
export type { ReplayRecorderOptions, RecordableSimulation } from './recorder.js';
export { ReplayPlayer } from './player.js';
export type { ReplayFactory, ReplayMismatch, ReplayPlayerOptions } from './player.js';
export { verifyReplay } from './verify.js';
export { replayFactory, setupFromReplayHeader } from './games.js';
export type { ReplaySource } from './games.js';
export type { VerifyReplayOptions, VerifyResult } from './verify.js';
