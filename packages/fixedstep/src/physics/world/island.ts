/**
 * Islands and sleep (Box2D's `island.c`, `solver.c`'s sleep pass).
 *
 * An island is a set of bodies joined by this step's body–body contacts (kinematic bodies and
 * walls do not join islands: they are not moved by what touches them). When every body of an
 * island has been slower than `sleepSpeed` for `timeToSleep`, the whole island falls asleep: its
 * velocities are zeroed, it is not moved, and pairs of sleeping bodies are not even looked at.
 * Each sleeping body remembers its island by the island's lowest body id, so the island wakes as
 * a whole: when something new touches it, a sweep hits it, a kinematic body pushes it, or a
 * caller moves it. Sleep is part of the state, so it is deterministic either way.
 */
import { BodyFlag, type BodyStore } from './body.js';
import type { ContactList, WarmStartCache } from './contacts.js';
import type { WorldDef } from './def.js';

const { ASLEEP, KINEMATIC } = BodyFlag;

/** Union–find root, with path halving. */
function find(parent: Int32Array, i: number): number {
  let r = i;
  while (parent[r] !== r) {
    const g = parent[parent[r]!]!;
    parent[r] = g;
    r = g;
  }
  return r;
}

/**
 * Bodies woken during the contact phase of a step, with what they had while asleep, so a step
 * that throws (too many contacts) can put them back to sleep and leave the world as it was.
 */
export class WakeLog {
  count = 0;
  ids = new Int32Array(0);
  restTime = new Float64Array(0);
  island = new Int32Array(0);
  /** Whether wakes are being recorded. */
  recording = false;

  resize(capacity: number): void {
    this.ids = new Int32Array(capacity);
    this.restTime = new Float64Array(capacity);
    this.island = new Int32Array(capacity);
  }

  /** Puts every recorded body back to sleep as it was, newest first. */
  undo(bodies: BodyStore): void {
    const flags = bodies.flags;
    for (let k = this.count - 1; k >= 0; k--) {
      const i = this.ids[k]!;
      flags[i] = flags[i]! | ASLEEP;
      bodies.restTime[i] = this.restTime[k]!;
      bodies.island[i] = this.island[k]!;
      bodies.solverInverseMass[i] = 0;
      bodies.sleepingCount++;
    }
    this.count = 0;
  }
}

/**
 * Wakes a sleeping body and everything that fell asleep with it (a no-op for an awake body). A
 * woken body starts its step's path where it is.
 */
export function wakeIsland(bodies: BodyStore, id: number, log: WakeLog | null = null): void {
  const flags = bodies.flags;
  if ((flags[id]! & ASLEEP) === 0) return;
  const island = bodies.island[id]!;
  for (let i = 0; i < bodies.slotCount; i++) {
    const f = flags[i]!;
    if ((f & ASLEEP) === 0 || bodies.island[i] !== island) continue;
    if (log?.recording === true) {
      const k = log.count++;
      log.ids[k] = i;
      log.restTime[k] = bodies.restTime[i]!;
      log.island[k] = island;
    }
    flags[i] = f & ~ASLEEP;
    bodies.restTime[i] = 0;
    bodies.island[i] = 0;
    bodies.solverInverseMass[i] = bodies.inverseMass[i]!;
    bodies.pathStartX[i] = bodies.x[i]!;
    bodies.pathStartY[i] = bodies.y[i]!;
    bodies.sleepingCount--;
  }
}

/**
 * Wakes the sleeping partner of every body–body contact that is new this step (not in last
 * step's cache) or that a kinematic body is part of. Returns whether it woke anything (then the
 * contacts must be found again: pairs of woken bodies were skipped).
 */
export function wakeByNewContacts(
  bodies: BodyStore,
  contacts: ContactList,
  cache: WarmStartCache,
  log: WakeLog,
): boolean {
  const flags = bodies.flags;
  const bodyA = contacts.bodyA;
  const bodyB = contacts.bodyB;
  const { head, next } = cache.chains(bodies.slotCount);
  const cachedB = cache.bodyB;
  let woke = false;
  for (let k = 0; k < contacts.bodyPairCount; k++) {
    const a = bodyA[k]!;
    const b = bodyB[k]!;
    const aSleeps = (flags[a]! & ASLEEP) !== 0;
    const bSleeps = (flags[b]! & ASLEEP) !== 0;
    if (aSleeps === bSleeps) continue;
    // A kinematic body pushes: what it touches never sleeps. (null: wake whatever the cache says.)
    let cached = ((flags[a]! | flags[b]!) & KINEMATIC) === 0 ? false : null;
    for (let w = head[a]!; cached === false && w !== -1; w = next[w]!) {
      if (cachedB[w] === b) cached = true;
    }
    if (cached === true) continue;
    wakeIsland(bodies, aSleeps ? a : b, log);
    woke = true;
  }
  return woke;
}

/** The sleep pass at the end of a step; union–find scratch by body. */
export class Islands {
  private parent = new Int32Array(0);
  private minRest = new Float64Array(0);

  resize(capacity: number): void {
    this.parent = new Int32Array(capacity);
    this.minRest = new Float64Array(capacity);
  }

  /**
   * Adds the step to each slow body's rest time (resets it for a fast one); every 8th tick, joins
   * bodies into islands through this step's contacts and puts to sleep each island whose every
   * body has rested `timeToSleep` (sleep comes at most 7 ticks late; forming islands costs a pass
   * over all contacts). With sleep disabled, wakes everything.
   */
  update(bodies: BodyStore, contacts: ContactList, def: Readonly<WorldDef>, tick: number): void {
    const n = bodies.slotCount;
    const flags = bodies.flags;
    if (!def.enableSleep) {
      if (bodies.sleepingCount > 0) for (let i = 0; i < n; i++) wakeIsland(bodies, i);
      return;
    }
    const vx = bodies.vx;
    const vy = bodies.vy;
    const inverseMass = bodies.solverInverseMass;
    const rest = bodies.restTime;
    const parent = this.parent;
    const minRest = this.minRest;
    const dt = def.timeStep;
    const slow2 = def.sleepSpeed * def.sleepSpeed;
    let candidates = 0;
    for (let i = 0; i < n; i++) {
      parent[i] = i;
      minRest[i] = Infinity;
      const f = flags[i]!;
      if (f === 0 || (f & ASLEEP) !== 0) continue;
      if (inverseMass[i] === 0) {
        rest[i] = 0; // kinematic: never sleeps
        continue;
      }
      const u = vx[i]!;
      const w = vy[i]!;
      if (u * u + w * w < slow2) {
        rest[i] = rest[i]! + dt;
        if (rest[i]! >= def.timeToSleep) candidates++;
      } else rest[i] = 0;
    }
    if (candidates === 0 || (tick & 7) !== 0) return;
    const bodyA = contacts.bodyA;
    const bodyB = contacts.bodyB;
    for (let k = 0; k < contacts.bodyPairCount; k++) {
      const a = bodyA[k]!;
      const b = bodyB[k]!;
      if (inverseMass[a] === 0 || inverseMass[b] === 0) continue;
      const ra = find(parent, a);
      const rb = find(parent, b);
      if (ra < rb) parent[rb] = ra;
      else if (rb < ra) parent[ra] = rb;
    }
    for (let i = 0; i < n; i++) {
      if (inverseMass[i] === 0 || flags[i] === 0 || (flags[i]! & ASLEEP) !== 0) continue;
      const r = find(parent, i);
      if (rest[i]! < minRest[r]!) minRest[r] = rest[i]!;
    }
    for (let i = 0; i < n; i++) {
      if (inverseMass[i] === 0 || flags[i] === 0 || (flags[i]! & ASLEEP) !== 0) continue;
      const r = find(parent, i);
      if (minRest[r]! < def.timeToSleep) continue;
      flags[i] = flags[i]! | ASLEEP;
      vx[i] = 0;
      vy[i] = 0;
      bodies.island[i] = r;
      bodies.sleepingCount++;
    }
  }
}
