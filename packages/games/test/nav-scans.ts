/**
 * The bots' searches as they were before their tables: the references the property tests
 * (bot-searches.test.ts, nav-goals.test.ts) hold the tables to.
 */
import type { NavGrid } from '@fixedstep/games';
import { scanNearest, scanWaypoints } from '../src/games/arena/nav.js';

/** `NavGrid.waypoint` as it was: the goal's node by the scan, then the scan of the waypoints. */
export function scanWaypoint(nav: NavGrid, x: number, y: number, tx: number, ty: number): number[] {
  const out = Float64Array.of(tx, ty);
  if (nav.walls.clear(x, y, tx, ty, nav.clearance)) return [...out];
  const goal = new Int32Array(1);
  if (scanNearest(nav, tx, ty, goal)) scanWaypoints(nav, x, y, goal[0]!, out);
  return [...out];
}
