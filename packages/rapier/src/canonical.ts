/**
 * The canonical state of a Rapier world: the bytes a {@link RapierSimulation}'s `hash()` is the
 * FNV-1a 64 of, and what the cross-engine determinism suite compares tick by tick.
 *
 * Why not hash Rapier's own snapshot (`world.takeSnapshot()`)? Its bytes are a bincode dump of
 * Rapier's internals — arenas with their free lists, the broad phase's tree, contact graphs,
 * solver caches, island bookkeeping — whose layout is Rapier's business and changes between
 * versions; two worlds that are the same to a player (same bodies where they are, moving as they
 * move) need not have equal snapshot bytes, and a snapshot says nothing a person can read when
 * two engines disagree. This encoding is small, documented, has one representation per state
 * (`ByteWriter`: little-endian, −0 as +0, one NaN) and names every value. The snapshot still
 * travels in `save()`, so `load()` restores everything Rapier needs.
 *
 * Layout (little-endian):
 *
 * | bytes | field |
 * |---|---|
 * | u32 | tick |
 * | u32 + n | user state: its length, then its bytes (the scene's `saveState`) |
 * | 4 × u32 | rigid bodies, colliders, impulse joints, multibody joints |
 * | per body, in handle order: | |
 * | u32, u32 | handle: arena index, generation |
 * | u8 | body type (0 dynamic, 1 fixed, 2 kinematic position, 3 kinematic velocity) + 4 if asleep |
 * | 6 × f64 | x, y (m), angle (rad), vx, vy (m/s), ω (rad/s) — Rapier's f32 values, exact |
 *
 * Handle order: Rapier keeps bodies in an arena and iterates it by index, so `forEach` visits
 * them in ascending index whatever order they were created or removed in.
 */
import { ByteWriter } from 'fixedstep';
import type { World } from '@dimforge/rapier2d-deterministic-compat';

/** Bytes per body in the canonical state. */
export const BODY_BYTES = 4 + 4 + 1 + 6 * 8;

/** Bytes before the first body, for a user state of `userBytes` bytes. */
export function headerBytes(userBytes: number): number {
  return 4 + 4 + userBytes + 4 * 4;
}

const handleView = new DataView(new ArrayBuffer(8));

/**
 * A Rapier handle is a float64 whose bits are the arena index (low 32) and generation (high 32).
 * Writes them as two u32s (the float itself is usually a subnormal, and could even be a NaN).
 */
export function splitHandle(handle: number): [index: number, generation: number] {
  handleView.setFloat64(0, handle, true);
  return [handleView.getUint32(0, true), handleView.getUint32(4, true)];
}

const scratch = { x: 0, y: 0 };

/** Appends the canonical state of `world` at `tick` with user state `user` to `w`. */
export function writeCanonicalState(
  w: ByteWriter,
  world: World,
  tick: number,
  user: Uint8Array,
): ByteWriter {
  w.u32(tick).u32(user.length).bytes(user);
  w.u32(world.bodies.len())
    .u32(world.colliders.len())
    .u32(world.impulseJoints.len())
    .u32(world.multibodyJoints.len());
  world.bodies.forEach((body) => {
    handleView.setFloat64(0, body.handle, true);
    w.u32(handleView.getUint32(0, true)).u32(handleView.getUint32(4, true));
    w.u8((body.bodyType() & 3) | (body.isSleeping() ? 4 : 0));
    const p = body.translation(scratch);
    w.f64(p.x).f64(p.y).f64(body.rotation());
    const v = body.linvel(scratch);
    w.f64(v.x).f64(v.y).f64(body.angvel());
  });
  return w;
}

/** One named field of a canonical state (the shape of `@fixedstep/games`'s `StateField`). */
export interface CanonicalField {
  readonly offset: number;
  readonly type: 'u8' | 'u32' | 'f64';
  readonly name: string;
}

const BODY_FIELDS = ['x', 'y', 'angle', 'vx', 'vy', 'angvel'] as const;

/**
 * Names every field of a canonical state, in offset order, read from the bytes themselves
 * (`body[12].vy`, `user[3]`, …); undefined if the bytes are not a whole canonical state. The
 * determinism suite uses it to say which value two engines disagree on.
 */
export function canonicalFields(bytes: Uint8Array): CanonicalField[] | undefined {
  if (bytes.length < 8) return undefined;
  const v = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const userBytes = v.getUint32(4, true);
  const head = headerBytes(userBytes);
  if (head > bytes.length) return undefined;
  const bodies = v.getUint32(8 + userBytes, true);
  if (head + bodies * BODY_BYTES !== bytes.length) return undefined;
  const out: CanonicalField[] = [
    { offset: 0, type: 'u32', name: 'tick' },
    { offset: 4, type: 'u32', name: 'user state length' },
  ];
  for (let i = 0; i < userBytes; i++) out.push({ offset: 8 + i, type: 'u8', name: `user[${i}]` });
  let at = 8 + userBytes;
  for (const name of ['bodies', 'colliders', 'impulse joints', 'multibody joints']) {
    out.push({ offset: at, type: 'u32', name: `count of ${name}` });
    at += 4;
  }
  for (let b = 0; b < bodies; b++) {
    const index = v.getUint32(at, true);
    const gen = v.getUint32(at + 4, true);
    const label = gen === 0 ? `body[${index}]` : `body[${index} gen ${gen}]`;
    out.push({ offset: at, type: 'u32', name: `${label}.index` });
    out.push({ offset: at + 4, type: 'u32', name: `${label}.generation` });
    out.push({ offset: at + 8, type: 'u8', name: `${label}.type+asleep` });
    at += 9;
    for (const f of BODY_FIELDS) {
      out.push({ offset: at, type: 'f64', name: `${label}.${f}` });
      at += 8;
    }
  }
  return out;
}
