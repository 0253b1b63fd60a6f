/**
 * The one error every wire protocol's decoder throws.
 * @module
 */
import type { ByteReadProblem } from '../../det/bytes.js';

/**
 * What is wrong with received bytes:
 * - `'TOO_LARGE'` — the message, or a count or length inside it, is above a limit;
 * - `'TRUNCATED'` — the bytes end inside a field;
 * - `'BAD_VERSION'` — another version of the protocol, or another protocol altogether;
 * - `'BAD_TYPE'` — an unknown message type, or one the sender may not send;
 * - `'BAD_VALUE'` — a field breaks a rule (a non-canonical varint, bad UTF-8, a name with other
 *   characters, a count that does not add up, a non-finite time …);
 * - `'TRAILING_BYTES'` — bytes left over after the last field.
 */
export type ProtocolErrorCode =
  'TOO_LARGE' | 'TRUNCATED' | 'BAD_VERSION' | 'BAD_TYPE' | 'BAD_VALUE' | 'TRAILING_BYTES';

/** Where a {@link ProtocolError} was found. */
export interface ProtocolErrorPlace {
  /** The protocol, e.g. `relay`, `state sync`, `signalling`, `quick match`. */
  protocol?: string;
  /** The message type, once known, e.g. `hello`. */
  messageType?: string;
  /** The field, e.g. `room`, `groups[1].peers`. */
  field?: string;
  /** Byte offset in the message (-1 when not about one place). */
  offset?: number;
}

/**
 * The only error a protocol's `decode` throws, whatever the bytes: it names the protocol, the
 * message type and the field, e.g. `relay hello.room: must be 1–32 of A–Z a–z 0–9 _ - . (at byte 4)`.
 */
export class ProtocolError extends Error {
  readonly code: ProtocolErrorCode;
  /** Byte offset where the problem was found (-1 when not about one place). */
  readonly offset: number;
  /** The protocol (`relay`, `state sync`, `signalling`, `quick match`), or `''`. */
  readonly protocol: string;
  /** The message type, or `''` when the problem is in the header. */
  readonly messageType: string;
  /** The field, or `''` when the problem is not in one field. */
  readonly field: string;
  constructor(code: ProtocolErrorCode, message: string, place: ProtocolErrorPlace = {}) {
    const offset = place.offset ?? -1;
    const where = [place.protocol, [place.messageType, place.field].filter(Boolean).join('.')]
      .filter(Boolean)
      .join(' ');
    super(
      `${code}: ${where ? `${where}: ` : ''}${message}${offset >= 0 ? ` (at byte ${offset})` : ''}`,
    );
    this.name = 'ProtocolError';
    this.code = code;
    this.offset = offset;
    this.protocol = place.protocol ?? '';
    this.messageType = place.messageType ?? '';
    this.field = place.field ?? '';
  }
}

/** A {@link ByteReadProblem} as a {@link ProtocolErrorCode}. */
export const PROBLEM_CODES: Readonly<Record<ByteReadProblem, ProtocolErrorCode>> = {
  truncated: 'TRUNCATED',
  invalid: 'BAD_VALUE',
  'too-large': 'TOO_LARGE',
  trailing: 'TRAILING_BYTES',
};
