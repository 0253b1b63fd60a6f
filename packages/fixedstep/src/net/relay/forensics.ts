/**
 * Desync detection and forensics of a relay room: players report a state hash every `hashEvery`
 * ticks; whenever players who agreed before disagree, one member of each side is asked for its
 * per-tick hashes to find the first differing tick, everyone is told, and the sides' snapshots of
 * that tick are collected for a byte diff. Spectators' hashes are never evidence.
 * @module
 */
import { diffSnapshots, type SnapshotDiff } from '../forensics.js';
import type { RoomContext } from '../room/host-types.js';
import type { NetMessage } from './messages.js';
import type { RelayMember, RelayRoom, RelayRoomEvents, RelaySettings } from './room.js';

/** A desync the relay found, with its forensics. */
export interface DesyncRecord {
  room: string;
  /** The periodic report tick where the hashes first disagreed. */
  reportTick: number;
  /** The first tick whose state differs (exact when per-tick hashes pinned it). */
  tick: number;
  exact: boolean;
  /** The sides: hash at `tick` (or `reportTick`), peers, and player slots among them. */
  groups: { hash: bigint; peers: number[]; slots: number[] }[];
  /** Index of the majority group (≥ 3 reporters and more than half), or -1. */
  majority: number;
  /** Each side's representative `save()` bytes at `tick` (empty when not received). */
  snapshots: { peer: number; bytes: Uint8Array }[];
  /** Byte offsets that differ between the first side (the majority, if any) and each other side. */
  diffs: { peer: number; diff: SnapshotDiff }[];
  /** Whether forensics finished (all answers in, or timed out). */
  complete: boolean;
}

/** Most report ticks waiting for comparison; a flood of hash reports cannot grow it. */
const MAX_OPEN_REPORTS = 64;
/** Past this many open reports the oldest is compared without waiting for late reporters. */
const COMPARE_AFTER_REPORTS = 48;
/** The players' agreed hashes kept, to check spectators' late reports. */
const AGREED_KEPT = 16;

/** A split found by the hash comparison, waiting for its forensics. */
interface Split {
  reportTick: number;
  /** The first tick to compare per-tick hashes from. */
  from: number;
  /** Whether the sides agreed at `from - 1` (the previous compared report). */
  agreedBefore: boolean;
  groups: { hash: bigint; peers: number[] }[];
}

interface Forensics {
  record: DesyncRecord;
  phase: 'hashes' | 'snapshots' | 'done';
  reps: RelayMember[];
  from: number;
  agreedBefore: boolean;
  requestId: number;
  hashes: Map<number, { from: number; hashes: BigUint64Array }>;
  snaps: Map<number, Uint8Array>;
  deadline: number;
  /** Whether the snapshots are collected (the room's forensics byte budget allows). */
  withSnapshots: boolean;
}

interface Report {
  at: number;
  /** Players' hashes: the evidence. */
  hashes: Map<number, bigint>;
  /** Spectators' hashes: checked against the players' agreed hash only. */
  spectators: Map<number, bigint>;
}

/** One room's hash comparison and desync forensics. */
export class DesyncDetector {
  /** The newest report tick on which every reporting player agreed. */
  lastAgreed = 0;
  /** Report ticks compared. */
  hashChecks = 0;
  readonly records: DesyncRecord[] = [];
  private readonly reports = new Map<number, Report>();
  /** The previous compared report tick (every group of the partition agreed within there). */
  private lastCompared = 0;
  /** Which side each player was on at the last compared report (one label: all agree). */
  private readonly partition = new Map<number, number>();
  private nextLabel = 1;
  private readonly agreed = new Map<number, bigint>();
  private forensics: Forensics | undefined;
  private splits: Split[] = [];
  private forensicsBytes = 0;

  constructor(
    private readonly room: RelayRoom,
    private readonly ctx: RoomContext<RelayMember, NetMessage>,
    private readonly o: RelaySettings,
    private readonly events: RelayRoomEvents,
  ) {}

  /** A (re)joining player's state comes from a donor: it is on the donor's side of any split. */
  forget(slot: number): void {
    this.partition.delete(slot);
  }

  onHash(m: RelayMember, tick: number, hash: bigint, now: number): void {
    if (m.state !== 'member') return;
    if (tick % this.o.hashEvery !== 0 || tick > this.room.closedEnd || tick <= m.joinTick) {
      this.ctx.strike(m, 'TICK_WINDOW', `hash for tick ${tick}`);
      return;
    }
    if (m.slot < 0) {
      // A spectator's hash is checked against the players' agreement, never counted as evidence.
      const agreed = this.agreed.get(tick);
      if (agreed !== undefined) {
        this.checkSpectator(m, tick, hash, agreed);
        return;
      }
      const r = tick > this.lastCompared ? this.report(tick, now) : undefined;
      r?.spectators.set(m.peer, hash);
      return;
    }
    if (tick <= this.lastCompared) return;
    const r = this.report(tick, now);
    if (r === undefined) return;
    r.hashes.set(m.peer, hash);
    this.checkReports(now);
  }

  onHashes(m: RelayMember, id: number, from: number, hashes: BigUint64Array, now: number): void {
    if (m.owes.get(id) !== 'hashes') {
      this.ctx.strike(m, 'UNEXPECTED', 'unrequested hashes');
      return;
    }
    m.owes.delete(id);
    const f = this.forensics;
    if (f?.phase === 'hashes' && id === f.requestId && f.reps.includes(m)) {
      f.hashes.set(m.peer, { from, hashes });
      if (f.hashes.size === f.reps.length) this.pinDesync(f, now);
    }
  }

  /** A snapshot that answered a forensics request (not a late joiner's). */
  onSnapshot(m: RelayMember, id: number, tick: number, bytes: Uint8Array, now: number): void {
    const f = this.forensics;
    if (
      f?.phase !== 'snapshots' ||
      id !== f.requestId ||
      !f.reps.includes(m) ||
      tick !== f.record.tick
    ) {
      return;
    }
    if (this.forensicsBytes + bytes.length <= this.o.maxForensicsBytes) {
      this.forensicsBytes += bytes.length;
      f.snaps.set(m.peer, bytes);
    } else {
      f.snaps.set(m.peer, new Uint8Array(0));
    }
    if (f.snaps.size === f.reps.length) this.finishForensics(f, now);
  }

  update(now: number): void {
    if (this.reports.size > 0) this.checkReports(now);
    const f = this.forensics;
    if (f && f.phase !== 'done' && now >= f.deadline) {
      if (f.phase === 'hashes') this.pinDesync(f, now);
      else this.finishForensics(f, now);
    }
  }

  private report(tick: number, now: number): Report | undefined {
    let r = this.reports.get(tick);
    if (r === undefined) {
      if (this.reports.size >= MAX_OPEN_REPORTS) return undefined;
      r = { at: now, hashes: new Map(), spectators: new Map() };
      this.reports.set(tick, r);
    }
    return r;
  }

  /**
   * Compare the players' reports of each tick once every player member that joined before it has
   * reported (or it timed out). Players who agreed at the previous comparison and now disagree
   * are a new desync — every one is diagnosed, not only the room's first — while a divergence
   * that persists (the same sides as before) is not reported again. Sides that agree again merge.
   */
  private checkReports(now: number): void {
    const ticks = [...this.reports.keys()].sort((a, b) => a - b);
    for (const tick of ticks) {
      const r = this.reports.get(tick)!;
      let all = true;
      for (const c of this.room.playerMembers()) {
        if (c.joinTick >= tick) continue;
        if (!r.hashes.has(c.peer)) all = false;
      }
      const timedOut =
        now - r.at >= this.o.hashTimeoutMs || this.reports.size > COMPARE_AFTER_REPORTS;
      if (!(all || timedOut)) continue;
      this.reports.delete(tick);
      if (r.hashes.size === 0) continue;
      this.hashChecks++;
      this.events.hashCheck();
      const groups = groupByHash(r.hashes);
      const previous = this.lastCompared;
      this.lastCompared = tick;
      if (groups.length === 1) {
        this.lastAgreed = tick;
        const agreed = groups[0]!.hash;
        this.agreed.set(tick, agreed);
        if (this.agreed.size > AGREED_KEPT) this.agreed.delete(this.agreed.keys().next().value!);
        for (const [peer, hash] of r.spectators) {
          const c = [...this.room.spectators].find((x) => x.peer === peer);
          if (c) this.checkSpectator(c, tick, hash, agreed);
        }
      }
      this.repartition(tick, previous, groups, now);
    }
  }

  /** Compare the new grouping with the previous one: splits are desyncs; relabel every player. */
  private repartition(
    tick: number,
    previous: number,
    groups: { hash: bigint; peers: number[] }[],
    now: number,
  ): void {
    // A player without a side yet (the first report, a newcomer) is on the most common side.
    const counts = new Map<number, number>();
    for (const l of this.partition.values()) counts.set(l, (counts.get(l) ?? 0) + 1);
    let common = 0;
    let best = -1;
    for (const [l, n] of counts) {
      if (n > best || (n === best && l < common)) {
        best = n;
        common = l;
      }
    }
    const labelOf = (peer: number) => this.partition.get(peer) ?? common;
    // For each old side: the new groups its players went to.
    const sides = new Map<number, Map<number, number[]>>();
    groups.forEach((g, gi) => {
      for (const p of g.peers) {
        const l = labelOf(p);
        let m = sides.get(l);
        if (!m) sides.set(l, (m = new Map<number, number[]>()));
        let list = m.get(gi);
        if (!list) m.set(gi, (list = []));
        list.push(p);
      }
    });
    const newLabel = groups.map(() => this.nextLabel++);
    const oldToNew = new Map<number, number>();
    for (const [l, m] of sides) {
      if (m.size === 1) {
        oldToNew.set(l, newLabel[m.keys().next().value!]!);
        continue;
      }
      // A split: players who agreed at `previous` disagree now.
      const split = [...m.entries()].map(([gi, peers]) => ({ hash: groups[gi]!.hash, peers }));
      split.sort((a, b) => b.peers.length - a.peers.length || a.peers[0]! - b.peers[0]!);
      this.events.split();
      const open = this.records.length + this.splits.length + (this.forensics ? 1 : 0);
      if (open < this.o.maxDesyncRecords) {
        const from = Math.max(previous + 1, tick - this.o.limits.maxHashes + 1);
        this.splits.push({
          reportTick: tick,
          from,
          agreedBefore: from === previous + 1,
          groups: split,
        });
      }
    }
    // Players who did not report keep their side if it did not split.
    for (const [peer, l] of [...this.partition]) {
      const next = oldToNew.get(l);
      if (next !== undefined) this.partition.set(peer, next);
    }
    groups.forEach((g, gi) => {
      for (const p of g.peers) this.partition.set(p, newLabel[gi]!);
    });
    if (this.forensics === undefined) this.nextForensics(now);
  }

  private checkSpectator(c: RelayMember, tick: number, hash: bigint, agreed: bigint): void {
    if (hash === agreed) return;
    this.events.spectatorSplit();
    const players = [...this.room.playerMembers()].map((p) => p.peer);
    this.room.send(c, {
      type: 'desync',
      room: this.room.number,
      tick,
      exact: false,
      reportTick: tick,
      majority: 0,
      groups: [
        { hash: agreed, peers: players },
        { hash, peers: [c.peer] },
      ],
    });
    this.events.spectatorDesync(this.room, c, tick);
  }

  private nextForensics(now: number): void {
    const split = this.splits.shift();
    if (split) this.beginForensics(split, now);
  }

  private beginForensics(split: Split, now: number): void {
    const byPeer = new Map<number, RelayMember>();
    for (const c of this.room.playerMembers()) byPeer.set(c.peer, c);
    const reps: RelayMember[] = [];
    for (const g of split.groups) {
      const rep = g.peers.map((p) => byPeer.get(p)).find((c) => c !== undefined);
      if (rep) reps.push(rep);
    }
    const total = split.groups.reduce((n, g) => n + g.peers.length, 0);
    const record: DesyncRecord = {
      room: this.room.name,
      reportTick: split.reportTick,
      tick: split.reportTick,
      exact: false,
      groups: split.groups.map((g) => ({
        hash: g.hash,
        peers: g.peers,
        slots: g.peers.filter((p) => p < 64),
      })),
      majority: majorityOf(split.groups, total),
      snapshots: [],
      diffs: [],
      complete: false,
    };
    const f: Forensics = {
      record,
      phase: 'hashes',
      reps,
      from: split.from,
      agreedBefore: split.agreedBefore,
      requestId: this.room.requestId(),
      hashes: new Map(),
      snaps: new Map(),
      deadline: now + this.o.forensicsTimeoutMs,
      withSnapshots: this.forensicsBytes < this.o.maxForensicsBytes,
    };
    this.forensics = f;
    this.records.push(record);
    for (const c of reps) {
      c.owe(f.requestId, 'hashes');
      this.room.send(c, {
        type: 'hashes-request',
        room: this.room.number,
        id: f.requestId,
        from: split.from,
        count: split.reportTick - split.from + 1,
      });
    }
    if (reps.length === 0) this.pinDesync(f, now);
  }

  /** Per-tick hashes are in (or timed out): find the first differing tick and tell everyone. */
  private pinDesync(f: Forensics, now: number): void {
    const rec = f.record;
    const hashAt = (peer: number, t: number): bigint | undefined => {
      const h = f.hashes.get(peer);
      if (!h || t < h.from || t >= h.from + h.hashes.length) return undefined;
      return h.hashes[t - h.from];
    };
    const peers = f.reps.map((c) => c.peer);
    let first = -1;
    for (let t = f.from; t <= rec.reportTick && first < 0; t++) {
      const seen = peers.map((p) => hashAt(p, t)).filter((h) => h !== undefined);
      if (seen.length >= 2 && seen.some((h) => h !== seen[0])) first = t;
    }
    if (first >= 0) {
      rec.tick = first;
      // Exact when the sides agree just before (or it is the first tick they were compared from).
      const before = peers.map((p) => hashAt(p, first - 1));
      rec.exact =
        (first === f.from && f.agreedBefore) ||
        (before.every((h) => h !== undefined) && before.every((h) => h === before[0]));
      // Regroup the representatives by their hash at the first differing tick.
      rec.groups = rec.groups.map((g, i) => {
        const rep = f.reps[i];
        const h = rep ? hashAt(rep.peer, first) : undefined;
        return { ...g, hash: h ?? g.hash };
      });
    }
    for (const c of this.room.members()) {
      this.room.send(c, {
        type: 'desync',
        room: this.room.number,
        tick: rec.tick,
        exact: rec.exact,
        reportTick: rec.reportTick,
        majority: rec.majority,
        groups: rec.groups.map((g) => ({ hash: g.hash, peers: g.peers })),
      });
    }
    if (!f.withSnapshots) {
      this.finishForensics(f, now);
      return;
    }
    f.phase = 'snapshots';
    f.requestId = this.room.requestId();
    f.deadline = now + this.o.forensicsTimeoutMs;
    for (const c of f.reps) {
      if (c.state !== 'member') continue;
      c.owe(f.requestId, 'snapshot');
      this.room.send(c, {
        type: 'snapshot-request',
        room: this.room.number,
        id: f.requestId,
        tick: rec.tick,
      });
    }
  }

  private finishForensics(f: Forensics, now: number): void {
    const rec = f.record;
    rec.snapshots = f.reps.map((c) => ({
      peer: c.peer,
      bytes: f.snaps.get(c.peer) ?? new Uint8Array(0),
    }));
    const baseIndex = rec.majority >= 0 ? rec.majority : 0;
    const base = rec.snapshots[baseIndex];
    if (base && base.bytes.length > 0) {
      rec.diffs = rec.snapshots
        .filter((s, i) => i !== baseIndex && s.bytes.length > 0)
        .map((s) => ({ peer: s.peer, diff: diffSnapshots(base.bytes, s.bytes) }));
    }
    rec.complete = true;
    f.phase = 'done';
    this.forensics = undefined;
    this.events.desync(this.room, rec);
    this.nextForensics(now);
  }
}

function groupByHash(hashes: Map<number, bigint>): { hash: bigint; peers: number[] }[] {
  const groups: { hash: bigint; peers: number[] }[] = [];
  const peers = [...hashes.keys()].sort((a, b) => a - b);
  for (const p of peers) {
    const h = hashes.get(p)!;
    const g = groups.find((x) => x.hash === h);
    if (g) g.peers.push(p);
    else groups.push({ hash: h, peers: [p] });
  }
  // Largest side first.
  return groups.sort((a, b) => b.peers.length - a.peers.length || a.peers[0]! - b.peers[0]!);
}

function majorityOf(groups: { peers: number[] }[], total: number): number {
  if (total < 3) return -1;
  return groups.findIndex((g) => g.peers.length * 2 > total);
}
