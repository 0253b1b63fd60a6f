/**
 * Determinism's tools: a seeded random generator, FNV-1a 64-bit hashes, canonical byte readers
 * and writers (varints, bounded counts), deterministic math (`dsin`, `dcos`, `datan2`, `dexp`,
 * `dhypot` … the same bits in every JS engine), and the guard that forbids clocks and
 * `Math.random` inside a step.
 * @module
 */
export { Random } from './random.js';
export { Fnv1a64, fnv1a64, fnv1a64Hex, hex64 } from './hash.js';
export {
  ByteWriter,
  ByteReader,
  readVarint,
  varintProblem,
  varintSize,
  VARINT_TRUNCATED,
  VARINT_TOO_LARGE,
  VARINT_NOT_CANONICAL,
} from './bytes.js';
export type { ByteReaderOptions, ByteReadFailure, ByteReadProblem } from './bytes.js';
export {
  dsin,
  dcos,
  dsincos,
  dtan,
  datan,
  datan2,
  dasin,
  dacos,
  dexp,
  dlog,
  dhypot,
  wrapAngle,
} from './math.js';
export type { WritableNumbers } from './math.js';
export { withDeterminismGuard, isGuardActive, DeterminismError } from './guard.js';
export { FORBIDDEN_FUNCTIONS } from './forbidden.js';
export type { ForbiddenFunction, ForbiddenKind } from './forbidden.js';
