/**
 * A wire protocol declared once, as data: its messages, each a type byte, who may send it and its
 * fields (see `fields.ts`). From the declaration come the encoder, the decoder (which throws only a
 * {@link ProtocolError} naming the protocol, message and field), every size limit, and random
 * valid messages for the fuzz test — the way GGRS declares its `MessageBody` once.
 *
 * Every message is `[header u8][type u8][fields…]`. The header's top three bits name the protocol
 * (relay 0x00, signalling 0x40, quick match 0x60, state sync 0x80) and the low five its version, so
 * a message of another protocol, or of an older client, is refused with a sentence that says so.
 * @module
 */
import { ByteWriter, varintSize } from '../../det/bytes.js';
import type { Random } from '../../det/random.js';
import { ProtocolError, type ProtocolErrorCode, type ProtocolErrorPlace } from './error.js';
import { Layout, WireReader, type Field, type Fields, type Limits } from './fields.js';

/** Who sends a message: a decoder reading one side's messages refuses the other side's. */
export type Sender = 'client' | 'server' | 'both';

/** One message of a protocol. */
export interface MessageSpec<T extends { type: string }> {
  /** The type byte (byte 1). */
  code: number;
  /** Who sends it. */
  from: Sender;
  /** Its fields in wire order (the object's key order), one per property of the message. */
  fields: { [K in Exclude<keyof T, 'type'>]-?: Field<T[K]> };
  /** Rules between fields: the field and why it is wrong, or undefined. Checked both ways. */
  check?: (m: T, limits: Limits) => readonly [string, string] | undefined;
}

/** One message as {@link WireProtocol.describe} tells it. */
export interface MessageDescription {
  type: string;
  code: number;
  from: Sender;
  /** Its fields in wire order: name and kind in words (`varint 0–maxPlayers`, `name` …). */
  fields: { name: string; kind: string }[];
  /** Fewest and most bytes, header included, under the limits described. */
  minBytes: number;
  maxBytes: number;
}

/** A protocol's declaration. */
export interface ProtocolSpec<M extends { type: string }, L extends object> {
  /** Its name in messages: `relay`, `state sync` … */
  name: string;
  /** Byte 0's top three bits: which protocol (0x00, 0x20 … 0xe0). */
  family: number;
  /** Byte 0's low five bits: its version, 1–31. */
  version: number;
  /** The default limits its fields' bounds name. */
  limits: Readonly<L>;
  /** Every message, by type. */
  messages: { [K in M['type']]: MessageSpec<Extract<M, { type: K }>> };
  /**
   * The type byte of a batch frame, if the protocol has them: `[header][batch]` and then, for
   * each message, its length as a varint and its bytes (header included) — several messages of
   * one side in one WebSocket frame (see {@link WireProtocol.frame}).
   */
  batch?: number;
}

interface Compiled {
  type: string;
  code: number;
  from: Sender;
  layout: Layout;
  check: ((m: never, limits: Limits) => readonly [string, string] | undefined) | undefined;
}

/** Names of the protocols declared so far, by family: a stray message is named in refusals. */
const FAMILIES = new Map<number, string>();

/** What {@link WireProtocol.decode} takes besides the bytes. */
export interface DecodeOptions<L> {
  /** The limits to hold the bytes to. Default: the protocol's. */
  limits?: Readonly<L>;
  /** Whose messages these are: a message the other side sends is refused (`BAD_TYPE`). */
  from?: 'client' | 'server';
}

/** A declared protocol: encode, decode, sizes, samples. See the module's comment. */
export class WireProtocol<M extends { type: string }, L extends object> {
  readonly name: string;
  readonly version: number;
  /** Byte 0 of every message. */
  readonly header: number;
  readonly limits: Readonly<L>;
  /** The type byte of a batch frame, or undefined (see {@link ProtocolSpec.batch}). */
  readonly batch: number | undefined;
  private readonly byCode: (Compiled | undefined)[] = [];
  private readonly byType = new Map<string, Compiled>();
  // Encoding is synchronous and never re-entered: one buffer serves every message, and a message
  // costs one allocation (the copy `finish()` returns).
  private readonly scratch = new ByteWriter(256);

  constructor(spec: ProtocolSpec<M, L>) {
    if (!(spec.family >= 0 && spec.family <= 0xe0 && (spec.family & 0x1f) === 0)) {
      throw new RangeError(`${spec.name}: family must be a multiple of 0x20`);
    }
    if (!(Number.isInteger(spec.version) && spec.version >= 1 && spec.version <= 31)) {
      throw new RangeError(`${spec.name}: version must be 1 to 31`);
    }
    this.name = spec.name;
    this.version = spec.version;
    this.header = spec.family | spec.version;
    this.limits = Object.freeze({ ...spec.limits });
    FAMILIES.set(spec.family, spec.name);
    this.batch = spec.batch;
    const messages = spec.messages as Record<string, MessageSpec<{ type: string }>>;
    for (const [type, m] of Object.entries(messages)) {
      if (this.byCode[m.code] !== undefined) {
        throw new RangeError(`${spec.name}: type byte ${m.code} used twice`);
      }
      const c: Compiled = {
        type,
        code: m.code,
        from: m.from,
        layout: new Layout(m.fields),
        check: m.check,
      };
      if (m.code === spec.batch)
        throw new RangeError(`${spec.name}: type byte ${m.code} is the batch's`);
      this.byCode[m.code] = c;
      this.byType.set(type, c);
    }
  }

  /**
   * One frame holding `messages` (each one's bytes, as {@link encode} made them): the message
   * itself when there is one, else a batch frame — one WebSocket frame instead of several, read
   * back with {@link split}. Throws when the protocol has no batch frame and there are several.
   */
  frame(messages: readonly Uint8Array[]): Uint8Array {
    if (messages.length === 1) return messages[0]!;
    if (this.batch === undefined) throw new RangeError(`${this.name}: no batch frames`);
    let size = 2;
    for (const b of messages) size += varintSize(b.length) + b.length;
    const out = new Uint8Array(size);
    out[0] = this.header;
    out[1] = this.batch;
    let at = 2;
    for (const b of messages) {
      for (let x = b.length; ; x >>>= 7) {
        if (x < 0x80) {
          out[at++] = x;
          break;
        }
        out[at++] = (x & 0x7f) | 0x80;
      }
      out.set(b, at);
      at += b.length;
    }
    return out;
  }

  /**
   * The messages of one frame: the frame itself, or a batch frame's messages (views into it, each
   * to {@link decode}). Throws a {@link ProtocolError} for a batch frame that is not a whole
   * number of non-empty messages; what the messages hold is left to `decode`.
   */
  split(frame: Uint8Array): Uint8Array[] {
    if (this.batch === undefined || frame.length < 2 || frame[1] !== this.batch) return [frame];
    this.checkHeader(frame[0]!);
    const r = new WireReader(frame, this.name, this.limits as Limits);
    r.messageType = 'batch';
    r.fieldName = 'messages';
    const out: Uint8Array[] = [];
    while (r.pos < frame.length) {
      const n = r.count('message length', frame.length, 2);
      r.need(n, 'message');
      out.push(frame.subarray(r.pos, r.pos + n));
      r.pos += n;
    }
    if (out.length < 2)
      throw this.error('BAD_VALUE', 'a batch of fewer than two messages', { messageType: 'batch' });
    return out;
  }

  /** Every message type. */
  get types(): M['type'][] {
    return [...this.byType.keys()] as M['type'][];
  }

  /** The type byte (byte 1) of messages of `type`. */
  code(type: M['type']): number {
    return this.compiled(type).code;
  }

  /** Who sends messages of `type`. */
  sender(type: M['type']): Sender {
    return this.compiled(type).from;
  }

  /** Every message as its declaration says, in type-byte order (docs are made from this). */
  describe(limits: Readonly<L> = this.limits): MessageDescription[] {
    return this.byCode
      .filter((c): c is Compiled => c !== undefined)
      .map((c) => ({
        type: c.type,
        code: c.code,
        from: c.from,
        fields: c.layout.entries
          .filter(([, f]) => !f.carried)
          .map(([name, f]) => ({ name, kind: f.kind })),
        minBytes: 2 + c.layout.minBytes,
        maxBytes: 2 + c.layout.maxBytes(limits as Limits),
      }));
  }

  /**
   * The bytes of `m`. Throws a RangeError naming the field for a message that breaks the
   * declaration (a value out of range, a name with other characters, a count above the default
   * limits): a bug in the sender, not bad data.
   */
  encode(m: M): Uint8Array {
    const c = this.compiled(m.type);
    const fields = m as unknown as Fields;
    const limits = this.limits as Limits;
    const w = this.scratch.reset();
    w.u8(this.header).u8(c.code);
    const problem = c.layout.encodeMessage(w, fields, limits) ?? c.check?.(m as never, limits);
    if (problem !== undefined) {
      throw new RangeError(`${this.name}: cannot encode ${m.type}.${problem[0]}: ${problem[1]}`);
    }
    return w.finish();
  }

  /**
   * Decodes one message. Throws a {@link ProtocolError} — and nothing else — for any bytes that
   * are not exactly one valid message within the limits; sizes and counts are checked before
   * anything is allocated. Byte fields of the result are copies.
   */
  decode(bytes: Uint8Array, options: DecodeOptions<L> = {}): M {
    const limits = (options.limits ?? this.limits) as Limits;
    // Every message of every match comes through here: the error's place is built only on error.
    try {
      if (!(bytes instanceof Uint8Array)) throw this.error('BAD_VALUE', 'not bytes');
      if (bytes.length < 2) throw this.error('TRUNCATED', 'shorter than a header', { offset: 0 });
      this.checkHeader(bytes[0]!);
      const c = this.byCode[bytes[1]!];
      if (c === undefined) {
        const what =
          bytes[1] === this.batch
            ? 'a batch frame: split it into its messages first'
            : `unknown message type 0x${bytes[1]!.toString(16)}`;
        throw this.error('BAD_TYPE', what, {
          offset: 1,
        });
      }
      if (options.from !== undefined && c.from !== 'both' && c.from !== options.from) {
        throw this.error(
          'BAD_TYPE',
          `a ${c.type} is sent by the ${c.from}, not the ${options.from}`,
          {
            messageType: c.type,
            offset: 1,
          },
        );
      }
      const max = 2 + c.layout.maxBytes(limits);
      if (bytes.length > max) {
        throw this.error(
          'TOO_LARGE',
          `${bytes.length} bytes; a ${c.type} message is at most ${max}`,
          {
            messageType: c.type,
          },
        );
      }
      const r = new WireReader(bytes, this.name, limits);
      r.messageType = c.type;
      const m = c.layout.readMessage(r, c.type);
      r.fieldName = '';
      r.end();
      if (c.check !== undefined) {
        const problem = c.check(m as never, limits);
        if (problem !== undefined) {
          throw this.error('BAD_VALUE', problem[1], { messageType: c.type, field: problem[0] });
        }
      }
      return m as unknown as M;
    } catch (error) {
      if (error instanceof ProtocolError) throw error;
      // A bug here must still surface as the one documented error type.
      throw this.error('BAD_VALUE', `undecodable: ${String(error)}`);
    }
  }

  /** A {@link ProtocolError} of this protocol at `place`. */
  private error(
    code: ProtocolErrorCode,
    message: string,
    place: Omit<ProtocolErrorPlace, 'protocol'> = {},
  ): ProtocolError {
    return new ProtocolError(code, message, { protocol: this.name, ...place });
  }

  /** The message type of `bytes` without decoding the rest (undefined: unknown, or not this protocol). */
  peek(bytes: Uint8Array): M['type'] | undefined {
    if (bytes.length < 2 || bytes[0] !== this.header) return undefined;
    return this.byCode[bytes[1]!]?.type;
  }

  /** Most bytes a message of `type` takes under `limits`. */
  maxBytes(type: M['type'], limits: Readonly<L> = this.limits): number {
    return 2 + this.compiled(type).layout.maxBytes(limits as Limits);
  }

  /** Most bytes any message `from` that side takes: what a socket needs to accept. */
  largest(from: 'client' | 'server', limits: Readonly<L> = this.limits): number {
    let n = 2;
    for (const c of this.byType.values()) {
      if (c.from === from || c.from === 'both') {
        n = Math.max(n, 2 + c.layout.maxBytes(limits as Limits));
      }
    }
    return n;
  }

  /** A random valid message of `type` (for fuzz tests): every field within `limits`. */
  sample(type: M['type'], rng: Random, limits: Readonly<L> = this.limits): M {
    const c = this.compiled(type);
    for (let attempt = 0; ; attempt++) {
      const l = limits as Limits;
      const m = c.layout.sample(rng, { type }, l);
      const problem = c.layout.problem(m, l) ?? c.check?.(m as never, l);
      if (problem === undefined) return m as unknown as M;
      if (attempt > 100) {
        throw new RangeError(`${this.name}: no valid ${type} sampled: ${problem.join(': ')}`);
      }
    }
  }

  private compiled(type: string): Compiled {
    const c = this.byType.get(type);
    if (c === undefined) throw new RangeError(`${this.name}: no message type "${type}"`);
    return c;
  }

  private checkHeader(byte: number): void {
    if (byte === this.header) return;
    const family = byte & 0xe0;
    const version = byte & 0x1f;
    const other = FAMILIES.get(family);
    const ours = this.header & 0xe0;
    const message =
      family !== ours
        ? `${other !== undefined ? `a ${other} message` : `header 0x${byte.toString(16)}`}, not ${this.name}`
        : version < this.version
          ? `${this.name} protocol version ${version}, this side speaks ${this.version}: the other side is older (reload the page or update fixedstep)`
          : `${this.name} protocol version ${version}, this side speaks ${this.version}: this side is older (update fixedstep)`;
    throw new ProtocolError('BAD_VERSION', message, { protocol: this.name, offset: 0 });
  }
}

/** Declares a protocol (see {@link ProtocolSpec}). */
export function defineProtocol<M extends { type: string }, L extends object>(
  spec: ProtocolSpec<M, L>,
): WireProtocol<M, L> {
  return new WireProtocol(spec);
}
