/**
 * Events of a step (Box2D's `b2World_GetContactEvents`, `b2World_GetSensorEvents`): what began
 * and ended touching, read after the step, in a fixed order.
 *
 * **Sensor events** compare which bodies each sensor overlaps at the end of this step with the
 * end of the last one. That list ({@link SensorOverlaps}) is part of the state — saved, loaded and
 * hashed — so a world loaded from a snapshot reports exactly the events the original reports:
 * a rollback does not fire a pickup twice.
 *
 * **Contact events** compare this step's contacts with last step's, which the warm-start cache
 * already holds (state), so they need no state of their own. A pair that falls asleep touching
 * is still touching: it ends no contact when the step stops looking at it, and begins none when
 * its island wakes (Box2D keeps a sleeping island's contacts; this world drops them, so it
 * remembers which bodies were asleep at the end of the last step instead — from the flags, so a
 * load restores it).
 */
import { BodyFlag, type BodyStore } from './body.js';
import type { ContactList, WarmStartCache } from './contacts.js';
import type { QueryIndex } from './queries.js';

const { ASLEEP, SENSOR } = BodyFlag;

/** A sensor began or ended overlapping a body (Box2D's `b2SensorBeginTouchEvent`). */
export interface SensorEvent {
  /** The sensor's body id. */
  sensor: number;
  /** The body that entered or left it (never a sensor). */
  visitor: number;
}

/** Two bodies, or a body and a wall, began or ended touching (Box2D's `b2ContactBeginTouchEvent`). */
export interface ContactEvent {
  /** The body with the lower id (the only body, against a wall). */
  bodyA: number;
  /** The other body, or −1 against a wall. */
  bodyB: number;
  /** The static wall, or −1 between two bodies. */
  wall: number;
}

/** One step's events: sorted by the first id, then the second (bodies before walls). */
export interface StepEvents<E> {
  readonly begin: readonly E[];
  readonly end: readonly E[];
}

const NO_EVENTS: StepEvents<never> = Object.freeze({
  begin: Object.freeze([]),
  end: Object.freeze([]),
});

/** Sensor overlaps at the end of the last step (state), and the last step's sensor events. */
export class SensorOverlaps {
  /** Pairs, sorted by sensor then visitor. */
  count = 0;
  sensor = new Int32Array(16);
  visitor = new Int32Array(16);
  /** The last step's events (not state). */
  events: StepEvents<SensorEvent> = NO_EVENTS;
  private nextSensor = new Int32Array(16);
  private nextVisitor = new Int32Array(16);
  private scratch = new Int32Array(16);

  /**
   * This step's overlaps (from `index`: where the bodies are now) and the events against the
   * last ones. Only when the world has a sensor or an overlap left to end.
   */
  update(bodies: BodyStore, index: QueryIndex): void {
    const n = bodies.slotCount;
    if (this.scratch.length < n) this.scratch = new Int32Array(n);
    let count = 0;
    for (let s = 0; s < n && bodies.sensorCount > 0; s++) {
      if ((bodies.flags[s]! & SENSOR) === 0) continue;
      const found = index.sensorVisitors(s, this.scratch, 0);
      if (this.nextSensor.length < count + found) this.growNext(count + found);
      for (let k = 0; k < found; k++) {
        this.nextSensor[count] = s;
        this.nextVisitor[count++] = this.scratch[k]!;
      }
    }
    // Merge the two sorted lists: in the new one only, begin; in the old one only, end.
    const begin: SensorEvent[] = [];
    const end: SensorEvent[] = [];
    let i = 0;
    let j = 0;
    const os = this.sensor;
    const ov = this.visitor;
    const ns = this.nextSensor;
    const nv = this.nextVisitor;
    while (i < this.count || j < count) {
      const order = i === this.count ? 1 : j === count ? -1 : os[i]! - ns[j]! || ov[i]! - nv[j]!;
      if (order < 0) {
        end.push({ sensor: os[i]!, visitor: ov[i]! });
        i++;
      } else if (order > 0) {
        begin.push({ sensor: ns[j]!, visitor: nv[j]! });
        j++;
      } else {
        i++;
        j++;
      }
    }
    this.events = begin.length + end.length === 0 ? NO_EVENTS : { begin, end };
    this.nextSensor = os;
    this.nextVisitor = ov;
    this.sensor = ns;
    this.visitor = nv;
    this.count = count;
  }

  /** No events this step (a step that moved nothing). */
  quiet(): void {
    this.events = NO_EVENTS;
  }

  /** Forgets every pair of body `id` (destroyed, or no longer a sensor), with no event. */
  forget(id: number): void {
    let kept = 0;
    for (let k = 0; k < this.count; k++) {
      if (this.sensor[k] === id || this.visitor[k] === id) continue;
      this.sensor[kept] = this.sensor[k]!;
      this.visitor[kept++] = this.visitor[k]!;
    }
    this.count = kept;
  }

  /** Sets the pairs (a snapshot's, checked): room first. */
  setCount(count: number): void {
    if (this.sensor.length < count) {
      this.sensor = new Int32Array(count);
      this.visitor = new Int32Array(count);
      this.growNext(count);
    }
    this.count = count;
    this.events = NO_EVENTS;
  }

  private growNext(count: number): void {
    const size = Math.max(count, 2 * this.nextSensor.length);
    const s = new Int32Array(size);
    const v = new Int32Array(size);
    s.set(this.nextSensor);
    v.set(this.nextVisitor);
    this.nextSensor = s;
    this.nextVisitor = v;
    if (this.sensor.length < size) {
      const a = new Int32Array(size);
      const b = new Int32Array(size);
      a.set(this.sensor);
      b.set(this.visitor);
      this.sensor = a;
      this.visitor = b;
    }
  }
}

/**
 * Contact begin/end events (see the file comment). Costs a pass over the contacts and the cache
 * per step, so a world computes them only when asked to (`WorldOptions.contactEvents`).
 */
export class ContactEvents {
  /** The last step's events. */
  events: StepEvents<ContactEvent> = NO_EVENTS;
  /** By body: asleep at the end of the last step (1) — derived from the flags, not saved. */
  private asleepAtEnd = new Uint8Array(0);
  /** By body: its first contact this step; by contact: the next of the same bodyA. */
  private head = new Int32Array(0);
  private next = new Int32Array(0);

  resize(capacity: number): void {
    const a = new Uint8Array(capacity);
    a.set(this.asleepAtEnd.subarray(0, Math.min(capacity, this.asleepAtEnd.length)));
    this.asleepAtEnd = a;
    this.head = new Int32Array(capacity);
  }

  /** Remembers who sleeps now (the end of a step, or a load). */
  remember(bodies: BodyStore): void {
    const n = bodies.slotCount;
    const flags = bodies.flags;
    const asleep = this.asleepAtEnd;
    for (let i = 0; i < n; i++) asleep[i] = (flags[i]! & ASLEEP) !== 0 ? 1 : 0;
  }

  /** A slot was created or freed: it was not asleep. */
  clearBody(id: number): void {
    this.asleepAtEnd[id] = 0;
  }

  /** No events this step. */
  quiet(): void {
    this.events = NO_EVENTS;
  }

  /**
   * This step's events: its contacts (final, filtered) against last step's in `cache`, before the
   * cache takes this step's. Call after the contact phase, before the solvers.
   */
  diff(contacts: ContactList, cache: WarmStartCache, bodies: BodyStore): void {
    const n = contacts.count;
    const bodyA = contacts.bodyA;
    const bodyB = contacts.bodyB;
    const flags = bodies.flags;
    const asleep = this.asleepAtEnd;
    const begin: ContactEvent[] = [];
    const end: ContactEvent[] = [];
    // Begin: a contact the cache does not have — unless it was asleep (and so dropped) last step.
    const { head: cacheHead, next: cacheNext } = cache.chains(bodies.slotCount);
    const cachedB = cache.bodyB;
    for (let k = 0; k < n; k++) {
      const a = bodyA[k]!;
      const b = bodyB[k]!;
      let found = false;
      for (let w = cacheHead[a]!; !found && w !== -1; w = cacheNext[w]!) found = cachedB[w] === b;
      if (found || (asleep[a] === 1 && (b < 0 || asleep[b] === 1))) continue;
      begin.push(event(a, b));
    }
    // End: a cached pair this step does not have — unless the step did not look at it (asleep).
    if (this.next.length < n) this.next = new Int32Array(Math.max(n, 2 * this.next.length));
    const head = this.head;
    const next = this.next;
    head.fill(-1, 0, bodies.slotCount);
    for (let k = n - 1; k >= 0; k--) {
      const a = bodyA[k]!;
      next[k] = head[a]!;
      head[a] = k;
    }
    const cachedA = cache.bodyA;
    for (let w = 0; w < cache.count; w++) {
      const a = cachedA[w]!;
      const b = cachedB[w]!;
      let found = false;
      for (let k = head[a]!; !found && k !== -1; k = next[k]!) found = bodyB[k] === b;
      if (found) continue;
      if ((flags[a]! & ASLEEP) !== 0 && (b < 0 || (flags[b]! & ASLEEP) !== 0)) continue;
      end.push(event(a, b));
    }
    begin.sort(byPair);
    end.sort(byPair);
    this.events = begin.length + end.length === 0 ? NO_EVENTS : { begin, end };
  }
}

function event(a: number, b: number): ContactEvent {
  return b >= 0 ? { bodyA: a, bodyB: b, wall: -1 } : { bodyA: a, bodyB: -1, wall: -1 - b };
}

/** By bodyA, then bodies before walls, then bodyB or wall. */
function byPair(p: ContactEvent, q: ContactEvent): number {
  return (
    p.bodyA - q.bodyA ||
    (p.bodyB < 0 ? 1 : 0) - (q.bodyB < 0 ? 1 : 0) ||
    p.bodyB - q.bodyB ||
    p.wall - q.wall
  );
}
