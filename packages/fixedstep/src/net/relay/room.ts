/**
 * A relay room: the tick clock and server-ordered inputs of one match (lockstep on the server; the
 * relay never runs the game), on the room core.
 * @module
 */
import { InputRing } from '../history.js';
import type { RoomContext } from '../room/host-types.js';
import type { HostedGame } from '../room/game-join.js';
import { Member, Room, type MemberInit } from '../room/room.js';
import type { LeaveReason } from '../wire/common.js';
import { DesyncDetector, type DesyncRecord } from './forensics.js';
import {
  CONFIRMED_DATAGRAM_EVERY,
  REDUNDANT_TICKS,
  encodeMessage,
  type NetMessage,
  type ProtocolLimits,
} from './messages.js';

/** The relay's own settings (besides the room core's). */
export interface RelaySettings {
  deadlineMs: number;
  hashEvery: number;
  sendEvery: number;
  startDelayMs: number;
  maxAheadTicks: number;
  maxBehindTicks: number;
  historyTicks: number;
  maxMatchTicks: number;
  startLivenessMs: number;
  snapshotTimeoutMs: number;
  forensicsTimeoutMs: number;
  hashTimeoutMs: number;
  maxDesyncRecords: number;
  maxForensicsBytes: number;
  limits: ProtocolLimits;
}

/** A relay connection: the room core's member and what the tick stream needs of it. */
export class RelayMember extends Member {
  /** The first confirmed tick it holds (its welcome's start). */
  joinTick = 0;
  /** The next confirmed tick it needs. */
  ack = 0;
  ackMovedAt: number;
  sentUpTo = 0;
  /**
   * Reliable transports: the tick after the last row of the previous confirmed message, which it
   * holds (the next message may be XOR-coded against that row); -1 when there is none.
   */
  deltaFrom = -1;
  /** Datagrams: the last message carried a changed input; send again with the next tick. */
  repeatChange = false;
  /**
   * Request ids it may answer (snapshot / hashes). An entry stays after its request timed out — a
   * late answer is ignored, not punished — and only the last 16 are kept.
   */
  readonly owes = new Map<number, 'snapshot' | 'hashes'>();
  /** Its welcome, to repeat when a hello is repeated (the first welcome was lost). */
  welcome: Uint8Array | undefined;
  welcomeSentAt = -Infinity;
  /** It knows the match has started (it sent an input, or acked a tick past its start). */
  started = false;

  constructor(init: MemberInit) {
    super(init);
    this.ackMovedAt = init.openedAt;
  }

  /** Remember that it owes an answer to request `id`. */
  owe(id: number, kind: 'snapshot' | 'hashes'): void {
    this.owes.set(id, kind);
    if (this.owes.size > 16) this.owes.delete(this.owes.keys().next().value!);
  }
}

/** A player seat's inputs. */
interface SeatInputs {
  /** The seat's input words of the newest closed tick. */
  last: Uint32Array;
  pending: InputRing;
  /** Sent at least one input since it (re)joined: the relay waits for it until the deadline. */
  active: boolean;
}

interface JoinRequest {
  member: RelayMember;
  donors: RelayMember[];
  id: number;
  donor: RelayMember | undefined;
  deadline: number;
}

/** What a room tells its relay. */
export interface RelayRoomEvents {
  join(room: RelayRoom, m: RelayMember, late: boolean): void;
  leave(room: RelayRoom, m: RelayMember, reason: LeaveReason): void;
  started(room: RelayRoom): void;
  desync(room: RelayRoom, record: DesyncRecord): void;
  spectatorDesync(room: RelayRoom, m: RelayMember, tick: number): void;
  /** A tick closed with an input filled after its deadline. */
  filled(): void;
  hashCheck(): void;
  split(): void;
  spectatorSplit(): void;
}

/**
 * One match: closes tick t when every connected, active player's input for t is in, or when its
 * clock passes `startAt + t × step + deadlineMs` — a missing input then becomes the player's last
 * input with held buttons only (a vacant seat's is 0) — and sends the closed ticks to every member.
 */
export class RelayRoom extends Room<RelayMember> {
  startAt: number | undefined;
  /** Every tick before this one is closed (its inputs final and sent). */
  closedEnd = 0;
  readonly log: InputRing;
  readonly tickMs: number;
  /** u32 words per player per tick. */
  readonly words: number;
  /** The room's desync detection and forensics. */
  readonly desyncs: DesyncDetector;
  private readonly inputs: SeatInputs[] = [];
  private joins: JoinRequest[] = [];
  private nextRequestId = 1;
  private row: Uint32Array;

  constructor(
    name: string,
    number: number,
    readonly game: HostedGame,
    players: number,
    readonly seed: number,
    readonly config: Uint8Array,
    creator: string,
    now: number,
    invite: Uint8Array,
    tokens: () => Uint8Array,
    ticketed: boolean,
    private readonly ctx: RoomContext<RelayMember, NetMessage>,
    private readonly relay: RelaySettings,
    private readonly events: RelayRoomEvents,
  ) {
    super(name, number, players, creator, now, invite, tokens, ticketed);
    this.tickMs = 1000 / game.tickRate;
    this.words = game.input.words;
    this.log = new InputRing(relay.historyTicks, players * this.words);
    this.row = new Uint32Array(players * this.words);
    for (let s = 0; s < players; s++) {
      this.inputs.push({
        last: new Uint32Array(this.words),
        pending: new InputRing(1024, this.words),
        active: false,
      });
    }
    this.desyncs = new DesyncDetector(this, ctx, relay, events);
  }

  /** A new request id (snapshots, hashes). */
  requestId(): number {
    return this.nextRequestId++;
  }

  protected replaced(old: RelayMember): void {
    this.ctx.drop(old, 'UNEXPECTED', 'replaced by a reconnect', 'replaced');
  }

  // ------------------------------------------------------------------------------ joining

  welcome(m: RelayMember, now: number): void {
    if (m.slot >= 0) {
      this.inputs[m.slot]!.active = false;
      // A (re)joining player's state comes from a donor: it is on the donor's side of any split.
      this.desyncs.forget(m.slot);
    }
    if (this.state === 'waiting') {
      this.sendWelcome(m, 0, undefined, now);
      this.events.join(this, m, false);
      this.tryStart(now);
      return;
    }
    // Late join or reconnect: a snapshot from a member, then the ticks since.
    const donors = [...this.members()].filter((c) => c !== m).sort((a, b) => b.ack - a.ack);
    const req: JoinRequest = { member: m, donors, id: 0, donor: undefined, deadline: 0 };
    this.joins.push(req);
    this.nextDonor(req, now);
  }

  /** A repeated hello of a member: its welcome was lost (resend, at most every 200 ms). */
  helloAgain(m: RelayMember, now: number): void {
    if (m.welcome && now - m.welcomeSentAt >= 200) {
      this.ctx.sendBytes(m, m.welcome);
      m.welcomeSentAt = now;
    }
  }

  private nextDonor(req: JoinRequest, now: number): void {
    const donor = req.donors.shift();
    if (donor?.state !== 'member') {
      if (donor !== undefined) {
        this.nextDonor(req, now);
        return;
      }
      this.joins = this.joins.filter((j) => j !== req);
      // No member can help: replay from tick 0 if the history still holds it.
      if (this.closedEnd <= this.log.capacity) {
        this.sendWelcome(req.member, 0, undefined, now);
        this.events.join(this, req.member, true);
      } else {
        this.ctx.drop(req.member, 'NO_SNAPSHOT', 'no member could send a snapshot');
      }
      return;
    }
    req.donor = donor;
    req.id = this.requestId();
    req.deadline = now + this.relay.snapshotTimeoutMs;
    donor.owe(req.id, 'snapshot');
    this.send(donor, { type: 'snapshot-request', room: this.number, id: req.id, tick: -1 });
  }

  private sendWelcome(
    m: RelayMember,
    tick: number,
    snapshot: Uint8Array | undefined,
    now: number,
  ): void {
    m.state = 'member';
    m.joinTick = tick;
    m.ack = tick;
    m.sentUpTo = tick;
    m.deltaFrom = -1;
    m.ackMovedAt = now;
    const seat = m.slot >= 0 ? this.seats[m.slot] : undefined;
    const w: NetMessage = {
      type: 'welcome',
      room: this.number,
      peer: m.peer,
      slot: m.slot,
      players: this.players,
      seed: this.seed,
      tickRate: this.game.tickRate,
      hashEvery: this.relay.hashEvery,
      deadlineMs: this.relay.deadlineMs,
      sendEvery: this.relay.sendEvery,
      inputFrom: this.state === 'waiting' ? 0 : this.closedEnd,
      startTick: tick,
      config: this.config,
      token: seat ? seat.token : new Uint8Array(0),
      invite: seat ? this.invite : new Uint8Array(0),
    };
    if (this.startAt !== undefined) w.startAt = this.startAt;
    if (snapshot !== undefined) w.snapshot = snapshot;
    m.welcome = encodeMessage(w);
    m.welcomeSentAt = now;
    m.started = this.startAt !== undefined;
    this.ctx.sendBytes(m, m.welcome);
  }

  /** Start a full waiting room, if every player in it has been heard from lately. */
  private tryStart(now: number): void {
    if (this.state !== 'waiting') return;
    for (const s of this.seats) {
      const c = s.member;
      if (c?.state !== 'member' || this.ctx.silence(c, now) > this.relay.startLivenessMs) return;
    }
    this.state = 'running';
    this.startAt = now + this.relay.startDelayMs;
    this.lastPlayAt = now;
    for (const s of this.inputs) s.active = true;
    for (const c of this.members()) {
      this.send(c, { type: 'start', room: this.number, startAt: this.startAt });
    }
    this.events.started(this);
  }

  // ------------------------------------------------------------------------------ receiving

  onMessage(m: RelayMember, message: { type: string }, now: number): void {
    const msg = message as NetMessage;
    if (msg.type === 'hello') {
      if (m.slot >= 0 !== (msg.role === 'player') || msg.room !== this.name) {
        this.ctx.drop(m, 'UNEXPECTED', 'hello for another room or role');
      } else {
        this.helloAgain(m, now);
      }
      return;
    }
    if (!('room' in msg) || msg.room !== this.number) {
      this.ctx.drop(m, 'WRONG_ROOM', `${msg.type} for another room`);
      return;
    }
    switch (msg.type) {
      case 'input':
        this.onInput(m, msg.player, msg.tick, msg.words, msg.inputs, now);
        this.onAck(m, msg.ack, now);
        break;
      case 'ack':
        this.onAck(m, msg.ack, now);
        break;
      case 'hash':
        this.desyncs.onHash(m, msg.tick, msg.hash, now);
        break;
      case 'leave':
        if (msg.peer !== m.peer) {
          this.ctx.drop(m, 'SPOOFED_PLAYER', 'leave for another peer');
          return;
        }
        this.ctx.leave(m);
        break;
      case 'snapshot':
        this.onSnapshot(m, msg.id, msg.tick, msg.bytes, now);
        break;
      case 'hashes':
        this.desyncs.onHashes(m, msg.id, msg.from, msg.hashes, now);
        break;
      default:
        this.ctx.drop(m, 'UNEXPECTED', `${msg.type} is a server-to-client message`);
    }
  }

  private onInput(
    m: RelayMember,
    player: number,
    tick: number,
    words: number,
    inputs: Uint32Array,
    now: number,
  ): void {
    if (m.slot < 0 || m.state !== 'member') {
      this.ctx.drop(m, 'SPOOFED_PLAYER', 'a spectator sent inputs');
      return;
    }
    if (player !== m.slot) {
      this.ctx.drop(m, 'SPOOFED_PLAYER', `inputs for player ${player} from player ${m.slot}`);
      return;
    }
    if (words !== this.words) {
      this.ctx.drop(
        m,
        'BAD_INPUT',
        `inputs of ${words} words, ${this.game.id} takes ${this.words}`,
      );
      return;
    }
    const ticks = inputs.length / words;
    for (let k = 0; k < ticks; k++) {
      const problem = this.game.input.problem(inputs, k * words);
      if (problem !== undefined) {
        this.ctx.drop(m, 'BAD_INPUT', `input of tick ${tick + k}: ${problem}`);
        return;
      }
    }
    const last = tick + ticks - 1;
    const clockTick =
      this.startAt === undefined ? 0 : Math.max(0, Math.floor((now - this.startAt) / this.tickMs));
    if (last > clockTick + this.relay.maxAheadTicks) {
      this.ctx.strike(m, 'TICK_WINDOW', `inputs for tick ${last}, the server is at ${clockTick}`);
      return;
    }
    if (last < this.closedEnd - this.relay.maxBehindTicks) {
      this.ctx.strike(m, 'TICK_WINDOW', `inputs for tick ${last}, long closed`);
      return;
    }
    const s = this.inputs[m.slot]!;
    for (let k = 0; k < ticks; k++) {
      const t = tick + k;
      if (t < this.closedEnd || t >= this.closedEnd + s.pending.capacity || s.pending.has(t))
        continue;
      s.pending.set(t, inputs, k * words);
    }
    s.active = true;
    m.started = true;
    // A player who sends inputs plays: the room is not idle.
    this.lastPlayAt = now;
  }

  private onAck(m: RelayMember, ack: number, now: number): void {
    if (ack > this.closedEnd) {
      this.ctx.strike(m, 'TICK_WINDOW', `ack of tick ${ack}, only ${this.closedEnd} closed`);
      return;
    }
    if (ack > m.ack) {
      m.ack = ack;
      m.ackMovedAt = now;
    }
    if (!m.started && this.startAt !== undefined) {
      if (ack > m.joinTick) {
        m.started = true;
      } else if (now - m.welcomeSentAt >= 200) {
        // Still waiting: the start was lost.
        this.send(m, { type: 'start', room: this.number, startAt: this.startAt });
        m.welcomeSentAt = now;
      }
    }
  }

  private onSnapshot(
    m: RelayMember,
    id: number,
    tick: number,
    bytes: Uint8Array,
    now: number,
  ): void {
    if (m.owes.get(id) !== 'snapshot') {
      this.ctx.drop(m, 'UNEXPECTED', 'unrequested snapshot');
      return;
    }
    m.owes.delete(id);
    const req = this.joins.find((j) => j.id === id && j.donor === m);
    if (req === undefined) {
      this.desyncs.onSnapshot(m, id, tick, bytes, now);
      return;
    }
    const oldest = Math.max(0, this.closedEnd - this.log.capacity + 1);
    if (
      bytes.length === 0 ||
      tick > this.closedEnd ||
      tick < oldest ||
      req.member.state !== 'joining'
    ) {
      if (req.member.state === 'joining') this.nextDonor(req, now);
      return;
    }
    this.joins = this.joins.filter((j) => j !== req);
    this.sendWelcome(req.member, tick, bytes, now);
    this.events.join(this, req.member, true);
  }

  /** A member left: free its seat's inputs, its joins and donations; tell the others. */
  onLeave(m: RelayMember, reason: LeaveReason, now: number): void {
    if (m.slot >= 0 && this.seats[m.slot]?.member === undefined) {
      const s = this.inputs[m.slot]!;
      s.active = false;
      s.last.fill(0);
      for (let t = this.closedEnd; t < this.closedEnd + s.pending.capacity; t++) s.pending.clear(t);
    }
    for (const req of [...this.joins]) {
      if (req.member === m) this.joins = this.joins.filter((j) => j !== req);
      else if (req.donor === m) this.nextDonor(req, now);
    }
    // Only a member that was welcomed was ever announced.
    if (m.welcome !== undefined) {
      for (const c of this.members()) {
        this.send(c, { type: 'leave', room: this.number, peer: m.peer, reason });
      }
      this.events.leave(this, m, reason);
    }
  }

  // ------------------------------------------------------------------------------ the tick clock

  advance(now: number): void {
    if (this.joins.length > 0) {
      for (const req of [...this.joins]) {
        if (req.member.state !== 'joining') this.joins = this.joins.filter((j) => j !== req);
        else if (now >= req.deadline) this.nextDonor(req, now);
      }
    }
    if (this.state === 'waiting' && this.seats.every((s) => s.member !== undefined)) {
      this.tryStart(now);
    }
    if (this.state === 'running') this.closeTicks(now);
    this.flush(now);
    this.desyncs.update(now);
  }

  private closeTicks(now: number): void {
    const startAt = this.startAt!;
    const w = this.words;
    const row = this.row;
    const maxTicks = this.relay.maxMatchTicks;
    for (let guard = 0; guard < 4096 && this.closedEnd < maxTicks; guard++) {
      const t = this.closedEnd;
      const tickStart = startAt + t * this.tickMs;
      let required = 0;
      let missing = 0;
      for (let p = 0; p < this.players; p++) {
        const s = this.inputs[p]!;
        if (this.seats[p]!.member?.state === 'member' && s.active) {
          required++;
          if (!s.pending.has(t)) missing++;
        }
      }
      // Early (before its time) only when every required input is in; never without any input.
      if (
        missing > 0
          ? now < tickStart + this.relay.deadlineMs
          : required === 0
            ? now < tickStart
            : false
      ) {
        break;
      }
      let filled = false;
      for (let p = 0; p < this.players; p++) {
        const s = this.inputs[p]!;
        const member = this.seats[p]!.member;
        if (s.pending.has(t)) {
          s.pending.copy(t, row, p * w);
          s.pending.clear(t);
        } else if (member) {
          // The game's rule for a missing input: held buttons only, axes kept.
          this.game.input.missing(s.last, 0, row, p * w);
          if (member.state === 'member' && s.active) filled = true;
        } else {
          row.fill(0, p * w, (p + 1) * w);
        }
        for (let k = 0; k < w; k++) s.last[k] = row[p * w + k]!;
      }
      if (filled) this.events.filled();
      this.log.set(t, row);
      this.closedEnd++;
    }
    if (this.closedEnd >= maxTicks) this.state = 'ended';
  }

  /**
   * Send each member the closed ticks it lacks. Over a reliable transport each tick goes once,
   * XOR-coded against the tick before it (a held button costs one byte a player, and the header
   * six); otherwise every message repeats every unacknowledged tick, so a lost one costs nothing
   * but the next. Either way a member whose ack stops moving is rewound to its ack.
   */
  private flush(now: number): void {
    // Loops rather than members(): this runs for every room twice a tick, and a generator costs
    // more than the usual work here (nothing to send).
    for (const s of this.seats) if (s.member?.state === 'member') this.flushMember(s.member, now);
    for (const c of this.spectators) if (c.state === 'member') this.flushMember(c, now);
  }

  private flushMember(c: RelayMember, now: number): void {
    const newest = this.closedEnd;
    const maxTicks = this.relay.limits.maxConfirmedTicks;
    const oldest = Math.max(0, newest - this.log.capacity + 1);
    const lanes = this.players * this.words;
    if (c.ack < oldest) {
      // Fell out of the history: it cannot catch up from here.
      this.ctx.drop(c, 'NO_SNAPSHOT', 'too far behind the room');
      return;
    }
    if (c.sentUpTo < c.ack) c.sentUpTo = c.ack;
    const rewind = c.ack < c.sentUpTo && now - c.ackMovedAt > (c.reliable ? 1000 : 250);
    if (!(newest > c.sentUpTo || rewind)) return;
    if (!c.reliable && !rewind && newest - c.ack <= maxTicks) {
      this.flushDatagram(c, newest, now);
      return;
    }
    // The network rate: new ticks wait until there are `sendEvery` of them, or the first has
    // waited that many ticks' time (a stalled room, the end of a match).
    const every = this.relay.sendEvery;
    if (
      every > 1 &&
      !rewind &&
      newest - c.sentUpTo < every &&
      this.state === 'running' &&
      now < this.startAt! + (c.sentUpTo + every) * this.tickMs
    ) {
      return;
    }
    // Small gap: every message carries every unacknowledged tick (loss costs nothing).
    // Large gap (a late joiner catching up): stream onwards; go back to the ack on a timeout.
    let from = rewind || (!c.reliable && newest - c.ack <= maxTicks) ? c.ack : c.sentUpTo;
    if (rewind) {
      c.ackMovedAt = now;
      c.deltaFrom = -1;
    }
    const inputAck = this.inputAck(c);
    for (let k = 0; k < 8 && from < newest; k++) {
      const n = Math.min(maxTicks, newest - from);
      const inputs = new Uint32Array(n * lanes);
      for (let i = 0; i < n; i++) this.log.copy(from + i, inputs, i * lanes);
      const delta = c.reliable && from > 0 && c.deltaFrom === from;
      if (delta) {
        // XOR every row with tick from − 1's (which it holds): unchanged inputs become zeros.
        for (let p = 0; p < lanes; p++) {
          const base = this.log.get(from - 1, p);
          for (let i = 0; i < n; i++) inputs[i * lanes + p] = (inputs[i * lanes + p]! ^ base) >>> 0;
        }
      }
      this.send(c, {
        type: 'confirmed',
        inputAck: c.slot < 0 ? from + n : Math.max(inputAck, from + n),
        tick: from,
        players: this.players,
        words: this.words,
        inputs,
        delta,
      });
      from += n;
      if (c.reliable) c.deltaFrom = from;
    }
    c.sentUpTo = Math.max(c.sentUpTo, from);
  }

  /**
   * A member on a datagram transport: new ticks in groups of {@link CONFIRMED_DATAGRAM_EVERY} (or the room's
   * `sendEvery`, if larger), a tick whose row changed at once and again with the next tick, each
   * message repeating at most {@link REDUNDANT_TICKS} sent but unacknowledged ticks (a rewind to the
   * ack resends the rest when the ack stops moving).
   */
  private flushDatagram(c: RelayMember, newest: number, now: number): void {
    const pace = Math.max(this.relay.sendEvery, CONFIRMED_DATAGRAM_EVERY);
    const lanes = this.players * this.words;
    let changed = false;
    for (let t = Math.max(c.sentUpTo, 1); t < newest && !changed; t++) {
      for (let p = 0; p < lanes; p++) {
        if (this.log.get(t, p) !== this.log.get(t - 1, p)) {
          changed = true;
          break;
        }
      }
    }
    const due =
      changed ||
      c.repeatChange ||
      newest - c.sentUpTo >= pace ||
      this.state !== 'running' ||
      now >= this.startAt! + (c.sentUpTo + pace) * this.tickMs;
    if (!due) return;
    c.repeatChange = changed && pace > 2;
    const from = Math.max(c.ack, c.sentUpTo - REDUNDANT_TICKS);
    const n = newest - from;
    const inputs = new Uint32Array(n * lanes);
    for (let i = 0; i < n; i++) this.log.copy(from + i, inputs, i * lanes);
    this.send(c, {
      type: 'confirmed',
      inputAck: c.slot < 0 ? newest : Math.max(this.inputAck(c), newest),
      tick: from,
      players: this.players,
      words: this.words,
      inputs,
      delta: false,
    });
    c.sentUpTo = newest;
  }

  /** The next tick the relay needs an input from `c` for. */
  private inputAck(c: RelayMember): number {
    if (c.slot < 0) return 0;
    const s = this.inputs[c.slot]!;
    let t = this.closedEnd;
    while (s.pending.has(t) && t < this.closedEnd + s.pending.capacity) t++;
    return t;
  }

  send(m: RelayMember, message: NetMessage): void {
    this.ctx.send(m, message);
  }
}
