/**
 * The world's snapshot (Box2D's `world_snapshot.c`): the whole state as canonical bytes, and back.
 *
 * ## Format (versions 1 and 2, little-endian, floats canonical: −0 as +0, one NaN)
 *
 * | bytes | what |
 * | --- | --- |
 * | 4 + 4 | magic `"FSPW"` (0x57505346), version (1 or 2) |
 * | 8 | tick (f64, an integer) |
 * | 11 × 8 | def: gravityX, gravityY, timeStep, restitution, restitutionThreshold, friction, linearSlop, positionCorrection, cellSize, sleepSpeed, timeToSleep |
 * | 3 × 4 | def: velocityIterations, positionIterations, maxCcdIterations (u32) |
 * | 1 + 1 | def: ccd (0 off, 1 bullets, 2 auto), enableSleep (0/1) |
 * | 4 | walls W (u32), then per wall: kind (u8: 0 segment, 1 box) and its 4 parameters (f64) |
 * | 4 | body slots N (u32), then columns of N: flags (u8); x, y, vx, vy, halfWidth, halfHeight, inverseMass, restTime (f64); island (i32) |
 * | 4 | warm-start entries C (u32), then columns of C: bodyA, bodyB (i32; a wall as −1 − id), normalImpulse, tangentImpulse (f64) |
 * | | *version 2 only:* |
 * | 3 × 4N | columns of N: categoryBits, maskBits (u32), groupIndex (i32) — a free slot's all 0 |
 * | 4 | sensor overlaps O (u32), then columns of O: sensor, visitor (i32), sorted by sensor then visitor |
| | *version 3 only (after version 2's section):* |
| 3 × 8N | columns of N: friction, restitution (f64; −1: the world's, `WORLD_MATERIAL`), linearDamping (f64) — a free slot's all 0 |
 *
 * Version 2 adds what filters and sensors need (`filter.ts`, `events.ts`), and a body flag
 * (`BodyFlag.SENSOR`). A world with no sensor, no body with a filter other than the default and no
 * sensor overlap writes version 1 — the same bytes, so the same hashes, as before version 2
 * existed — and version 2 otherwise (a version 2 snapshot that could be version 1 is refused as
 * not canonical). Both load; an older world refuses version 2 with "unsupported snapshot version 2".

Version 3 adds the bodies' materials (`material.ts`: friction, restitution, linear damping) after
version 2's section. It is written only when some live body's material is not the default one
(the world's friction and restitution, no damping), so worlds without materials keep writing
versions 1 and 2, byte for byte; a version 3 snapshot whose materials are all the default is
refused as not canonical.
 *
 * `def.maxContacts` is not in it (it never changes a step that completes).
 *
 * ## Speed
 *
 * A save is a copy: the body columns are `Uint8Array.set` copies of the world's own typed arrays
 * (they are little-endian on every platform JavaScript runs on, and the world keeps them
 * canonical: no −0, no NaN ever gets in — see `WarmStartCache.store` for the one −0 a step can
 * make), the rest is a few hundred scalar writes plus the warm-start columns. Nothing is
 * allocated once the views onto the world's arrays and the caller's buffer exist. A load copies
 * the bytes into a staging buffer placed so the body columns are 8-byte aligned, checks every
 * value from typed views of it, and only then copies them into the world.
 */
import { ByteWriter } from '../../det/bytes.js';
import {
  BodyFlag,
  DEFAULT_CATEGORY_BITS,
  DEFAULT_MASK_BITS,
  KNOWN_FLAGS,
  KNOWN_FLAGS_V2,
  WORLD_MATERIAL,
  type BodyStore,
} from './body.js';
import { CACHE_ENTRY_BYTES, type WarmStartCache } from './contacts.js';
import { CCD_MODES, type WorldDef } from './def.js';
import type { SensorOverlaps } from './events.js';
import { WallKind, type StaticStore } from './statics.js';
import { WORLD_LIMITS, checkDef, show } from './validate.js';

const { ALIVE, ASLEEP, BOX, KINEMATIC, SENSOR } = BodyFlag;
const { SEGMENT, BOX: STATIC_BOX } = WallKind;

/** The first four bytes of a world snapshot: "FSPW" (0x57505346, little-endian u32). */
export const SNAPSHOT_MAGIC = 0x57505346;
/** The snapshot format of a world with no filter, sensor or sensor overlap (see the file comment). */
export const SNAPSHOT_VERSION = 1;
/** The snapshot format of a world with filters or sensors: version 1 and the filter section. */
export const SNAPSHOT_VERSION_FILTERS = 2;
/** The snapshot format of a world with materials: version 2 and the material columns. */
export const SNAPSHOT_VERSION_MATERIALS = 3;
/** Bytes per body slot of version 3's material columns. */
const MATERIAL_BYTES = 24;
/** Bytes per body slot of version 2's filter columns. */
const FILTER_BYTES = 12;
/** Bytes up to and including the wall count. */
const HEADER_BYTES = 122;
/** Offset of the wall count. */
const WALL_COUNT_AT = 118;
/** Bytes per wall: kind and 4 parameters. */
const WALL_BYTES = 33;
/** Bytes per body slot: flags, 8 f64 columns, island. */
const BODY_BYTES = 69;
/** f64 columns per body slot. */
const BODY_F64_COLUMNS = 8;

/** Whether typed arrays on this platform are little-endian (all JavaScript platforms in use). */
const LITTLE_ENDIAN = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;

/** What a snapshot holds. */
export interface WorldState {
  tick: number;
  def: Readonly<WorldDef>;
  statics: StaticStore;
  bodies: BodyStore;
  cache: WarmStartCache;
  overlaps: SensorOverlaps;
}

/**
 * Whether a world's snapshot has version 2's section: it has a filter, a sensor or a sensor
 * overlap, or it is version 3 (a body with a material).
 */
export function needsVersion2(bodies: BodyStore, overlaps: SensorOverlaps): boolean {
  return bodies.filteredCount + bodies.sensorCount + overlaps.count + bodies.materialCount > 0;
}

/** The version of a world's snapshot: 3 with materials, else 2 with filters or sensors, else 1. */
export function snapshotVersion(bodies: BodyStore, overlaps: SensorOverlaps): number {
  if (bodies.materialCount > 0) return SNAPSHOT_VERSION_MATERIALS;
  return needsVersion2(bodies, overlaps) ? SNAPSHOT_VERSION_FILTERS : SNAPSHOT_VERSION;
}

/**
 * Bytes of the snapshot of a world with these counts; `overlaps` is −1 for version 1, else the
 * sensor overlap count of version 2; `materials` for version 3.
 */
export function snapshotSize(
  walls: number,
  slots: number,
  cacheEntries: number,
  overlaps = -1,
  materials = false,
): number {
  return (
    HEADER_BYTES +
    WALL_BYTES * walls +
    4 +
    BODY_BYTES * slots +
    4 +
    CACHE_ENTRY_BYTES * cacheEntries +
    (overlaps < 0 ? 0 : FILTER_BYTES * slots + 4 + 8 * overlaps) +
    (materials ? MATERIAL_BYTES * slots : 0)
  );
}

/**
 * The snapshot through {@link ByteWriter}, value by value: the definition of the format that the
 * fast writer must match byte for byte (a test checks it on random worlds), and the path on a
 * big-endian platform.
 */
export function writeCanonical(w: ByteWriter, s: WorldState): void {
  const d = s.def;
  const version = snapshotVersion(s.bodies, s.overlaps);
  w.u32(SNAPSHOT_MAGIC).u32(version).f64(s.tick);
  w.f64(d.gravityX).f64(d.gravityY).f64(d.timeStep).f64(d.restitution);
  w.f64(d.restitutionThreshold).f64(d.friction).f64(d.linearSlop).f64(d.positionCorrection);
  w.f64(d.cellSize).f64(d.sleepSpeed).f64(d.timeToSleep);
  w.u32(d.velocityIterations).u32(d.positionIterations).u32(d.maxCcdIterations);
  w.u8(CCD_MODES.indexOf(d.ccd)).u8(d.enableSleep ? 1 : 0);
  const statics = s.statics;
  w.u32(statics.count);
  for (let k = 0; k < statics.count; k++) {
    w.u8(statics.kind[k]!);
    w.f64(statics.ax[k]!).f64(statics.ay[k]!).f64(statics.bx[k]!).f64(statics.by[k]!);
  }
  const b = s.bodies;
  const n = b.slotCount;
  w.u32(n);
  w.ints(b.flags.subarray(0, n));
  for (const column of [b.x, b.y, b.vx, b.vy, b.halfWidth, b.halfHeight, b.inverseMass, b.restTime])
    w.f64s(column.subarray(0, n));
  w.ints(b.island.subarray(0, n));
  const c = s.cache;
  const wc = c.count;
  w.u32(wc);
  w.ints(c.bodyA.subarray(0, wc));
  w.ints(c.bodyB.subarray(0, wc));
  w.f64s(c.normalImpulse.subarray(0, wc));
  w.f64s(c.tangentImpulse.subarray(0, wc));
  if (version === SNAPSHOT_VERSION) return;
  w.ints(b.categoryBits.subarray(0, n));
  w.ints(b.maskBits.subarray(0, n));
  w.ints(b.groupIndex.subarray(0, n));
  const o = s.overlaps;
  w.u32(o.count);
  w.ints(o.sensor.subarray(0, o.count));
  w.ints(o.visitor.subarray(0, o.count));
  if (version !== SNAPSHOT_VERSION_MATERIALS) return;
  w.f64s(b.friction.subarray(0, n));
  w.f64s(b.restitution.subarray(0, n));
  w.f64s(b.linearDamping.subarray(0, n));
}

/** Typed views of a whole buffer, made once per buffer (again if it was resized). */
interface BufferViews {
  byteLength: number;
  bytes: Uint8Array;
  data: DataView;
  f64: Float64Array;
  i32: Int32Array;
}

function viewsOf(buffer: ArrayBufferLike): BufferViews {
  return {
    byteLength: buffer.byteLength,
    bytes: new Uint8Array(buffer),
    data: new DataView(buffer),
    f64: new Float64Array(buffer, 0, buffer.byteLength >>> 3),
    i32: new Int32Array(buffer, 0, buffer.byteLength >>> 2),
  };
}

/** Writes snapshots into caller buffers without allocating (once warm). */
export class SnapshotWriter {
  /** Views of callers' buffers (a rollback ring reuses a few). */
  private readonly outViews = new WeakMap<ArrayBufferLike, BufferViews>();
  /** Byte views of the body columns for `viewSlots` slots, rebuilt when either changes. */
  private columnBytes: Uint8Array[] = [];
  private columnSources: (Float64Array | Int32Array | Uint8Array)[] = [];
  private viewSlots = -1;
  private reference: ByteWriter | null = null;

  private views(buffer: ArrayBufferLike): BufferViews {
    let v = this.outViews.get(buffer);
    if (v?.byteLength !== buffer.byteLength) {
      v = viewsOf(buffer);
      this.outViews.set(buffer, v);
    }
    return v;
  }

  private columns(b: BodyStore): Uint8Array[] {
    const src = this.columnSources;
    if (
      b.slotCount !== this.viewSlots ||
      src[0] !== b.flags ||
      src[1] !== b.x ||
      src[2] !== b.y ||
      src[3] !== b.vx ||
      src[4] !== b.vy ||
      src[5] !== b.halfWidth ||
      src[6] !== b.halfHeight ||
      src[7] !== b.inverseMass ||
      src[8] !== b.restTime ||
      src[9] !== b.island
    ) {
      const n = b.slotCount;
      this.columnSources = [
        b.flags,
        b.x,
        b.y,
        b.vx,
        b.vy,
        b.halfWidth,
        b.halfHeight,
        b.inverseMass,
        b.restTime,
        b.island,
      ];
      // A loop, not a closure: a closure here would make V8 allocate a context on every save.
      const bytes: Uint8Array[] = [];
      for (const a of this.columnSources)
        bytes.push(new Uint8Array(a.buffer, a.byteOffset, n * a.BYTES_PER_ELEMENT));
      this.columnBytes = bytes;
      this.viewSlots = n;
    }
    return this.columnBytes;
  }

  /** Writes the snapshot of `s` at the start of `out` (room checked by the caller); returns its length. */
  write(out: Uint8Array, s: WorldState): number {
    if (!LITTLE_ENDIAN) {
      const w = (this.reference ??= new ByteWriter(4096)).reset();
      writeCanonical(w, s);
      out.set(w.peek());
      return w.length;
    }
    const v = this.views(out.buffer);
    const data = v.data;
    const base = out.byteOffset;
    const d = s.def;
    const version = snapshotVersion(s.bodies, s.overlaps);
    let p = base;
    // Scalars through the DataView directly (V8 boxes a double passed to a helper it does not
    // inline), each `+ 0` so a −0 is written +0; the def and the walls never hold a NaN (checked).
    data.setUint32(p, SNAPSHOT_MAGIC, true);
    data.setUint32(p + 4, version, true);
    data.setFloat64(p + 8, s.tick + 0, true);
    p += 16;
    data.setFloat64(p, d.gravityX + 0, true);
    data.setFloat64(p + 8, d.gravityY + 0, true);
    data.setFloat64(p + 16, d.timeStep + 0, true);
    data.setFloat64(p + 24, d.restitution + 0, true);
    data.setFloat64(p + 32, d.restitutionThreshold + 0, true);
    data.setFloat64(p + 40, d.friction + 0, true);
    data.setFloat64(p + 48, d.linearSlop + 0, true);
    data.setFloat64(p + 56, d.positionCorrection + 0, true);
    data.setFloat64(p + 64, d.cellSize + 0, true);
    data.setFloat64(p + 72, d.sleepSpeed + 0, true);
    data.setFloat64(p + 80, d.timeToSleep + 0, true);
    p += 88;
    data.setUint32(p, d.velocityIterations, true);
    data.setUint32(p + 4, d.positionIterations, true);
    data.setUint32(p + 8, d.maxCcdIterations, true);
    data.setUint8(p + 12, CCD_MODES.indexOf(d.ccd));
    data.setUint8(p + 13, d.enableSleep ? 1 : 0);
    p += 14;
    const statics = s.statics;
    data.setUint32(p, statics.count, true);
    p += 4;
    for (let k = 0; k < statics.count; k++) {
      data.setUint8(p, statics.kind[k]!);
      data.setFloat64(p + 1, statics.ax[k]! + 0, true);
      data.setFloat64(p + 9, statics.ay[k]! + 0, true);
      data.setFloat64(p + 17, statics.bx[k]! + 0, true);
      data.setFloat64(p + 25, statics.by[k]! + 0, true);
      p += WALL_BYTES;
    }
    const b = s.bodies;
    data.setUint32(p, b.slotCount, true);
    p += 4;
    // The body columns: plain copies (the world keeps them canonical).
    const bytes = v.bytes;
    const columns = this.columns(b);
    for (let k = 0; k < columns.length; k++) {
      const column = columns[k]!;
      bytes.set(column, p);
      p += column.length;
    }
    // The warm-start entries: their count, then their columns, which the cache lays out as the
    // snapshot stores them.
    const c = s.cache;
    data.setUint32(p, c.count, true);
    p += 4;
    bytes.set(c.image, p);
    p += c.image.length;
    if (version !== SNAPSHOT_VERSION) p = writeVersion2(bytes, data, p, s);
    if (version === SNAPSHOT_VERSION_MATERIALS) p = writeMaterials(data, p, s.bodies);
    return p - base;
  }
}

/** Version 2's section at `p` (little-endian platform); returns where it ends. */
function writeVersion2(bytes: Uint8Array, data: DataView, p: number, s: WorldState): number {
  const b = s.bodies;
  const n = b.slotCount;
  // Byte views of the columns (three small objects per save, only in worlds with filters).
  for (const column of [b.categoryBits, b.maskBits, b.groupIndex]) {
    bytes.set(new Uint8Array(column.buffer, column.byteOffset, 4 * n), p);
    p += 4 * n;
  }
  const o = s.overlaps;
  data.setUint32(p, o.count, true);
  p += 4;
  for (let k = 0; k < o.count; k++) data.setInt32(p + 4 * k, o.sensor[k]!, true);
  p += 4 * o.count;
  for (let k = 0; k < o.count; k++) data.setInt32(p + 4 * k, o.visitor[k]!, true);
  return p + 4 * o.count;
}

/**
 * Version 3's material columns at `p` (any alignment: through the DataView, `+ 0` so a −0 is
 * written +0 — only worlds with materials pay); returns where they end.
 */
function writeMaterials(data: DataView, p: number, b: BodyStore): number {
  const n = b.slotCount;
  for (const column of [b.friction, b.restitution, b.linearDamping]) {
    for (let i = 0; i < n; i++) data.setFloat64(p + 8 * i, column[i]! + 0, true);
    p += 8 * n;
  }
  return p;
}

/** Swaps the byte order of `count` values of `width` bytes at `p` (a big-endian platform). */
function swapBytes(bytes: Uint8Array, p: number, count: number, width: number): void {
  for (let k = 0; k < count; k++) {
    const o = p + k * width;
    for (let a = o, z = o + width - 1; a < z; a++, z--) {
      const t = bytes[a]!;
      bytes[a] = bytes[z]!;
      bytes[z] = t;
    }
  }
}

/**
 * Reads snapshots in two stages: {@link read} checks everything and remembers where it is (in the
 * reader's staging buffer), changing nothing in the world; {@link commit} then copies it in.
 * Allocates nothing once its staging buffer is large enough and the def is unchanged.
 */
export class SnapshotReader {
  private staging = new Uint8Array(0);
  private views: BufferViews = viewsOf(new ArrayBuffer(0));
  /** Where {@link read} left off (a byte offset in staging) and where the bytes end. */
  private p = 0;
  private end = 0;
  /** Where the bytes start in staging. */
  private shift = 0;

  // What the last successful read found.
  tick = 0;
  def: Readonly<WorldDef> | null = null;
  private wallCount = 0;
  /** Byte offset of the first wall in staging. */
  private wallsAt = 0;
  /** Whether the walls are exactly the world's current ones. */
  private sameWalls = false;
  slots = 0;
  private liveCount = 0;
  private sleepingCount = 0;
  private flagsAt = 0;
  /** f64 index of the x column in staging (the other body columns follow, `slots` apart). */
  private columnsAt = 0;
  /** i32 index of the island column. */
  private islandAt = 0;
  private cacheCount = 0;
  /** i32 index of the cache's bodyA column (bodyB follows). */
  private cacheIdsAt = 0;
  /** f64 index of the cache's normal impulses (tangent impulses follow). */
  private cacheImpulsesAt = 0;
  /** Version 2: byte offset of the filter columns (−1 for version 1), the overlaps' count and offset. */
  private filtersAt = -1;
  private overlapCount = 0;
  private overlapsAt = 0;
  /** Version 3: byte offset of the material columns (−1 before version 3). */
  private materialsAt = -1;
  /** Whether a −0 was read (then values are copied one by one, with `+ 0`). */
  private negativeZero = false;
  // Views of the body columns in staging for the last slot count and offset (a rollback loop
  // loads the same shape every time: the views are made once, the columns copied at memcpy speed).
  private viewsBuffer: ArrayBufferLike | null = null;
  private viewsAt = -1;
  private viewsSlots = -1;
  private flagsView = new Uint8Array(0);
  private columnViews: Float64Array[] = [];
  private islandView = new Int32Array(0);

  private fail(message: string): never {
    throw new RangeError(`PhysicsWorld.load: ${message}`);
  }

  /** Fails unless `count` more bytes are there for `what` (`items` of them, if ≥ 0). */
  private need(count: number, what: string, items = -1): void {
    if (this.p + count > this.end)
      this.fail(
        `truncated snapshot: ${items >= 0 ? `${items} ` : ''}${what}: ${count} bytes needed at offset ${this.p - this.shift}, ${this.end - this.p} left`,
      );
  }

  private ensureStaging(size: number): void {
    if (this.staging.length >= size) return;
    this.staging = new Uint8Array(Math.max(size, 2 * this.staging.length));
    this.views = viewsOf(this.staging.buffer);
  }

  /**
   * Checks `bytes` completely against what the world accepts, changing nothing in the world.
   * Throws a RangeError naming the problem.
   */
  read(bytes: Uint8Array, current: WorldState): void {
    const length = bytes.length;
    // Place the bytes so the body columns land 8-byte aligned: their offset depends on the wall
    // and slot counts, read here byte by byte (they are checked again below).
    let shift = 0;
    if (length >= HEADER_BYTES) {
      const slotsAt = HEADER_BYTES + WALL_BYTES * u32At(bytes, WALL_COUNT_AT);
      if (slotsAt + 4 <= length) shift = (8 - ((slotsAt + 4 + u32At(bytes, slotsAt)) & 7)) & 7;
    }
    this.ensureStaging(length + shift + 16);
    const staging = this.staging;
    staging.set(bytes, shift);
    const { data, f64, i32 } = this.views;
    this.shift = shift;
    this.end = shift + length;
    this.p = shift;

    this.need(8, 'the header');
    if (data.getUint32(this.p, true) !== SNAPSHOT_MAGIC) this.fail('not a physics world snapshot');
    const version = data.getUint32(this.p + 4, true);
    if (
      version !== SNAPSHOT_VERSION &&
      version !== SNAPSHOT_VERSION_FILTERS &&
      version !== SNAPSHOT_VERSION_MATERIALS
    )
      this.fail(`unsupported snapshot version ${version} (this world reads versions 1, 2 and 3)`);
    this.p += 8;
    this.need(HEADER_BYTES - 8, 'the header');
    const tick = data.getFloat64(this.p, true);
    if (!(Number.isInteger(tick) && tick >= 0 && tick <= Number.MAX_SAFE_INTEGER))
      this.fail(`bad tick ${tick}`);
    this.p += 8;
    const def = this.readDef(data, this.p, current.def);
    this.p += 11 * 8 + 3 * 4 + 2;

    const wallCount = data.getUint32(this.p, true);
    this.p += 4;
    this.need(WALL_BYTES * wallCount, 'walls', wallCount);
    const wallsAt = this.p;
    const sameWalls = this.checkWalls(wallsAt, wallCount, current.statics);
    this.p += WALL_BYTES * wallCount;

    this.need(4, 'the body count');
    const slots = data.getUint32(this.p, true);
    this.p += 4;
    this.need(BODY_BYTES * slots + 4, 'bodies', slots);
    const flagsAt = this.p;
    this.p += slots;
    // Here p is 8-byte aligned (that is what the shift was for).
    const columnsAt = this.p >>> 3;
    this.p += 8 * BODY_F64_COLUMNS * slots;
    const islandAt = this.p >>> 2;
    this.p += 4 * slots;
    if (!LITTLE_ENDIAN) {
      swapBytes(staging, columnsAt * 8, BODY_F64_COLUMNS * slots, 8);
      swapBytes(staging, islandAt * 4, slots, 4);
    }
    this.checkBodies(
      staging,
      flagsAt,
      f64,
      columnsAt,
      i32,
      islandAt,
      slots,
      version === SNAPSHOT_VERSION ? KNOWN_FLAGS : KNOWN_FLAGS_V2,
    );

    const cacheCount = data.getUint32(this.p, true);
    this.p += 4;
    this.need(CACHE_ENTRY_BYTES * cacheCount, 'warm-start entries', cacheCount);
    // 4-byte aligned: the body columns end 8-aligned, then 4·slots + 4 bytes.
    const cacheIdsAt = this.p >>> 2;
    this.p += 8 * cacheCount;
    let impulsesAt = this.p;
    this.p += 16 * cacheCount;
    let filtersAt = -1;
    let overlapCount = 0;
    let overlapsAt = 0;
    let materialsAt = -1;
    if (version !== SNAPSHOT_VERSION) {
      this.need(FILTER_BYTES * slots + 4, 'filters', slots);
      filtersAt = this.p;
      this.p += FILTER_BYTES * slots;
      overlapCount = data.getUint32(this.p, true);
      this.p += 4;
      this.need(8 * overlapCount, 'sensor overlaps', overlapCount);
      overlapsAt = this.p;
      this.p += 8 * overlapCount;
      this.checkVersion2(
        staging,
        flagsAt,
        slots,
        filtersAt,
        overlapsAt,
        overlapCount,
        version === SNAPSHOT_VERSION_FILTERS,
      );
    }
    if (version === SNAPSHOT_VERSION_MATERIALS) {
      this.need(MATERIAL_BYTES * slots, 'materials', slots);
      materialsAt = this.p;
      this.p += MATERIAL_BYTES * slots;
      this.checkMaterials(staging, flagsAt, slots, materialsAt);
    }
    if (this.p !== this.end) this.fail(`${this.end - this.p} bytes after the end of the snapshot`);
    if ((impulsesAt & 7) !== 0) {
      // Move the impulse columns 4 bytes on, to an 8-byte boundary (staging has the room), and
      // the sections after them with them: moving the impulses alone overwrote the first 4 bytes
      // of version 2's filter columns (body 0's categoryBits) whenever the slot count was even.
      staging.copyWithin(impulsesAt + 4, impulsesAt, this.end);
      impulsesAt += 4;
      if (filtersAt >= 0) filtersAt += 4;
      overlapsAt += 4;
      if (materialsAt >= 0) materialsAt += 4;
    }
    if (!LITTLE_ENDIAN) {
      swapBytes(staging, cacheIdsAt * 4, 2 * cacheCount, 4);
      swapBytes(staging, impulsesAt, 2 * cacheCount, 8);
    }
    const cacheImpulsesAt = impulsesAt >>> 3;
    this.checkCache(
      staging,
      flagsAt,
      slots,
      wallCount,
      i32,
      cacheIdsAt,
      f64,
      cacheImpulsesAt,
      cacheCount,
    );

    this.tick = tick;
    this.def = def;
    this.wallCount = wallCount;
    this.wallsAt = wallsAt;
    this.sameWalls = sameWalls;
    this.slots = slots;
    this.flagsAt = flagsAt;
    this.columnsAt = columnsAt;
    this.islandAt = islandAt;
    this.cacheCount = cacheCount;
    this.cacheIdsAt = cacheIdsAt;
    this.cacheImpulsesAt = cacheImpulsesAt;
    this.filtersAt = filtersAt;
    this.overlapCount = overlapCount;
    this.overlapsAt = overlapsAt;
    this.materialsAt = materialsAt;
  }

  /**
   * Version 2's section: a free slot's filter all 0; each overlap a sensor and a live body that is
   * not one, in strictly ascending order; and something that needs version 2 (else it is not
   * canonical). Reads through the DataView (the section may sit at any offset).
   */
  private checkVersion2(
    staging: Uint8Array,
    flagsAt: number,
    n: number,
    at: number,
    overlapsAt: number,
    count: number,
    mustBeNeeded: boolean,
  ): void {
    const data = this.views.data;
    let needed = count > 0;
    for (let i = 0; i < n; i++) {
      const f = staging[flagsAt + i]!;
      const category = data.getUint32(at + 4 * i, true);
      const mask = data.getUint32(at + 4 * (n + i), true);
      const group = data.getInt32(at + 4 * (2 * n + i), true);
      if (f === 0) {
        if (category !== 0 || mask !== 0 || group !== 0)
          this.fail(`body ${i}: a free slot's filter must be all zeros`);
        continue;
      }
      if (
        (f & SENSOR) !== 0 ||
        category !== DEFAULT_CATEGORY_BITS ||
        mask !== DEFAULT_MASK_BITS ||
        group !== 0
      )
        needed = true;
    }
    let lastSensor = -1;
    let lastVisitor = -1;
    for (let k = 0; k < count; k++) {
      const s = data.getInt32(overlapsAt + 4 * k, true);
      const v = data.getInt32(overlapsAt + 4 * (count + k), true);
      const fs = s >= 0 && s < n ? staging[flagsAt + s]! : 0;
      const fv = v >= 0 && v < n ? staging[flagsAt + v]! : 0;
      if (!((fs & SENSOR) !== 0 && fv !== 0 && (fv & SENSOR) === 0))
        this.fail(
          `sensor overlap ${k}: ${s} must be a sensor and ${v} a live body that is not one`,
        );
      if (!(s > lastSensor || (s === lastSensor && v > lastVisitor)))
        this.fail(`sensor overlap ${k}: not in ascending order (not canonical)`);
      lastSensor = s;
      lastVisitor = v;
    }
    if (mustBeNeeded && !needed)
      this.fail(
        'a version 2 snapshot with no filter, sensor or sensor overlap (not canonical: that is version 1)',
      );
  }

  /**
   * Version 3's materials: a free slot's all 0; a live body's friction −1 (the world's) or finite
   * ≥ 0, restitution −1 or in [0, 1], linear damping finite ≥ 0; and some live body's not the
   * default (else it is not canonical).
   */
  private checkMaterials(staging: Uint8Array, flagsAt: number, n: number, at: number): void {
    const data = this.views.data;
    let needed = false;
    for (let i = 0; i < n; i++) {
      const f = data.getFloat64(at + 8 * i, true);
      const e = data.getFloat64(at + 8 * (n + i), true);
      const c = data.getFloat64(at + 8 * (2 * n + i), true);
      if (staging[flagsAt + i] === 0) {
        if (f !== 0 || e !== 0 || c !== 0)
          this.fail(`body ${i}: a free slot's material must be all zeros`);
        continue;
      }
      if (!(f === WORLD_MATERIAL || (f >= 0 && f < Infinity)))
        this.fail(`body ${i}: friction must be -1 (the world's) or finite and ≥ 0, got ${show(f)}`);
      if (!(e === WORLD_MATERIAL || (e >= 0 && e <= 1)))
        this.fail(`body ${i}: restitution must be -1 (the world's) or in [0, 1], got ${show(e)}`);
      if (!(c >= 0 && c < Infinity))
        this.fail(`body ${i}: linearDamping must be finite and ≥ 0, got ${show(c)}`);
      if (f !== WORLD_MATERIAL || e !== WORLD_MATERIAL || c !== 0) needed = true;
    }
    if (!needed)
      this.fail(
        'a version 3 snapshot whose materials are all the default (not canonical: that is version 1 or 2)',
      );
  }

  /**
   * The walls at byte `at`: a known kind, coordinates within ±1e9 m, a box's half extents in
   * (0, 1e9]. Returns whether they are exactly `current`'s. (The values stay local: passing
   * doubles to a call V8 does not inline boxes each of them.)
   */
  private checkWalls(at: number, count: number, current: StaticStore): boolean {
    const staging = this.staging;
    const data = this.views.data;
    const m = WORLD_LIMITS.maxCoordinate;
    let same = count === current.count;
    for (let s = 0, p = at; s < count; s++, p += WALL_BYTES) {
      const kind = staging[p]!;
      if (kind !== SEGMENT && kind !== STATIC_BOX) this.fail(`bad kind ${kind} of static ${s}`);
      const segment = kind === SEGMENT;
      const p0 = data.getFloat64(p + 1, true);
      const p1 = data.getFloat64(p + 9, true);
      const p2 = data.getFloat64(p + 17, true);
      const p3 = data.getFloat64(p + 25, true);
      const bad = !(p0 >= -m && p0 <= m)
        ? 0
        : !(p1 >= -m && p1 <= m)
          ? 1
          : !(segment ? p2 >= -m && p2 <= m : p2 > 0 && p2 <= m)
            ? 2
            : !(segment ? p3 >= -m && p3 <= m : p3 > 0 && p3 <= m)
              ? 3
              : -1;
      if (bad !== -1) {
        const names = segment ? ['ax', 'ay', 'bx', 'by'] : ['x', 'y', 'halfWidth', 'halfHeight'];
        const rule =
          !segment && bad >= 2
            ? 'a number > 0 and at most 1e9'
            : 'a finite number from -1e9 to 1e9';
        this.fail(
          `static ${s}: ${names[bad]!} must be ${rule}, got ${show([p0, p1, p2, p3][bad])}`,
        );
      }
      if (same)
        same =
          current.kind[s] === kind &&
          current.ax[s] === p0 &&
          current.ay[s] === p1 &&
          current.bx[s] === p2 &&
          current.by[s] === p3;
    }
    return same;
  }

  /** The def at `p`: the world's own object when nothing differs (no allocation), else a checked one. */
  private readDef(data: DataView, p: number, current: Readonly<WorldDef>): Readonly<WorldDef> {
    const modeIndex = data.getUint8(p + 100);
    const sleep = data.getUint8(p + 101);
    const mode = CCD_MODES[modeIndex];
    if (mode === undefined) this.fail(`bad ccd mode ${modeIndex}`);
    if (sleep > 1) this.fail(`bad enableSleep ${sleep}`);
    if (
      data.getFloat64(p, true) === current.gravityX &&
      data.getFloat64(p + 8, true) === current.gravityY &&
      data.getFloat64(p + 16, true) === current.timeStep &&
      data.getFloat64(p + 24, true) === current.restitution &&
      data.getFloat64(p + 32, true) === current.restitutionThreshold &&
      data.getFloat64(p + 40, true) === current.friction &&
      data.getFloat64(p + 48, true) === current.linearSlop &&
      data.getFloat64(p + 56, true) === current.positionCorrection &&
      data.getFloat64(p + 64, true) === current.cellSize &&
      data.getFloat64(p + 72, true) === current.sleepSpeed &&
      data.getFloat64(p + 80, true) === current.timeToSleep &&
      data.getUint32(p + 88, true) === current.velocityIterations &&
      data.getUint32(p + 92, true) === current.positionIterations &&
      data.getUint32(p + 96, true) === current.maxCcdIterations &&
      mode === current.ccd &&
      (sleep === 1) === current.enableSleep
    )
      return current;
    return checkDef('PhysicsWorld.load', {
      gravityX: data.getFloat64(p, true) + 0,
      gravityY: data.getFloat64(p + 8, true) + 0,
      timeStep: data.getFloat64(p + 16, true) + 0,
      restitution: data.getFloat64(p + 24, true) + 0,
      restitutionThreshold: data.getFloat64(p + 32, true) + 0,
      friction: data.getFloat64(p + 40, true) + 0,
      linearSlop: data.getFloat64(p + 48, true) + 0,
      positionCorrection: data.getFloat64(p + 56, true) + 0,
      cellSize: data.getFloat64(p + 64, true) + 0,
      sleepSpeed: data.getFloat64(p + 72, true) + 0,
      timeToSleep: data.getFloat64(p + 80, true) + 0,
      velocityIterations: data.getUint32(p + 88, true),
      positionIterations: data.getUint32(p + 92, true),
      maxCcdIterations: data.getUint32(p + 96, true),
      ccd: mode,
      enableSleep: sleep === 1,
      maxContacts: current.maxContacts,
    });
  }

  /**
   * Every body slot: flags; a free slot all zeros; a live one with finite position and velocity,
   * sizes within the limits (a circle's two equal), an inverse mass that is 0 exactly for a
   * kinematic body and otherwise comes from a density within the limits, a finite rest time ≥ 0,
   * an island only while asleep. Counts the live and sleeping bodies.
   */
  private checkBodies(
    staging: Uint8Array,
    flagsAt: number,
    f64: Float64Array,
    at: number,
    i32: Int32Array,
    islandAt: number,
    n: number,
    knownFlags: number,
  ): void {
    const minSize = WORLD_LIMITS.minSize;
    const maxSize = WORLD_LIMITS.maxSize;
    // inverseMass × area is 1/density: allow the limits a relative 1e-9 for rounding.
    const minInvDensity = (1 / WORLD_LIMITS.maxDensity) * (1 - 1e-9);
    const maxInvDensity = (1 / WORLD_LIMITS.minDensity) * (1 + 1e-9);
    let live = 0;
    let sleeping = 0;
    let negativeZero = false;
    for (let i = 0; i < n; i++) {
      const f = staging[flagsAt + i]!;
      const x = f64[at + i]!;
      const y = f64[at + n + i]!;
      const vx = f64[at + 2 * n + i]!;
      const vy = f64[at + 3 * n + i]!;
      const w = f64[at + 4 * n + i]!;
      const h = f64[at + 5 * n + i]!;
      const im = f64[at + 6 * n + i]!;
      const rest = f64[at + 7 * n + i]!;
      const island = i32[islandAt + i]!;
      if (f === 0) {
        if (
          x !== 0 ||
          y !== 0 ||
          vx !== 0 ||
          vy !== 0 ||
          w !== 0 ||
          h !== 0 ||
          im !== 0 ||
          rest !== 0 ||
          island !== 0
        )
          this.fail(`body ${i}: a free slot must be all zeros`);
        if (1 / x < 0 || 1 / y < 0 || 1 / vx < 0 || 1 / vy < 0 || 1 / rest < 0) negativeZero = true;
        continue;
      }
      if (
        (f & ~knownFlags) !== 0 ||
        (f & ALIVE) === 0 ||
        (f & (ASLEEP | KINEMATIC)) === (ASLEEP | KINEMATIC)
      )
        this.fail(`bad flags ${f} for body ${i}`);
      live++;
      if (
        (x === 0 && 1 / x < 0) ||
        (y === 0 && 1 / y < 0) ||
        (vx === 0 && 1 / vx < 0) ||
        (vy === 0 && 1 / vy < 0) ||
        (rest === 0 && 1 / rest < 0)
      )
        negativeZero = true;
      if (!(x - x === 0 && y - y === 0 && vx - vx === 0 && vy - vy === 0)) {
        const field = x - x !== 0 ? 'x' : y - y !== 0 ? 'y' : vx - vx !== 0 ? 'vx' : 'vy';
        const value = field === 'x' ? x : field === 'y' ? y : field === 'vx' ? vx : vy;
        this.fail(`body ${i}: ${field} must be finite, got ${show(value)}`);
      }
      if (!(w >= minSize && w <= maxSize && h >= minSize && h <= maxSize))
        this.fail(
          `body ${i}: halfWidth and halfHeight must be from 1e-6 to 1e6, got ${show(w)}, ${show(h)}`,
        );
      const box = (f & BOX) !== 0;
      if (!box && w !== h)
        this.fail(`body ${i}: a circle's halfWidth ${w} and halfHeight ${h} differ`);
      if ((f & KINEMATIC) !== 0) {
        if (im !== 0)
          this.fail(`body ${i}: a kinematic body's inverseMass must be 0, got ${show(im)}`);
      } else {
        const invDensity = im * (box ? 4 * w * h : Math.PI * w * w);
        if (!(invDensity >= minInvDensity && invDensity <= maxInvDensity))
          this.fail(
            `body ${i}: inverseMass ${show(im)} is not 1/(density × area) for a density from 1e-6 to 1e6`,
          );
      }
      if (!(rest >= 0 && rest < Infinity))
        this.fail(`body ${i}: restTime must be finite and ≥ 0, got ${show(rest)}`);
      if ((f & ASLEEP) !== 0) {
        sleeping++;
        if (!(island >= 0 && island < n)) this.fail(`body ${i}: bad island ${island}`);
      } else if (island !== 0)
        this.fail(`body ${i}: an awake body's island must be 0, got ${island}`);
    }
    if (n > 0 && staging[flagsAt + n - 1] === 0) this.fail('trailing free slot (not canonical)');
    this.liveCount = live;
    this.sleepingCount = sleeping;
    this.negativeZero = negativeZero;
  }

  /** Every warm-start entry: a live body, and a live body of higher id or a wall; finite impulses, the normal one ≥ 0. */
  private checkCache(
    staging: Uint8Array,
    flagsAt: number,
    n: number,
    walls: number,
    i32: Int32Array,
    idsAt: number,
    f64: Float64Array,
    impulsesAt: number,
    count: number,
  ): void {
    for (let k = 0; k < count; k++) {
      const a = i32[idsAt + k]!;
      const b = i32[idsAt + count + k]!;
      const jn = f64[impulsesAt + k]!;
      const jt = f64[impulsesAt + count + k]!;
      if (!(
        a >= 0 &&
        a < n &&
        staging[flagsAt + a] !== 0 &&
        (b < 0 ? -1 - b < walls : b > a && b < n && staging[flagsAt + b] !== 0)
      ))
        this.fail(`bad contact cache entry ${k}`);
      if ((jn === 0 && 1 / jn < 0) || (jt === 0 && 1 / jt < 0)) this.negativeZero = true;
      if (!(jn >= 0 && jn < Infinity && jt - jt === 0))
        this.fail(
          `contact cache entry ${k}: impulses must be finite (normal ≥ 0), got ${show(jn)}, ${show(jt)}`,
        );
    }
  }

  /**
   * The filters and sensor overlaps: version 2's, or the defaults (version 1). Leaves free slots
   * (up to `previous`, the slots in use before) all zeros.
   */
  private commitVersion2(bodies: BodyStore, overlaps: SensorOverlaps, previous: number): void {
    const n = this.slots;
    const flags = bodies.flags;
    const category = bodies.categoryBits;
    const mask = bodies.maskBits;
    const group = bodies.groupIndex;
    const at = this.filtersAt;
    if (at < 0) {
      // Fills, then zeros for the free slots (usually none): a rollback loads at copy speed.
      category.fill(DEFAULT_CATEGORY_BITS, 0, n);
      mask.fill(DEFAULT_MASK_BITS, 0, n);
      group.fill(0, 0, n);
      if (this.liveCount < n)
        for (let i = 0; i < n; i++) {
          if (flags[i] !== 0) continue;
          category[i] = 0;
          mask[i] = 0;
        }
      overlaps.setCount(0);
    } else {
      const data = this.views.data;
      for (let i = 0; i < n; i++) {
        category[i] = data.getUint32(at + 4 * i, true);
        mask[i] = data.getUint32(at + 4 * (n + i), true);
        group[i] = data.getInt32(at + 4 * (2 * n + i), true);
      }
      const count = this.overlapCount;
      overlaps.setCount(count);
      const p = this.overlapsAt;
      for (let k = 0; k < count; k++) {
        overlaps.sensor[k] = data.getInt32(p + 4 * k, true);
        overlaps.visitor[k] = data.getInt32(p + 4 * (count + k), true);
      }
    }
    if (previous > n) {
      category.fill(0, n, previous);
      mask.fill(0, n, previous);
      group.fill(0, n, previous);
    }
    if (at < 0) {
      bodies.filteredCount = 0;
      bodies.sensorCount = 0;
      bodies.materialCount = 0;
    } else bodies.recountFeatures();
  }

  /** The materials: version 3's, or the defaults. Leaves free slots (up to `previous`) all zeros. */
  private commitMaterials(bodies: BodyStore, previous: number): void {
    const n = this.slots;
    const friction = bodies.friction;
    const restitution = bodies.restitution;
    const damping = bodies.linearDamping;
    const at = this.materialsAt;
    if (at < 0) {
      friction.fill(WORLD_MATERIAL, 0, n);
      restitution.fill(WORLD_MATERIAL, 0, n);
      damping.fill(0, 0, n);
      if (this.liveCount < n) {
        const flags = bodies.flags;
        for (let i = 0; i < n; i++) {
          if (flags[i] !== 0) continue;
          friction[i] = 0;
          restitution[i] = 0;
        }
      }
    } else {
      const data = this.views.data;
      for (let i = 0; i < n; i++) {
        friction[i] = data.getFloat64(at + 8 * i, true) + 0;
        restitution[i] = data.getFloat64(at + 8 * (n + i), true) + 0;
        damping[i] = data.getFloat64(at + 8 * (2 * n + i), true) + 0;
      }
    }
    if (previous > n) {
      friction.fill(0, n, previous);
      restitution.fill(0, n, previous);
      damping.fill(0, n, previous);
    }
  }

  /** Views of the body columns in staging, made again only when their place or size changed. */
  private makeViews(): void {
    const buffer = this.staging.buffer;
    const n = this.slots;
    const at = this.columnsAt;
    if (buffer === this.viewsBuffer && at === this.viewsAt && n === this.viewsSlots) return;
    this.flagsView = new Uint8Array(buffer, this.flagsAt, n);
    // A loop, not a closure: a closure here would make V8 allocate a context on every call.
    const views: Float64Array[] = [];
    for (let c = 0; c < BODY_F64_COLUMNS; c++)
      views.push(new Float64Array(buffer, 8 * (at + c * n), n));
    this.columnViews = views;
    this.islandView = new Int32Array(buffer, 4 * this.islandAt, n);
    this.viewsBuffer = buffer;
    this.viewsAt = at;
    this.viewsSlots = n;
  }

  /**
   * Puts what {@link read} checked into the world's stores; the caller has made room for
   * {@link slots} bodies. Values are copied with `+ 0`, so a −0 in the bytes becomes +0.
   */
  commit(
    bodies: BodyStore,
    statics: StaticStore,
    cache: WarmStartCache,
    overlaps: SensorOverlaps,
  ): void {
    const staging = this.staging;
    const { data, f64, i32 } = this.views;
    if (!this.sameWalls) {
      statics.clear();
      for (let s = 0, p = this.wallsAt; s < this.wallCount; s++, p += WALL_BYTES) {
        statics.add(
          staging[p]!,
          data.getFloat64(p + 1, true) + 0,
          data.getFloat64(p + 9, true) + 0,
          data.getFloat64(p + 17, true) + 0,
          data.getFloat64(p + 25, true) + 0,
        );
      }
    }
    const n = this.slots;
    const previous = bodies.slotCount;
    const flags = bodies.flags;
    const island = bodies.island;
    const at = this.columnsAt;
    if (this.negativeZero) {
      for (let i = 0; i < n; i++) flags[i] = staging[this.flagsAt + i]!;
      copyColumn(bodies.x, f64, at, n);
      copyColumn(bodies.y, f64, at + n, n);
      copyColumn(bodies.vx, f64, at + 2 * n, n);
      copyColumn(bodies.vy, f64, at + 3 * n, n);
      copyColumn(bodies.halfWidth, f64, at + 4 * n, n);
      copyColumn(bodies.halfHeight, f64, at + 5 * n, n);
      copyColumn(bodies.inverseMass, f64, at + 6 * n, n);
      copyColumn(bodies.restTime, f64, at + 7 * n, n);
      for (let i = 0; i < n; i++) island[i] = i32[this.islandAt + i]!;
    } else {
      this.makeViews();
      flags.set(this.flagsView);
      const views = this.columnViews;
      bodies.x.set(views[0]!);
      bodies.y.set(views[1]!);
      bodies.vx.set(views[2]!);
      bodies.vy.set(views[3]!);
      bodies.halfWidth.set(views[4]!);
      bodies.halfHeight.set(views[5]!);
      bodies.inverseMass.set(views[6]!);
      bodies.restTime.set(views[7]!);
      island.set(this.islandView);
    }
    if (previous > n) {
      flags.fill(0, n, previous);
      island.fill(0, n, previous);
      bodies.x.fill(0, n, previous);
      bodies.y.fill(0, n, previous);
      bodies.vx.fill(0, n, previous);
      bodies.vy.fill(0, n, previous);
      bodies.halfWidth.fill(0, n, previous);
      bodies.halfHeight.fill(0, n, previous);
      bodies.inverseMass.fill(0, n, previous);
      bodies.restTime.fill(0, n, previous);
    }
    bodies.slotCount = n;
    bodies.liveCount = this.liveCount;
    bodies.sleepingCount = this.sleepingCount;
    bodies.recomputeExtents();
    this.commitMaterials(bodies, previous);
    this.commitVersion2(bodies, overlaps, previous);

    const count = this.cacheCount;
    cache.resize(count);
    const ids = this.cacheIdsAt;
    const impulses = this.cacheImpulsesAt;
    const bodyA = cache.bodyA;
    const bodyB = cache.bodyB;
    const normal = cache.normalImpulse;
    const tangent = cache.tangentImpulse;
    // Value by value: copying whole columns with `set` of subarray views of staging takes
    // ~0.8x the time of load() at 2,000 bodies, but makes four views (384 B) per load; this way a
    // load allocates only when the entry count changes (the cache's own views, in resize).
    for (let k = 0; k < count; k++) {
      bodyA[k] = i32[ids + k]!;
      bodyB[k] = i32[ids + count + k]!;
      normal[k] = f64[impulses + k]! + 0;
      tangent[k] = f64[impulses + count + k]! + 0;
    }
    cache.changed();
  }
}

/** `dst[0, n) = src[at, at + n) + 0` (−0 becomes +0). */

function copyColumn(dst: Float64Array, src: Float64Array, at: number, n: number): void {
  for (let i = 0; i < n; i++) dst[i] = src[at + i]! + 0;
}

function u32At(bytes: Uint8Array, p: number): number {
  return (bytes[p]! | (bytes[p + 1]! << 8) | (bytes[p + 2]! << 16) | (bytes[p + 3]! << 24)) >>> 0;
}
