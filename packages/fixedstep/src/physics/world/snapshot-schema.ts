/**
 * The world's snapshot as a state schema (`defineStateSchema`), for state sync: the columns of
 * `snapshot.ts`'s format (version 1), with bodies' positions, velocities and rest times quantised
 * (a sleeping body's island and rest time go with its flags: the world checks they agree), and the
 * solver's warm-start cache kept local — each side keeps its own, a client's from its prediction.
 * It describes version 1, the snapshot of a world without filters or sensors (a world that uses
 * them writes version 2, which it refuses with a message naming the extra bytes).
 * @module
 */
import type { StateColumn } from '../../sim/state-schema.js';

/** Options of {@link worldStateColumns}. */
export interface WorldStateSchemaOptions {
  /** Position precision, metres. Default 1/512 (Fiedler's). */
  position?: number;
  /** Velocity precision, m/s. Default 1/64. */
  velocity?: number;
  /**
   * `'sent'` (default): velocities are sent, and positions predicted from them. `'local'`: as
   * Glenn Fiedler sends his cubes — positions only, each predicted from the two snapshots before
   * (`extrapolate`); each side keeps its own velocities and rest timers (a client's come from its
   * prediction; sleep flags are still sent), so
   * a client that renders snapshots needs none, and one that steps ahead of them starts from its
   * own. Sent bytes fall by about half when every body moves.
   */
  velocities?: 'sent' | 'local';
  /** Largest |x|, |y|, metres. Default 1000. */
  extent?: number;
  /** Largest |vx|, |vy|, m/s. Default 200. */
  maxSpeed?: number;
  /** Most body slots. Default 8192. */
  maxBodies?: number;
  /** Most static shapes. Default 4096. */
  maxStatics?: number;
  /** Most warm-start entries. Default 65536. */
  maxContacts?: number;
  /** A prefix for the column names (to put a world in a larger state). Default none. */
  prefix?: string;
}

/**
 * The columns of a world's snapshot (`PhysicsWorld.save()`): put them in a game's schema where its
 * `save()` writes the world, or use them alone when the world is the state.
 */
export function worldStateColumns(o: WorldStateSchemaOptions = {}): StateColumn[] {
  const p = o.prefix ?? '';
  const pos = o.position ?? 1 / 512;
  const vel = o.velocity ?? 1 / 64;
  const extent = o.extent ?? 1000;
  const velocities: unknown = o.velocities ?? 'sent';
  if (velocities !== 'sent' && velocities !== 'local') {
    throw new RangeError(`worldStateColumns: velocities must be 'sent' or 'local'`);
  }
  const local = velocities === 'local';
  const speed = o.maxSpeed ?? 200;
  const bodies = { of: `${p}slots`, max: o.maxBodies ?? 8192 };
  const contacts = { of: `${p}contacts`, max: o.maxContacts ?? 65536 };
  const g = `${p}bodies`;
  const head = `${p}head`;
  const raw = (name: string, type: StateColumn['type'], count = 1): StateColumn => ({
    name: `${p}${name}`,
    type,
    count,
    group: count === 1 ? head : `${p}${name}`,
  });
  return [
    raw('magic', 'u32'),
    raw('version', 'u32'),
    // The tick (an integer in an f64): sent as itself.
    { name: `${p}tick`, type: 'f64', group: head, precision: 1, min: 0, max: 2147483647 },
    raw('def', 'f64', 11),
    raw('iterations', 'u32', 3),
    raw('ccd', 'u8'),
    raw('enableSleep', 'u8'),
    { name: `${p}statics`, type: 'u32', local: true, group: `${p}local` },
    {
      name: `${p}staticBytes`,
      type: 'u8',
      count: { of: `${p}statics`, times: 33, max: (o.maxStatics ?? 4096) * 33 },
      local: true,
      group: `${p}local`,
    },
    raw('slots', 'u32'),
    { name: `${p}flags`, type: 'u8', count: bodies, group: g },
    ...(['x', 'y'] as const).map((name): StateColumn => ({
      name: `${p}${name}`,
      type: 'f64',
      count: bodies,
      group: g,
      precision: pos,
      min: -extent,
      max: extent,
      ...(local ? { extrapolate: true } : { rate: `${p}v${name}` }),
    })),
    ...(['vx', 'vy'] as const).map((name): StateColumn =>
      local
        ? { name: `${p}${name}`, type: 'f64', count: bodies, local: true, group: `${p}velocities` }
        : {
            name: `${p}${name}`,
            type: 'f64',
            count: bodies,
            group: g,
            precision: vel,
            min: -speed,
            max: speed,
          },
    ),
    { name: `${p}halfWidth`, type: 'f64', count: bodies, group: g },
    { name: `${p}halfHeight`, type: 'f64', count: bodies, group: g },
    { name: `${p}inverseMass`, type: 'f64', count: bodies, group: g },
    // Sleep state goes with the flags (a sleeping body's island and rest time must agree with its
    // flag): rest time in whole ticks of 1/60 s, the island as it is (0 while awake).
    // With local velocities the rest timers (how long a body has been slow) are local too.
    local
      ? { name: `${p}restTime`, type: 'f64', count: bodies, local: true, group: `${p}velocities` }
      : {
          name: `${p}restTime`,
          type: 'f64',
          count: bodies,
          group: g,
          precision: 1 / 60,
          min: 0,
          max: 16777216, // 2^24 s
        },
    { name: `${p}island`, type: 'i32', count: bodies, group: g },
    { name: `${p}contacts`, type: 'u32', local: true, group: `${p}cache` },
    { name: `${p}bodyA`, type: 'i32', count: contacts, local: true, group: `${p}cache` },
    { name: `${p}bodyB`, type: 'i32', count: contacts, local: true, group: `${p}cache` },
    { name: `${p}normalImpulse`, type: 'f64', count: contacts, local: true, group: `${p}cache` },
    { name: `${p}tangentImpulse`, type: 'f64', count: contacts, local: true, group: `${p}cache` },
  ];
}
