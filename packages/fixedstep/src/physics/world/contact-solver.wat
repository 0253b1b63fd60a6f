;; The contact solver's inner loops; contact-solver.ts has each in JavaScript under the same name
;; (warmStart, iterateVelocities, iteratePositions, planVisits, preparePositions, velocitiesIn/Out,
;; positionsIn/Out), which give the same bits: the same IEEE-754 operations in the same order, and
;; `select` exactly where the JavaScript branches. Everything lives in the imported memory, laid out
;; as kernel-layout.ts says (scripts/wasm.mjs puts its values in the placeholders): velocities
;; (vx, vy) a body, positions (movedX, movedY, x, y) a body, then the visits two by two, transposed:
;; pairs of VISIT_PAIR_BYTES whose fields — nx, ny, normal mass (the separation for positions),
;; inverse masses of A and B, normal and tangent impulse (f64), the byte offsets of A's and B's
;; velocities (i32) — hold the first visit's value in lane 0 and the second's in lane 1, the
;; second VISIT_LANE_BYTES after the first. The two visits of a pair share no body.
(module
  (import "env" "memory" (memory 1))

  ;; Warm start: each of the `count` pairs of visits' impulses applied once, the pair's two visits
  ;; side by side as in iterateVelocities. The JavaScript skips a visit whose two impulses are 0
  ;; (a pad's always are); here `skip` (all ones there) selects the old velocities instead: the
  ;; same bits (adding a zero impulse would turn a velocity of −0 into +0).
  (func (export "warmStart") (param $first i32) (param $count i32)
    (local $p i32) (local $end i32) (local $a i32) (local $b i32) (local $a1 i32) (local $b1 i32)
    (local $lo v128) (local $hi v128) (local $nX v128) (local $nY v128) (local $jN v128) (local $jT v128)
    (local $pX v128) (local $pY v128) (local $iA v128) (local $iB v128) (local $skip v128)
    (local $vaX v128) (local $vaY v128) (local $vbX v128) (local $vbY v128)
    (local.set $p (local.get $first))
    (local.set $end (i32.add (local.get $p) (i32.shl (local.get $count) (i32.const {{VISIT_PAIR_SHIFT}}))))
    (block $done
      (loop $pair
        (br_if $done (i32.ge_u (local.get $p) (local.get $end)))
        (local.set $a (i32.load offset={{VISIT_VELOCITY_A}} (local.get $p)))
        (local.set $b (i32.load offset={{VISIT_VELOCITY_B}} (local.get $p)))
        (local.set $a1 (i32.load offset={{VISIT_VELOCITY_A + VISIT_LANE_BYTES}} (local.get $p)))
        (local.set $b1 (i32.load offset={{VISIT_VELOCITY_B + VISIT_LANE_BYTES}} (local.get $p)))
        (local.set $jN (v128.load offset={{VISIT_NORMAL_IMPULSE}} (local.get $p)))
        (local.set $jT (v128.load offset={{VISIT_TANGENT_IMPULSE}} (local.get $p)))
        (local.set $skip (v128.and (f64x2.eq (local.get $jN) (f64x2.splat (f64.const 0)))
                                   (f64x2.eq (local.get $jT) (f64x2.splat (f64.const 0)))))
        (local.set $nX (v128.load offset={{VISIT_NORMAL_X}} (local.get $p)))
        (local.set $nY (v128.load offset={{VISIT_NORMAL_Y}} (local.get $p)))
        ;; P = (jn·nx − jt·ny, jn·ny + jt·nx)
        (local.set $pX (f64x2.sub (f64x2.mul (local.get $jN) (local.get $nX))
                                  (f64x2.mul (local.get $jT) (local.get $nY))))
        (local.set $pY (f64x2.add (f64x2.mul (local.get $jN) (local.get $nY))
                                  (f64x2.mul (local.get $jT) (local.get $nX))))
        (local.set $iA (v128.load offset={{VISIT_INVERSE_MASS_A}} (local.get $p)))
        (local.set $iB (v128.load offset={{VISIT_INVERSE_MASS_B}} (local.get $p)))
        (local.set $lo (v128.load (local.get $a)))
        (local.set $hi (v128.load (local.get $a1)))
        (local.set $vaX (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $lo) (local.get $hi)))
        (local.set $vaY (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $lo) (local.get $hi)))
        (local.set $lo (v128.load (local.get $b)))
        (local.set $hi (v128.load (local.get $b1)))
        (local.set $vbX (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $lo) (local.get $hi)))
        (local.set $vbY (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $lo) (local.get $hi)))
        (local.set $vaX (v128.bitselect (local.get $vaX) (f64x2.add (local.get $vaX) (f64x2.mul (local.get $pX) (local.get $iA))) (local.get $skip)))
        (local.set $vaY (v128.bitselect (local.get $vaY) (f64x2.add (local.get $vaY) (f64x2.mul (local.get $pY) (local.get $iA))) (local.get $skip)))
        (local.set $vbX (v128.bitselect (local.get $vbX) (f64x2.sub (local.get $vbX) (f64x2.mul (local.get $pX) (local.get $iB))) (local.get $skip)))
        (local.set $vbY (v128.bitselect (local.get $vbY) (f64x2.sub (local.get $vbY) (f64x2.mul (local.get $pY) (local.get $iB))) (local.get $skip)))
        (v128.store (local.get $a) (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $vaX) (local.get $vaY)))
        (v128.store (local.get $a1) (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $vaX) (local.get $vaY)))
        (v128.store (local.get $b) (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $vbX) (local.get $vbY)))
        (v128.store (local.get $b1) (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $vbX) (local.get $vbY)))
        (local.set $p (i32.add (local.get $p) (i32.const {{VISIT_PAIR_BYTES}})))
        (br $pair))))

  ;; `iterations` sweeps of sequential impulses over `count` pairs of visits from byte `first`.
  ;; The two visits of a pair share no body, so they commute: they go side by side, the first in
  ;; lane 0 and the second in lane 1, each lane the very operations of one visit in the JavaScript
  ;; (IEEE-754 per lane, no fused operations; pmax and pmin where it branches). Stored transposed, a
  ;; pair's fields load straight into lanes; only the bodies' (vx, vy) are transposed here, and back.
  (func (export "iterateVelocities") (param $first i32) (param $count i32) (param $iterations i32) (param $mu f64)
    (local $p i32) (local $end i32) (local $it i32) (local $a i32) (local $b i32)
    (local $a1 i32) (local $b1 i32) (local $lo v128) (local $hi v128)
    (local $nX v128) (local $nY v128) (local $m v128) (local $iA v128) (local $iB v128)
    (local $jN v128) (local $jT v128) (local $vaX v128) (local $vaY v128) (local $vbX v128) (local $vbY v128)
    (local $rX v128) (local $rY v128) (local $nN v128) (local $nT v128) (local $dN v128) (local $dT v128)
    (local $f v128) (local $pX v128) (local $pY v128) (local $muV v128)
    (local.set $muV (f64x2.splat (local.get $mu)))
    (local.set $end (i32.add (local.get $first) (i32.shl (local.get $count) (i32.const {{VISIT_PAIR_SHIFT}}))))
    (block $done
      (loop $iteration
        (br_if $done (i32.ge_u (local.get $it) (local.get $iterations)))
        (local.set $p (local.get $first))
        (block $swept
          (loop $pair
            (br_if $swept (i32.ge_u (local.get $p) (local.get $end)))
            (local.set $a (i32.load offset={{VISIT_VELOCITY_A}} (local.get $p)))
            (local.set $b (i32.load offset={{VISIT_VELOCITY_B}} (local.get $p)))
            (local.set $a1 (i32.load offset={{VISIT_VELOCITY_A + VISIT_LANE_BYTES}} (local.get $p)))
            (local.set $b1 (i32.load offset={{VISIT_VELOCITY_B + VISIT_LANE_BYTES}} (local.get $p)))
            (local.set $nX (v128.load offset={{VISIT_NORMAL_X}} (local.get $p)))
            (local.set $nY (v128.load offset={{VISIT_NORMAL_Y}} (local.get $p)))
            (local.set $m (v128.load offset={{VISIT_NORMAL_MASS}} (local.get $p)))
            (local.set $jN (v128.load offset={{VISIT_NORMAL_IMPULSE}} (local.get $p)))
            (local.set $jT (v128.load offset={{VISIT_TANGENT_IMPULSE}} (local.get $p)))
            ;; The bodies' velocities, (vx, vy) each, into (first visit's, second visit's) lanes.
            (local.set $lo (v128.load (local.get $a)))
            (local.set $hi (v128.load (local.get $a1)))
            (local.set $vaX (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $lo) (local.get $hi)))
            (local.set $vaY (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $lo) (local.get $hi)))
            (local.set $lo (v128.load (local.get $b)))
            (local.set $hi (v128.load (local.get $b1)))
            (local.set $vbX (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $lo) (local.get $hi)))
            (local.set $vbY (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $lo) (local.get $hi)))
            (local.set $rX (f64x2.sub (local.get $vaX) (local.get $vbX)))
            (local.set $rY (f64x2.sub (local.get $vaY) (local.get $vbY)))
            ;; λ' = max(0, λ − (rx·nx + ry·ny)·mN), as `if (λ' < 0) λ' = 0`: pmax(λ', 0) is
            ;; `λ' < 0 ? 0 : λ'` to the bit (a NaN and a −0 stay), without a compare and select.
            (local.set $nN (f64x2.pmax
              (f64x2.sub (local.get $jN)
                (f64x2.mul (f64x2.add (f64x2.mul (local.get $rX) (local.get $nX)) (f64x2.mul (local.get $rY) (local.get $nY)))
                           (local.get $m)))
              (f64x2.splat (f64.const 0))))
            (local.set $dN (f64x2.sub (local.get $nN) (local.get $jN)))
            ;; τ' = clamp(τ − (ry·nx − rx·ny)·mN, ±μλ'), as `if (τ' > f) τ' = f; else if
            ;; (τ' < −f) τ' = −f` with f = μλ': pmin(τ', f) is `f < τ' ? f : τ'`, then pmax(·, −f)
            ;; `· < −f ? −f : ·`, which leaves f alone: f is never below −f (μ ≥ 0 and λ' ≥ 0, so
            ;; f ≥ 0, a zero of either sign or NaN). The same bits as the two branches.
            (local.set $f (f64x2.mul (local.get $muV) (local.get $nN)))
            (local.set $nT
              (f64x2.pmax
                (f64x2.pmin
                  (f64x2.sub (local.get $jT)
                    (f64x2.mul (f64x2.sub (f64x2.mul (local.get $rY) (local.get $nX)) (f64x2.mul (local.get $rX) (local.get $nY)))
                               (local.get $m)))
                  (local.get $f))
                (f64x2.neg (local.get $f))))
            (local.set $dT (f64x2.sub (local.get $nT) (local.get $jT)))
            (v128.store offset={{VISIT_NORMAL_IMPULSE}} (local.get $p) (local.get $nN))
            (v128.store offset={{VISIT_TANGENT_IMPULSE}} (local.get $p) (local.get $nT))
            ;; P = (dN·nx − dT·ny, dN·ny + dT·nx)
            (local.set $pX (f64x2.sub (f64x2.mul (local.get $dN) (local.get $nX))
                                      (f64x2.mul (local.get $dT) (local.get $nY))))
            (local.set $pY (f64x2.add (f64x2.mul (local.get $dN) (local.get $nY))
                                      (f64x2.mul (local.get $dT) (local.get $nX))))
            (local.set $iA (v128.load offset={{VISIT_INVERSE_MASS_A}} (local.get $p)))
            (local.set $iB (v128.load offset={{VISIT_INVERSE_MASS_B}} (local.get $p)))
            (local.set $vaX (f64x2.add (local.get $vaX) (f64x2.mul (local.get $pX) (local.get $iA))))
            (local.set $vaY (f64x2.add (local.get $vaY) (f64x2.mul (local.get $pY) (local.get $iA))))
            (local.set $vbX (f64x2.sub (local.get $vbX) (f64x2.mul (local.get $pX) (local.get $iB))))
            (local.set $vbY (f64x2.sub (local.get $vbY) (f64x2.mul (local.get $pY) (local.get $iB))))
            (v128.store (local.get $a) (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $vaX) (local.get $vaY)))
            (v128.store (local.get $a1) (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $vaX) (local.get $vaY)))
            (v128.store (local.get $b) (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $vbX) (local.get $vbY)))
            (v128.store (local.get $b1) (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $vbX) (local.get $vbY)))
            (local.set $p (i32.add (local.get $p) (i32.const {{VISIT_PAIR_BYTES}})))
            (br $pair)))
        (local.set $it (i32.add (local.get $it) (i32.const 1)))
        (br $iteration))))

  ;; `iterations` sweeps of the position relaxation over `count` pairs of visits; positions start at
  ;; byte `positions`. A pair's two visits side by side as in iterateVelocities: the predicted
  ;; separation s = s0 + (ΔAx − ΔBx)·nx + (ΔAy − ΔBy)·ny of each in its lane, in the JavaScript's
  ;; order, and one division for both. Each body's push then goes back to (x, y) lanes, added to its
  ;; motion (movedX, movedY) and its position (x, y) alike. The JavaScript skips a visit with
  ;; s ≥ −slop; here every visit computes its push and `keep` (all ones where s ≥ −slop) makes it
  ;; +0 instead: the same bits, and no branch to mispredict (in a pile about two visits in three
  ;; keep). A pad keeps: its separation and motion are 0.
  (func (export "iteratePositions") (param $first i32) (param $count i32) (param $positions i32)
        (param $iterations i32) (param $slop f64) (param $beta f64)
    (local $p i32) (local $end i32) (local $it i32) (local $a i32) (local $b i32) (local $a1 i32) (local $b1 i32)
    (local $nX v128) (local $nY v128) (local $mA v128) (local $mA1 v128) (local $mB v128) (local $mB1 v128)
    (local $s v128) (local $keep v128) (local $iA v128) (local $iB v128) (local $c v128)
    (local $pX v128) (local $pY v128) (local $push v128)
    (local $slopV v128) (local $negSlopV v128) (local $betaV v128)
    (local.set $slopV (f64x2.splat (local.get $slop)))
    (local.set $negSlopV (f64x2.splat (f64.neg (local.get $slop))))
    (local.set $betaV (f64x2.splat (local.get $beta)))
    (local.set $end (i32.add (local.get $first) (i32.shl (local.get $count) (i32.const {{VISIT_PAIR_SHIFT}}))))
    (block $done
      (loop $iteration
        (br_if $done (i32.ge_u (local.get $it) (local.get $iterations)))
        (local.set $p (local.get $first))
        (block $swept
          (loop $pair
            (br_if $swept (i32.ge_u (local.get $p) (local.get $end)))
            ;; A position's offset is a velocity's shifted by POSITION_SHIFT − VELOCITY_SHIFT.
            (local.set $a (i32.add (local.get $positions) (i32.shl (i32.load offset={{VISIT_VELOCITY_A}} (local.get $p)) (i32.const {{POSITION_SHIFT - VELOCITY_SHIFT}}))))
            (local.set $b (i32.add (local.get $positions) (i32.shl (i32.load offset={{VISIT_VELOCITY_B}} (local.get $p)) (i32.const {{POSITION_SHIFT - VELOCITY_SHIFT}}))))
            (local.set $a1 (i32.add (local.get $positions) (i32.shl (i32.load offset={{VISIT_VELOCITY_A + VISIT_LANE_BYTES}} (local.get $p)) (i32.const {{POSITION_SHIFT - VELOCITY_SHIFT}}))))
            (local.set $b1 (i32.add (local.get $positions) (i32.shl (i32.load offset={{VISIT_VELOCITY_B + VISIT_LANE_BYTES}} (local.get $p)) (i32.const {{POSITION_SHIFT - VELOCITY_SHIFT}}))))
            (local.set $nX (v128.load offset={{VISIT_NORMAL_X}} (local.get $p)))
            (local.set $nY (v128.load offset={{VISIT_NORMAL_Y}} (local.get $p)))
            (local.set $mA (v128.load (local.get $a)))
            (local.set $mA1 (v128.load (local.get $a1)))
            (local.set $mB (v128.load (local.get $b)))
            (local.set $mB1 (v128.load (local.get $b1)))
            ;; s = s0 + (ΔAx − ΔBx)·nx + (ΔAy − ΔBy)·ny
            (local.set $s (f64x2.add
              (f64x2.add (v128.load offset={{VISIT_SEPARATION}} (local.get $p))
                (f64x2.mul (f64x2.sub (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $mA) (local.get $mA1))
                                      (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $mB) (local.get $mB1)))
                           (local.get $nX)))
              (f64x2.mul (f64x2.sub (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $mA) (local.get $mA1))
                                    (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $mB) (local.get $mB1)))
                         (local.get $nY))))
            (local.set $keep (f64x2.ge (local.get $s) (local.get $negSlopV)))
            (local.set $iA (v128.load offset={{VISIT_INVERSE_MASS_A}} (local.get $p)))
            (local.set $iB (v128.load offset={{VISIT_INVERSE_MASS_B}} (local.get $p)))
            ;; C = −(s + slop)·β / (iA + iB); A moves by (C·iA)·n, B by −(C·iB)·n. Every body
            ;; subtracts its push: A's is ((−C)·iA)·n, exactly −((C·iA)·n), and a − (−p) is
            ;; a + p to the bit. Where `keep`, the push is +0 instead (and-not), and a − (+0) is a
            ;; for every a, −0 included: the old value, as the JavaScript's skip leaves it.
            (local.set $c (f64x2.div (f64x2.mul (f64x2.neg (f64x2.add (local.get $s) (local.get $slopV))) (local.get $betaV))
                                     (f64x2.add (local.get $iA) (local.get $iB))))
            (local.set $iA (f64x2.mul (f64x2.neg (local.get $c)) (local.get $iA)))
            (local.set $pX (v128.andnot (f64x2.mul (local.get $iA) (local.get $nX)) (local.get $keep)))
            (local.set $pY (v128.andnot (f64x2.mul (local.get $iA) (local.get $nY)) (local.get $keep)))
            ;; The first visit's A: its push (x, y) from lane 0; the second's from lane 1.
            (local.set $push (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $pX) (local.get $pY)))
            (v128.store (local.get $a) (f64x2.sub (local.get $mA) (local.get $push)))
            (v128.store offset={{POSITION_XY}} (local.get $a) (f64x2.sub (v128.load offset={{POSITION_XY}} (local.get $a)) (local.get $push)))
            (local.set $push (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $pX) (local.get $pY)))
            (v128.store (local.get $a1) (f64x2.sub (local.get $mA1) (local.get $push)))
            (v128.store offset={{POSITION_XY}} (local.get $a1) (f64x2.sub (v128.load offset={{POSITION_XY}} (local.get $a1)) (local.get $push)))
            ;; B's of both, by (C·iB)·n.
            (local.set $iB (f64x2.mul (local.get $c) (local.get $iB)))
            (local.set $pX (v128.andnot (f64x2.mul (local.get $iB) (local.get $nX)) (local.get $keep)))
            (local.set $pY (v128.andnot (f64x2.mul (local.get $iB) (local.get $nY)) (local.get $keep)))
            (local.set $push (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $pX) (local.get $pY)))
            (v128.store (local.get $b) (f64x2.sub (local.get $mB) (local.get $push)))
            (v128.store offset={{POSITION_XY}} (local.get $b) (f64x2.sub (v128.load offset={{POSITION_XY}} (local.get $b)) (local.get $push)))
            (local.set $push (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $pX) (local.get $pY)))
            (v128.store (local.get $b1) (f64x2.sub (local.get $mB1) (local.get $push)))
            (v128.store offset={{POSITION_XY}} (local.get $b1) (f64x2.sub (v128.load offset={{POSITION_XY}} (local.get $b1)) (local.get $push)))
            (local.set $p (i32.add (local.get $p) (i32.const {{VISIT_PAIR_BYTES}})))
            (br $pair)))
        (local.set $it (i32.add (local.get $it) (i32.const 1)))
        (br $iteration))))

  ;; SolverSchedule.plan's waves, order and visits (contact-solver.ts does the same in JavaScript,
  ;; and still does it when restitution needs the approach speeds). The contacts in columns at
  ;; $bodyA, $bodyB (i32), $nx, $ny (f64); the solver inverse masses (f64) by body; the $cached
  ;; entries of the warm-start cache in columns at $cachedA, $cachedB (i32), $cachedN, $cachedT
  ;; (f64). Scratch: the cache's chains ($head by body, $next by entry: made here, as
  ;; WarmStartCache.link makes them), $lastWave by body, $waveOf by contact, $waveStart, $firstOf,
  ;; $lastOf by wave (count + 2 of each). Writes the visiting order at $order (i32; -1 for a pad)
  ;; and the visits, paired, at $visits; returns how many visits, pads included (an even number).
  (func (export "planVisits") (param $count i32) (param $pairs i32) (param $slots i32)
        (param $bodyA i32) (param $bodyB i32) (param $nx i32) (param $ny i32) (param $im i32)
        (param $cached i32) (param $head i32) (param $next i32) (param $cachedA i32) (param $cachedB i32)
        (param $cachedN i32) (param $cachedT i32)
        (param $lastWave i32) (param $waveOf i32) (param $waveStart i32) (param $firstOf i32)
        (param $lastOf i32) (param $order i32) (param $visits i32) (result i32)
    (local $k i32) (local $a i32) (local $b i32) (local $wave i32) (local $waveB i32) (local $waves i32)
    (local $w i32) (local $s i32) (local $p i32) (local $q i32) (local $cursor i32) (local $pad i32)
    (local $ia f64) (local $ib f64) (local $mass f64) (local $jn f64) (local $jt f64)
    ;; The chains: each body's entries in cache order (-1 ends one).
    (memory.fill (local.get $head) (i32.const 255) (i32.shl (local.get $slots) (i32.const 2)))
    (local.set $w (local.get $cached))
    (block $linked
      (loop $link
        (br_if $linked (i32.eqz (local.get $w)))
        (local.set $w (i32.sub (local.get $w) (i32.const 1)))
        (local.set $p (i32.add (local.get $head) (i32.shl (i32.load (i32.add (local.get $cachedA) (i32.shl (local.get $w) (i32.const 2)))) (i32.const 2))))
        (i32.store (i32.add (local.get $next) (i32.shl (local.get $w) (i32.const 2))) (i32.load (local.get $p)))
        (i32.store (local.get $p) (local.get $w))
        (br $link)))
    (memory.fill (local.get $lastWave) (i32.const 0) (i32.shl (local.get $slots) (i32.const 2)))
    (memory.fill (local.get $waveStart) (i32.const 0) (i32.shl (i32.add (local.get $count) (i32.const 2)) (i32.const 2)))
    ;; Each contact's wave, contacts per wave, and each wave's first and last contact.
    (block $wavesDone
      (loop $waveLoop
        (br_if $wavesDone (i32.ge_s (local.get $k) (local.get $count)))
        (local.set $a (i32.load (i32.add (local.get $bodyA) (i32.shl (local.get $k) (i32.const 2)))))
        (local.set $wave (i32.load (i32.add (local.get $lastWave) (i32.shl (local.get $a) (i32.const 2)))))
        (if (i32.lt_s (local.get $k) (local.get $pairs))
          (then
            (local.set $b (i32.load (i32.add (local.get $bodyB) (i32.shl (local.get $k) (i32.const 2)))))
            (local.set $waveB (i32.load (i32.add (local.get $lastWave) (i32.shl (local.get $b) (i32.const 2)))))
            (if (i32.gt_s (local.get $waveB) (local.get $wave)) (then (local.set $wave (local.get $waveB))))
            (i32.store (i32.add (local.get $lastWave) (i32.shl (local.get $b) (i32.const 2)))
                       (i32.add (local.get $wave) (i32.const 1)))))
        (local.set $wave (i32.add (local.get $wave) (i32.const 1)))
        (i32.store (i32.add (local.get $lastWave) (i32.shl (local.get $a) (i32.const 2))) (local.get $wave))
        (i32.store (i32.add (local.get $waveOf) (i32.shl (local.get $k) (i32.const 2))) (local.get $wave))
        (if (i32.gt_s (local.get $wave) (local.get $waves)) (then (local.set $waves (local.get $wave))))
        (local.set $q (i32.shl (local.get $wave) (i32.const 2)))
        (local.set $p (i32.add (local.get $waveStart) (i32.add (local.get $q) (i32.const 4))))
        (if (i32.eqz (i32.load (local.get $p)))
          (then (i32.store (i32.add (local.get $firstOf) (local.get $q)) (local.get $k))))
        (i32.store (i32.add (local.get $lastOf) (local.get $q)) (local.get $k))
        (i32.store (local.get $p) (i32.add (i32.load (local.get $p)) (i32.const 1)))
        (local.set $k (i32.add (local.get $k) (i32.const 1)))
        (br $waveLoop)))
    ;; Where each wave starts, in visits: the waves one after the other, and a pad after a wave that
    ;; ends a pair's first visit when the next wave's first visit shares a body with it (or there is
    ;; none). $s: visits so far.
    (local.set $w (i32.const 1))
    (block $sumDone
      (loop $sum
        (br_if $sumDone (i32.gt_s (local.get $w) (local.get $waves)))
        (local.set $p (i32.add (local.get $waveStart) (i32.shl (local.get $w) (i32.const 2))))
        (local.set $q (i32.load offset=4 (local.get $p)))
        (i32.store (local.get $p) (local.get $s))
        (local.set $s (i32.add (local.get $s) (local.get $q)))
        (if (i32.and (local.get $s) (i32.const 1))
          (then
            (local.set $pad (i32.const 1))
            (if (i32.lt_s (local.get $w) (local.get $waves))
              (then
                ;; A's and B's velocity bodies of the two (a wall's B is its own stand-in).
                (local.set $k (i32.load (i32.add (local.get $lastOf) (i32.shl (local.get $w) (i32.const 2)))))
                (local.set $a (i32.load (i32.add (local.get $bodyA) (i32.shl (local.get $k) (i32.const 2)))))
                (local.set $b (select (i32.load (i32.add (local.get $bodyB) (i32.shl (local.get $k) (i32.const 2))))
                                      (i32.sub (i32.add (local.get $slots) (local.get $k)) (local.get $pairs))
                                      (i32.lt_s (local.get $k) (local.get $pairs))))
                (local.set $k (i32.load offset=4 (i32.add (local.get $firstOf) (i32.shl (local.get $w) (i32.const 2)))))
                (local.set $wave (i32.load (i32.add (local.get $bodyA) (i32.shl (local.get $k) (i32.const 2)))))
                (local.set $waveB (select (i32.load (i32.add (local.get $bodyB) (i32.shl (local.get $k) (i32.const 2))))
                                          (i32.sub (i32.add (local.get $slots) (local.get $k)) (local.get $pairs))
                                          (i32.lt_s (local.get $k) (local.get $pairs))))
                (local.set $pad (i32.or (i32.or (i32.eq (local.get $a) (local.get $wave)) (i32.eq (local.get $a) (local.get $waveB)))
                                        (i32.or (i32.eq (local.get $b) (local.get $wave)) (i32.eq (local.get $b) (local.get $waveB)))))))
            (if (local.get $pad)
              (then
                ;; A pad: zeros, both bodies the pad body after the stand-ins (the pair's first
                ;; visit is written below).
                (local.set $p (i32.add (local.get $visits) (i32.shl (i32.shr_u (local.get $s) (i32.const 1)) (i32.const {{VISIT_PAIR_SHIFT}}))))
                (memory.fill (local.get $p) (i32.const 0) (i32.const {{VISIT_VELOCITY_A}}))
                (local.set $q (i32.shl (i32.sub (i32.add (local.get $slots) (local.get $count)) (local.get $pairs)) (i32.const {{VELOCITY_SHIFT}})))
                (i32.store offset={{VISIT_VELOCITY_A + VISIT_LANE_BYTES}} (local.get $p) (local.get $q))
                (i32.store offset={{VISIT_VELOCITY_B + VISIT_LANE_BYTES}} (local.get $p) (local.get $q))
                (i32.store (i32.add (local.get $order) (i32.shl (local.get $s) (i32.const 2))) (i32.const -1))
                (local.set $s (i32.add (local.get $s) (i32.const 1)))))))
        (local.set $w (i32.add (local.get $w) (i32.const 1)))
        (br $sum)))
    (local.set $pad (local.get $s))
    ;; The order, stable within a wave, and each contact's visit at its place in it (the contacts'
    ;; columns read in list order).
    (local.set $k (i32.const 0))
    (block $visitsDone
      (loop $visit
        (br_if $visitsDone (i32.ge_s (local.get $k) (local.get $count)))
        (local.set $p (i32.add (local.get $waveStart)
          (i32.shl (i32.load (i32.add (local.get $waveOf) (i32.shl (local.get $k) (i32.const 2)))) (i32.const 2))))
        (local.set $s (i32.load (local.get $p)))
        (i32.store (local.get $p) (i32.add (local.get $s) (i32.const 1)))
        (i32.store (i32.add (local.get $order) (i32.shl (local.get $s) (i32.const 2))) (local.get $k))
        (local.set $a (i32.load (i32.add (local.get $bodyA) (i32.shl (local.get $k) (i32.const 2)))))
        (local.set $b (i32.load (i32.add (local.get $bodyB) (i32.shl (local.get $k) (i32.const 2)))))
        ;; Visit s: lane s & 1 of pair s >> 1.
        (local.set $p (i32.add (local.get $visits)
          (i32.or (i32.shl (i32.shr_u (local.get $s) (i32.const 1)) (i32.const {{VISIT_PAIR_SHIFT}}))
                  (i32.mul (i32.and (local.get $s) (i32.const 1)) (i32.const {{VISIT_LANE_BYTES}})))))
        (local.set $ia (f64.load (i32.add (local.get $im) (i32.shl (local.get $a) (i32.const 3)))))
        (if (i32.lt_s (local.get $k) (local.get $pairs))
          (then
            (local.set $ib (f64.load (i32.add (local.get $im) (i32.shl (local.get $b) (i32.const 3)))))
            (local.set $mass (f64.div (f64.const 1) (f64.add (local.get $ia) (local.get $ib))))
            (f64.store offset={{VISIT_INVERSE_MASS_B}} (local.get $p) (local.get $ib))
            (i32.store offset={{VISIT_VELOCITY_B}} (local.get $p) (i32.shl (local.get $b) (i32.const {{VELOCITY_SHIFT}}))))
          (else
            (local.set $mass (f64.div (f64.const 1) (local.get $ia)))
            (f64.store offset={{VISIT_INVERSE_MASS_B}} (local.get $p) (f64.const 0))
            (i32.store offset={{VISIT_VELOCITY_B}} (local.get $p)
              (i32.shl (i32.sub (i32.add (local.get $slots) (local.get $k)) (local.get $pairs)) (i32.const {{VELOCITY_SHIFT}})))))
        ;; Last step's impulses for the same pair (a pair has at most one entry): the entry after
        ;; the last one found, when it is the pair (contacts mostly come in last step's order),
        ;; else the entry of A's chain with B.
        (local.set $jn (f64.const 0))
        (local.set $jt (f64.const 0))
        (local.set $w (local.get $cursor))
        (if (i32.eqz (i32.and (i32.lt_u (local.get $w) (local.get $cached))
                              (i32.and (i32.eq (i32.load (i32.add (local.get $cachedA) (i32.shl (local.get $w) (i32.const 2)))) (local.get $a))
                                       (i32.eq (i32.load (i32.add (local.get $cachedB) (i32.shl (local.get $w) (i32.const 2)))) (local.get $b)))))
          (then
            (local.set $w (i32.load (i32.add (local.get $head) (i32.shl (local.get $a) (i32.const 2)))))
            (block $found
              (loop $chain
                (br_if $found (i32.eq (local.get $w) (i32.const -1)))
                (br_if $found (i32.eq (i32.load (i32.add (local.get $cachedB) (i32.shl (local.get $w) (i32.const 2)))) (local.get $b)))
                (local.set $w (i32.load (i32.add (local.get $next) (i32.shl (local.get $w) (i32.const 2)))))
                (br $chain)))))
        (if (i32.ne (local.get $w) (i32.const -1))
          (then
            (local.set $jn (f64.load (i32.add (local.get $cachedN) (i32.shl (local.get $w) (i32.const 3)))))
            (local.set $jt (f64.load (i32.add (local.get $cachedT) (i32.shl (local.get $w) (i32.const 3)))))
            (local.set $cursor (i32.add (local.get $w) (i32.const 1)))))
        (local.set $q (i32.shl (local.get $k) (i32.const 3)))
        (f64.store offset={{VISIT_NORMAL_X}} (local.get $p) (f64.load (i32.add (local.get $nx) (local.get $q))))
        (f64.store offset={{VISIT_NORMAL_Y}} (local.get $p) (f64.load (i32.add (local.get $ny) (local.get $q))))
        (f64.store offset={{VISIT_NORMAL_MASS}} (local.get $p) (local.get $mass))
        (f64.store offset={{VISIT_INVERSE_MASS_A}} (local.get $p) (local.get $ia))
        (f64.store offset={{VISIT_NORMAL_IMPULSE}} (local.get $p) (local.get $jn))
        (f64.store offset={{VISIT_TANGENT_IMPULSE}} (local.get $p) (local.get $jt))
        (i32.store offset={{VISIT_VELOCITY_A}} (local.get $p) (i32.shl (local.get $a) (i32.const {{VELOCITY_SHIFT}})))
        (local.set $k (i32.add (local.get $k) (i32.const 1)))
        (br $visit)))
    (local.get $pad))

  ;; solvePositions' preparation of the `count` visits (pads included): each visit's separation
  ;; (from the column at $sep, by contact; $order gives the contact of each visit, -1 for a pad,
  ;; which is left as it is: zeros) over its normal mass, and the inverse masses again from the
  ;; column at $im (by body) — 1 and 0 for a wall, whose correction is whole.
  (func (export "preparePositions") (param $first i32) (param $count i32) (param $pairs i32)
        (param $order i32) (param $sep i32) (param $im i32)
    (local $s i32) (local $p i32) (local $k i32)
    (block $done
      (loop $visit
        (br_if $done (i32.ge_s (local.get $s) (local.get $count)))
        (local.set $p (i32.add (local.get $first)
          (i32.or (i32.shl (i32.shr_u (local.get $s) (i32.const 1)) (i32.const {{VISIT_PAIR_SHIFT}}))
                  (i32.mul (i32.and (local.get $s) (i32.const 1)) (i32.const {{VISIT_LANE_BYTES}})))))
        (local.set $k (i32.load (i32.add (local.get $order) (i32.shl (local.get $s) (i32.const 2)))))
        (if (i32.ge_s (local.get $k) (i32.const 0))
          (then
            (f64.store offset={{VISIT_SEPARATION}} (local.get $p)
              (f64.load (i32.add (local.get $sep) (i32.shl (local.get $k) (i32.const 3)))))
            (if (i32.lt_s (local.get $k) (local.get $pairs))
              (then
                ;; A velocity's byte offset, shifted to an inverse mass's (8 bytes a body).
                (f64.store offset={{VISIT_INVERSE_MASS_A}} (local.get $p)
                  (f64.load (i32.add (local.get $im) (i32.shr_u (i32.load offset={{VISIT_VELOCITY_A}} (local.get $p)) (i32.const {{VELOCITY_SHIFT - 3}})))))
                (f64.store offset={{VISIT_INVERSE_MASS_B}} (local.get $p)
                  (f64.load (i32.add (local.get $im) (i32.shr_u (i32.load offset={{VISIT_VELOCITY_B}} (local.get $p)) (i32.const {{VELOCITY_SHIFT - 3}}))))))
              (else
                (f64.store offset={{VISIT_INVERSE_MASS_A}} (local.get $p) (f64.const 1))
                (f64.store offset={{VISIT_INVERSE_MASS_B}} (local.get $p) (f64.const 0))))))
        (local.set $s (i32.add (local.get $s) (i32.const 1)))
        (br $visit))))

  ;; Velocities in: the columns at $vx, $vy (f64 by body) interleaved from byte 0, and the $standIns
  ;; wall stand-ins after them set to 0.
  (func (export "velocitiesIn") (param $slots i32) (param $standIns i32) (param $vx i32) (param $vy i32)
    (local $i i32) (local $p i32)
    (block $done
      (loop $body
        (br_if $done (i32.ge_s (local.get $i) (local.get $slots)))
        (local.set $p (i32.shl (local.get $i) (i32.const 3)))
        (f64.store (i32.shl (local.get $p) (i32.const {{VELOCITY_SHIFT - 3}})) (f64.load (i32.add (local.get $vx) (local.get $p))))
        (f64.store offset=8 (i32.shl (local.get $p) (i32.const {{VELOCITY_SHIFT - 3}})) (f64.load (i32.add (local.get $vy) (local.get $p))))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $body)))
    (memory.fill (i32.shl (local.get $slots) (i32.const {{VELOCITY_SHIFT}})) (i32.const 0) (i32.shl (local.get $standIns) (i32.const {{VELOCITY_SHIFT}}))))

  ;; Velocities and impulses out: the velocities from byte 0 into the columns at $vx, $vy (by
  ;; body); each of the `count` visits' impulses into the columns at $jn, $jt by contact ($order:
  ;; each visit's; a pad's -1 is skipped), the tangent one + 0 (a −0 becomes +0: the warm-start
  ;; cache keeps it as it is).
  (func (export "velocitiesOut") (param $first i32) (param $count i32) (param $slots i32)
        (param $order i32) (param $vx i32) (param $vy i32) (param $jn i32) (param $jt i32)
    (local $i i32) (local $p i32) (local $s i32) (local $k i32)
    (block $done
      (loop $body
        (br_if $done (i32.ge_s (local.get $i) (local.get $slots)))
        (local.set $p (i32.shl (local.get $i) (i32.const 3)))
        (f64.store (i32.add (local.get $vx) (local.get $p)) (f64.load (i32.shl (local.get $p) (i32.const {{VELOCITY_SHIFT - 3}}))))
        (f64.store (i32.add (local.get $vy) (local.get $p)) (f64.load offset=8 (i32.shl (local.get $p) (i32.const {{VELOCITY_SHIFT - 3}}))))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $body)))
    (block $visitsDone
      (loop $visit
        (br_if $visitsDone (i32.ge_s (local.get $s) (local.get $count)))
        (local.set $k (i32.load (i32.add (local.get $order) (i32.shl (local.get $s) (i32.const 2)))))
        (if (i32.ge_s (local.get $k) (i32.const 0))
          (then
            (local.set $p (i32.add (local.get $first)
              (i32.or (i32.shl (i32.shr_u (local.get $s) (i32.const 1)) (i32.const {{VISIT_PAIR_SHIFT}}))
                      (i32.mul (i32.and (local.get $s) (i32.const 1)) (i32.const {{VISIT_LANE_BYTES}})))))
            (local.set $k (i32.shl (local.get $k) (i32.const 3)))
            (f64.store (i32.add (local.get $jn) (local.get $k)) (f64.load offset={{VISIT_NORMAL_IMPULSE}} (local.get $p)))
            (f64.store (i32.add (local.get $jt) (local.get $k)) (f64.add (f64.load offset={{VISIT_TANGENT_IMPULSE}} (local.get $p)) (f64.const 0)))))
        (local.set $s (i32.add (local.get $s) (i32.const 1)))
        (br $visit))))

  ;; Positions in: for each of the $slots bodies, 32 bytes from $at — how far it has moved since its
  ;; contacts were found (x − startX, y − startY: the columns at $x, $y, $sx, $sy, f64 by body),
  ;; then x and y — and the $standIns wall stand-ins after them set to 0.
  (func (export "positionsIn") (param $slots i32) (param $standIns i32) (param $at i32)
        (param $x i32) (param $y i32) (param $sx i32) (param $sy i32)
    (local $i i32) (local $q i32) (local $p i32) (local $px f64) (local $py f64)
    (local.set $p (local.get $at))
    (block $done
      (loop $body
        (br_if $done (i32.ge_s (local.get $i) (local.get $slots)))
        (local.set $q (i32.shl (local.get $i) (i32.const 3)))
        (local.set $px (f64.load (i32.add (local.get $x) (local.get $q))))
        (local.set $py (f64.load (i32.add (local.get $y) (local.get $q))))
        (f64.store (local.get $p) (f64.sub (local.get $px) (f64.load (i32.add (local.get $sx) (local.get $q)))))
        (f64.store offset=8 (local.get $p) (f64.sub (local.get $py) (f64.load (i32.add (local.get $sy) (local.get $q)))))
        (f64.store offset={{POSITION_XY}} (local.get $p) (local.get $px))
        (f64.store offset={{POSITION_XY + 8}} (local.get $p) (local.get $py))
        (local.set $p (i32.add (local.get $p) (i32.const {{POSITION_BYTES}})))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $body)))
    (memory.fill (local.get $p) (i32.const 0) (i32.shl (local.get $standIns) (i32.const {{POSITION_SHIFT}}))))

  ;; Positions out: each body's x and y from the 32 bytes a body from $at into the columns at $x, $y.
  (func (export "positionsOut") (param $slots i32) (param $at i32) (param $x i32) (param $y i32)
    (local $i i32) (local $q i32) (local $p i32)
    (local.set $p (local.get $at))
    (block $done
      (loop $body
        (br_if $done (i32.ge_s (local.get $i) (local.get $slots)))
        (local.set $q (i32.shl (local.get $i) (i32.const 3)))
        (f64.store (i32.add (local.get $x) (local.get $q)) (f64.load offset={{POSITION_XY}} (local.get $p)))
        (f64.store (i32.add (local.get $y) (local.get $q)) (f64.load offset={{POSITION_XY + 8}} (local.get $p)))
        (local.set $p (i32.add (local.get $p) (i32.const {{POSITION_BYTES}})))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $body))))
)
