/**
 * The world's WebAssembly memory layout, written once: the JavaScript loops read these names, and
 * `scripts/wasm.mjs` substitutes them into `contact-solver.wat` and `broad-phase.wat` wherever a
 * `{{NAME}}` (or a small sum such as `{{VISIT_LANE_BYTES + VISIT_NORMAL_IMPULSE}}`) stands,
 * before it assembles them. The script refuses a placeholder naming nothing here and a name here
 * that no `.wat` uses, and a test assembles the sources again and compares them with the committed
 * bytes (`npm run build:wasm` after a change here).
 *
 * Every value is a plain integer literal (the script reads this file as text). Offsets are bytes.
 */

// ---- The solvers' working memory (contact-solver.ts, "Visiting order"): velocities, positions,
// visits, in that order.

/**
 * log2 of the bytes of one body's velocity (vx, vy: f64, 16 bytes) in the velocity region: a body
 * id shifted by it is its velocity's offset.
 */
export const VELOCITY_SHIFT = 4;
/** Bytes of one body's positions: movedX, movedY (since its contacts were found), then x, y. */
export const POSITION_BYTES = 32;
/** log2 of {@link POSITION_BYTES}. */
export const POSITION_SHIFT = 5;
/** Where x, y start in a body's positions (after movedX, movedY). */
export const POSITION_XY = 16;

/**
 * Bytes of one pair of visits. The visits (contacts in visiting order) are stored two by two,
 * transposed: each field below is an f64x2 (an i32 pair for the velocity offsets) whose lane 0 is
 * the first visit's and lane 1 the second's, so the two-visit SIMD sweeps load every field with
 * one 16-byte load and no shuffle. The two visits of a pair share no body; a visit the plan could
 * not pair has a pad beside it (see contact-solver.ts, "Visiting order").
 */
export const VISIT_PAIR_BYTES = 128;
/** log2 of {@link VISIT_PAIR_BYTES}. */
export const VISIT_PAIR_SHIFT = 7;
/**
 * How far the second visit of a pair is from the first, in every field (f64 and i32 alike): a
 * visit is the bytes at its pair's offset plus 0 or this, plus each field's offset below.
 */
export const VISIT_LANE_BYTES = 8;
/** The contact normal, x and y (f64), from B to A. */
export const VISIT_NORMAL_X = 0;
export const VISIT_NORMAL_Y = 16;
/**
 * The normal mass 1 / (1/mA + 1/mB) (f64) for the velocities; the position solver puts the
 * contact's separation in the same place.
 */
export const VISIT_NORMAL_MASS = 32;
export const VISIT_SEPARATION = 32;
/** The solver inverse masses of A and B (f64). */
export const VISIT_INVERSE_MASS_A = 48;
export const VISIT_INVERSE_MASS_B = 64;
/** The accumulated normal and tangent impulses (f64). */
export const VISIT_NORMAL_IMPULSE = 80;
export const VISIT_TANGENT_IMPULSE = 96;
/**
 * The byte offsets of A's and B's velocities in the velocity region (i32; a wall's is its stand-in
 * body's, a pad's the pad body's). A position's offset is twice a velocity's
 * ({@link POSITION_BYTES}). The first visit's A, B, then the second's: each lane's pair of offsets
 * is {@link VISIT_LANE_BYTES} after the other's, like the f64 fields.
 */
export const VISIT_VELOCITY_A = 112;
export const VISIT_VELOCITY_B = 116;

// ---- The broad phase's grid bounds (Grid.build): gridBounds writes them, the JavaScript reads.

/** Min x, min y, max x, max y of the live bodies' centres (f64). */
export const BOUNDS_MIN_X = 0;
export const BOUNDS_MIN_Y = 8;
export const BOUNDS_MAX_X = 16;
export const BOUNDS_MAX_Y = 24;
/** Every live body's flags or-ed (i32; the record is 8-byte aligned, 40 bytes in all). */
export const BOUNDS_FLAGS = 32;

// ---- Body flags the kernels test (BodyFlag in body.ts takes these two from here).

/** BodyFlag.KINEMATIC. */
export const BODY_KINEMATIC = 8;
/** BodyFlag.ASLEEP. */
export const BODY_ASLEEP = 16;
