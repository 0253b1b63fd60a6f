/**
 * The wire layer: each protocol's messages declared once, as data, and the encoder, decoder, size
 * limits and fuzz samples that follow from the declaration; one error type; one list of refusal
 * codes. See `protocol.ts`.
 * @module
 */
export { ProtocolError } from './error.js';
export type { ProtocolErrorCode, ProtocolErrorPlace } from './error.js';
export { WireProtocol, defineProtocol } from './protocol.js';
export type {
  DecodeOptions,
  Sender,
  MessageSpec,
  ProtocolSpec,
  MessageDescription,
} from './protocol.js';
export { protocolTable } from './table.js';
export { NAME_PATTERN } from './fields.js';
export type { Field, Fields, Limits, Bound } from './fields.js';
export {
  NET_ERROR_CODES,
  TOKEN_BYTES,
  MAX_PLAYER_NAME_BYTES,
  MAX_ERROR_TEXT_BYTES,
  MAX_TICKET_BYTES,
  LEAVE_REASONS,
  refusalCode,
} from './common.js';
export type {
  NetErrorCode,
  LeaveReason,
  ErrorMessage,
  PingMessage,
  PongMessage,
  JoinFields,
} from './common.js';
