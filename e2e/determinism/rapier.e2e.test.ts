/**
 * The Rapier scenes in the determinism suite, in Node: a difference in one engine is reported
 * with its first tick and the body and value that differ.
 */
import { beforeAll, describe, expect, it } from 'vitest';
import { hexFloat, traceHashAt, traceScene } from '@fixedstep/games';
import { loadRapier } from '@fixedstep/rapier';
import { compareInNode, formatMismatch } from './compare.js';
import { rapierScenes, towerTraceScene } from './rapier.js';

beforeAll(async () => {
  await loadRapier();
});

describe('Rapier scenes in the determinism suite', () => {
  it('an engine whose Rapier differs names the first tick, the body and the two values', async () => {
    const ticks = 80;
    const good = [towerTraceScene(ticks)];
    // As an engine whose math differed once: the ball (body[17], after the ground and 16 boxes;
    // fired at tick 30, so awake) spins a little faster after tick 50.
    let changed = 0;
    const bad = [
      towerTraceScene(ticks, (sim) => {
        if (sim.tick !== 50) return;
        const ball = sim.world.getRigidBody(sim.scene.ball);
        ball.setAngvel(ball.angvel() + 1 / 1024, true);
        changed = ball.angvel();
      }),
    ];
    const c = await compareInNode('webkit', good, bad);
    expect(c.mismatches).toHaveLength(1);
    const line = formatMismatch(c.mismatches[0]!);
    expect(line).toMatch(/^webkit · rapier\/tower: differs from Node first at tick 50 /);
    expect(line).toContain(': body[17].angvel (f64 at offset 1046) ');
    expect(line).toContain(` vs ${hexFloat(changed)} `);
  });

  it('every Rapier scene traces, and the reloaded and display-rate towers equal the tower', async () => {
    const scenes = await rapierScenes(240);
    const traces = new Map(scenes.map((s) => [s.id, traceScene(s)]));
    expect([...traces.keys()]).toEqual([
      'rapier/tower',
      'rapier/tower/reloaded',
      'rapier/tower@30hz',
      'rapier/tower@59.94hz',
      'rapier/tower@60hz',
      'rapier/tower@144hz',
      'rapier/tower@240hz',
      'rapier/joints',
      'rapier/circles-150',
      'rapier/boxes-150',
    ]);
    const variants = scenes.filter((s) => s.sameAs !== undefined);
    expect(variants).toHaveLength(6);
    expect(variants.filter((s) => traces.get(s.id) !== traces.get(s.sameAs!))).toEqual([]);
    // Not a still life: the tower's state changes from tick to tick.
    const tower = traces.get('rapier/tower')!;
    expect(traceHashAt(tower, 239)).not.toBe(traceHashAt(tower, 240));
  });
});
