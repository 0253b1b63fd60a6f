/**
 * Quick-match tickets: what seats a matched player in its relay room, with the room's setup fixed
 * by the matchmaker. A ticket is signed (HMAC-SHA256, `node:crypto`) with a secret the matchmaker
 * and every relay process share, so any process behind a balancer can check it without asking the
 * one that matched.
 * @module
 */
import { createHmac, randomBytes, timingSafeEqual } from 'node:crypto';
import { ByteReader, ByteWriter, type MatchTicket, type TicketVerifier } from 'fixedstep';

/** A ticket is good for this long after the match: its players join the room at once. */
export const TICKET_LIFETIME_MS = 10 * 60_000;
/** Bytes of a ticket's signature (a whole HMAC-SHA256). */
const MAC_BYTES = 32;
/** The ticket format's version (byte 0). */
const TICKET_VERSION = 1;
/** The shortest secret taken from the environment. */
const MIN_SECRET_CHARS = 16;

/** Options of {@link MatchTickets}. */
export interface MatchTicketsOptions {
  /**
   * The signing secret, shared by every process of a deployment (the matchmaker's and the relays').
   * Default `FIXEDSTEP_MATCH_SECRET` (16 characters or more), else random for this process — then
   * only this process's relay takes its tickets.
   */
  secret?: string | Uint8Array;
  /** How long a ticket is good for, ms. Default {@link TICKET_LIFETIME_MS}. */
  lifetimeMs?: number;
  /** Wall-clock time, ms (tickets cross processes: not a monotonic clock). Default `Date.now`. */
  now?: () => number;
  /** Where `FIXEDSTEP_MATCH_SECRET` is read from. Default `process.env`. */
  env?: Readonly<Record<string, string | undefined>>;
}

/** Makes and checks quick-match tickets (see the module's comment). */
export class MatchTickets {
  private readonly secret: Buffer;
  private readonly lifetimeMs: number;
  private readonly now: () => number;
  /** Checks a ticket's bytes: the ticket, or why it is refused (for the relay's `tickets`). */
  readonly verify: TicketVerifier;

  constructor(options: MatchTicketsOptions = {}) {
    const fromEnv = (options.env ?? process.env).FIXEDSTEP_MATCH_SECRET;
    if (
      options.secret === undefined &&
      fromEnv !== undefined &&
      fromEnv.length < MIN_SECRET_CHARS
    ) {
      throw new Error(`FIXEDSTEP_MATCH_SECRET: at least ${MIN_SECRET_CHARS} characters`);
    }
    const secret = options.secret ?? fromEnv;
    this.secret =
      secret === undefined
        ? randomBytes(32)
        : typeof secret === 'string'
          ? Buffer.from(secret, 'utf8')
          : Buffer.from(secret);
    this.lifetimeMs = options.lifetimeMs ?? TICKET_LIFETIME_MS;
    this.now = options.now ?? Date.now;
    this.verify = (bytes) => this.check(bytes);
  }

  /** A ticket for seat `t.slot` of room `t.room`, good for the lifetime from now. */
  issue(t: MatchTicket): Uint8Array {
    const w = new ByteWriter(128)
      .u8(TICKET_VERSION)
      .f64(this.now() + this.lifetimeMs)
      .str(t.room)
      .str(t.game)
      .varint(t.gameVersion)
      .varint(t.players)
      .u32(t.seed)
      .varint(t.slot);
    const body = w.peek();
    const ticket = new Uint8Array(body.length + MAC_BYTES);
    ticket.set(body);
    ticket.set(this.mac(body), body.length);
    return ticket;
  }

  private mac(body: Uint8Array): Buffer {
    return createHmac('sha256', this.secret).update(body).digest();
  }

  private check(bytes: Uint8Array): MatchTicket | string {
    if (bytes.length <= MAC_BYTES) return 'too short to be a ticket';
    const body = bytes.subarray(0, bytes.length - MAC_BYTES);
    const mac = bytes.subarray(bytes.length - MAC_BYTES);
    if (!timingSafeEqual(mac, this.mac(body))) return 'not signed by this deployment';
    try {
      const r = new ByteReader(body);
      if (r.u8('version') !== TICKET_VERSION) return 'a ticket of another version';
      const expires = r.f64('expiry');
      const t: MatchTicket = {
        room: r.str('room', 32),
        game: r.str('game', 32),
        gameVersion: r.varint('game version'),
        players: r.varint('players'),
        seed: r.u32('seed'),
        slot: r.varint('slot'),
      };
      r.end();
      if (!(expires > this.now())) return 'expired';
      if (t.slot >= t.players) return `seat ${t.slot} of ${t.players}`;
      return t;
    } catch (error) {
      // Signed by us yet unreadable: a bug, said as a refusal.
      return `unreadable: ${error instanceof Error ? error.message : String(error)}`;
    }
  }
}
