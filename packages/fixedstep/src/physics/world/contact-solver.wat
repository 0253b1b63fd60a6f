;; The contact solver's inner loops; contact-solver.ts has each in JavaScript under the same name
;; (warmStart, iterateVelocities, iteratePositions, planVisits, preparePositions, velocitiesIn/Out,
;; positionsIn/Out), which give the same bits: the same IEEE-754 operations in the same order, and
;; `select` exactly where the JavaScript branches. Everything lives in the imported memory, laid out
;; as kernel-layout.ts says (scripts/wasm.mjs puts its values in the placeholders): velocities
;; (vx, vy) a body, positions (movedX, movedY, x, y) a body, visits of VISIT_BYTES each — nx, ny,
;; normal mass (the separation for positions), inverse masses of A and B, normal and tangent impulse
;; (f64), then the byte offsets of A's and B's velocities (i32).
(module
  (import "env" "memory" (memory 1))

  ;; Warm start: each visit's impulses applied once (a visit whose two impulses are 0 is skipped).
  (func (export "warmStart") (param $p i32) (param $count i32)
    (local $end i32) (local $a i32) (local $b i32)
    (local $jn f64) (local $jt f64) (local $nx f64) (local $ny f64)
    (local $px f64) (local $py f64) (local $ia f64) (local $ib f64)
    (local.set $end (i32.add (local.get $p) (i32.shl (local.get $count) (i32.const {{VISIT_SHIFT}}))))
    (block $done
      (loop $visit
        (br_if $done (i32.ge_u (local.get $p) (local.get $end)))
        (local.set $jn (f64.load offset={{VISIT_NORMAL_IMPULSE}} (local.get $p)))
        (local.set $jt (f64.load offset={{VISIT_TANGENT_IMPULSE}} (local.get $p)))
        (if (i32.eqz (i32.and (f64.eq (local.get $jn) (f64.const 0))
                              (f64.eq (local.get $jt) (f64.const 0))))
          (then
            (local.set $a (i32.load offset={{VISIT_VELOCITY_A}} (local.get $p)))
            (local.set $b (i32.load offset={{VISIT_VELOCITY_B}} (local.get $p)))
            (local.set $nx (f64.load offset={{VISIT_NORMAL_X}} (local.get $p)))
            (local.set $ny (f64.load offset={{VISIT_NORMAL_Y}} (local.get $p)))
            (local.set $px (f64.sub (f64.mul (local.get $jn) (local.get $nx))
                                    (f64.mul (local.get $jt) (local.get $ny))))
            (local.set $py (f64.add (f64.mul (local.get $jn) (local.get $ny))
                                    (f64.mul (local.get $jt) (local.get $nx))))
            (local.set $ia (f64.load offset={{VISIT_INVERSE_MASS_A}} (local.get $p)))
            (local.set $ib (f64.load offset={{VISIT_INVERSE_MASS_B}} (local.get $p)))
            (f64.store (local.get $a)
              (f64.add (f64.load (local.get $a)) (f64.mul (local.get $px) (local.get $ia))))
            (f64.store offset=8 (local.get $a)
              (f64.add (f64.load offset=8 (local.get $a)) (f64.mul (local.get $py) (local.get $ia))))
            (f64.store (local.get $b)
              (f64.sub (f64.load (local.get $b)) (f64.mul (local.get $px) (local.get $ib))))
            (f64.store offset=8 (local.get $b)
              (f64.sub (f64.load offset=8 (local.get $b)) (f64.mul (local.get $py) (local.get $ib))))))
        (local.set $p (i32.add (local.get $p) (i32.const {{VISIT_BYTES}})))
        (br $visit))))

  ;; `iterations` sweeps of sequential impulses over `count` visits from byte `first`. Two visits
  ;; in a row that share no body (in a wave, all of them) go side by side: lane 0 is the first
  ;; visit's, lane 1 the second's, and each lane does exactly what one visit does below (a rollback
  ;; of the settling 2,000-circle pile runs about 1.15× as fast for it). One visit alone: a body's (vx, vy) is one f64x2,
  ;; and so is a normal: every lane does what the JavaScript does to that component (IEEE-754 per
  ;; lane, no fused operations), and the dot products add lane 0 and lane 1 in the JavaScript's
  ;; order. The impulse is P = λ·(nx, ny) + τ·(−ny, nx): lane 0 adds −(τ·ny), which is subtracting
  ;; τ·ny.
  (func (export "iterateVelocities") (param $first i32) (param $count i32) (param $iterations i32) (param $mu f64)
    (local $p i32) (local $end i32) (local $it i32) (local $a i32) (local $b i32)
    (local $n v128) (local $swapped v128) (local $va v128) (local $vb v128) (local $rel v128)
    (local $q v128) (local $impulse v128) (local $mass f64)
    (local $oldN f64) (local $newN f64) (local $dN f64) (local $oldT f64) (local $newT f64)
    (local $dT f64) (local $maxF f64)
    (local $a1 i32) (local $b1 i32) (local $lo v128) (local $hi v128)
    (local $nX v128) (local $nY v128) (local $m v128) (local $iA v128) (local $iB v128)
    (local $jN v128) (local $jT v128) (local $vaX v128) (local $vaY v128) (local $vbX v128) (local $vbY v128)
    (local $rX v128) (local $rY v128) (local $nN v128) (local $nT v128) (local $dN2 v128) (local $dT2 v128)
    (local $f v128) (local $pX v128) (local $pY v128) (local $muV v128)
    (local.set $muV (f64x2.splat (local.get $mu)))
    (local.set $end (i32.add (local.get $first) (i32.shl (local.get $count) (i32.const {{VISIT_SHIFT}}))))
    (block $done
      (loop $iteration
        (br_if $done (i32.ge_u (local.get $it) (local.get $iterations)))
        (local.set $p (local.get $first))
        (block $swept
          (loop $visit
            (br_if $swept (i32.ge_u (local.get $p) (local.get $end)))
            (local.set $a (i32.load offset={{VISIT_VELOCITY_A}} (local.get $p)))
            (local.set $b (i32.load offset={{VISIT_VELOCITY_B}} (local.get $p)))
            ;; Two visits in a row that share no body commute: do them side by side, visit p in
            ;; lane 0 and visit p + 64 in lane 1, each lane the very operations of one visit below.
            (if (i32.lt_u (i32.add (local.get $p) (i32.const {{VISIT_BYTES}})) (local.get $end))
              (then
                (local.set $a1 (i32.load offset={{VISIT_BYTES + VISIT_VELOCITY_A}} (local.get $p)))
                (local.set $b1 (i32.load offset={{VISIT_BYTES + VISIT_VELOCITY_B}} (local.get $p)))
                (if (i32.eqz (i32.or (i32.or (i32.eq (local.get $a1) (local.get $a)) (i32.eq (local.get $a1) (local.get $b)))
                                     (i32.or (i32.eq (local.get $b1) (local.get $a)) (i32.eq (local.get $b1) (local.get $b)))))
                  (then
                    ;; Transpose the two visits' fields into (visit 0, visit 1) lanes.
                    (local.set $lo (v128.load offset={{VISIT_NORMAL_X}} (local.get $p)))
                    (local.set $hi (v128.load offset={{VISIT_BYTES + VISIT_NORMAL_X}} (local.get $p)))
                    (local.set $nX (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $lo) (local.get $hi)))
                    (local.set $nY (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $lo) (local.get $hi)))
                    (local.set $lo (v128.load offset={{VISIT_NORMAL_MASS}} (local.get $p)))
                    (local.set $hi (v128.load offset={{VISIT_BYTES + VISIT_NORMAL_MASS}} (local.get $p)))
                    (local.set $m (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $lo) (local.get $hi)))
                    (local.set $iA (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $lo) (local.get $hi)))
                    (local.set $lo (v128.load offset={{VISIT_INVERSE_MASS_B}} (local.get $p)))
                    (local.set $hi (v128.load offset={{VISIT_BYTES + VISIT_INVERSE_MASS_B}} (local.get $p)))
                    (local.set $iB (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $lo) (local.get $hi)))
                    (local.set $jN (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $lo) (local.get $hi)))
                    (local.set $jT (f64x2.replace_lane 1 (f64x2.splat (f64.load offset={{VISIT_TANGENT_IMPULSE}} (local.get $p)))
                                                        (f64.load offset={{VISIT_BYTES + VISIT_TANGENT_IMPULSE}} (local.get $p))))
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
                    ;; λ' = max(0, λ − (rx·nx + ry·ny)·mN)
                    (local.set $nN (f64x2.sub (local.get $jN)
                      (f64x2.mul (f64x2.add (f64x2.mul (local.get $rX) (local.get $nX)) (f64x2.mul (local.get $rY) (local.get $nY)))
                                 (local.get $m))))
                    (local.set $nN (v128.bitselect (f64x2.splat (f64.const 0)) (local.get $nN)
                                                   (f64x2.lt (local.get $nN) (f64x2.splat (f64.const 0)))))
                    (local.set $dN2 (f64x2.sub (local.get $nN) (local.get $jN)))
                    ;; τ' = clamp(τ − (ry·nx − rx·ny)·mN, ±μλ')
                    (local.set $f (f64x2.mul (local.get $muV) (local.get $nN)))
                    (local.set $nT (f64x2.sub (local.get $jT)
                      (f64x2.mul (f64x2.sub (f64x2.mul (local.get $rY) (local.get $nX)) (f64x2.mul (local.get $rX) (local.get $nY)))
                                 (local.get $m))))
                    (local.set $nT
                      (v128.bitselect (local.get $f)
                        (v128.bitselect (f64x2.neg (local.get $f)) (local.get $nT)
                                        (f64x2.lt (local.get $nT) (f64x2.neg (local.get $f))))
                        (f64x2.gt (local.get $nT) (local.get $f))))
                    (local.set $dT2 (f64x2.sub (local.get $nT) (local.get $jT)))
                    (v128.store64_lane offset={{VISIT_NORMAL_IMPULSE}} 0 (local.get $p) (local.get $nN))
                    (v128.store64_lane offset={{VISIT_BYTES + VISIT_NORMAL_IMPULSE}} 1 (local.get $p) (local.get $nN))
                    (v128.store64_lane offset={{VISIT_TANGENT_IMPULSE}} 0 (local.get $p) (local.get $nT))
                    (v128.store64_lane offset={{VISIT_BYTES + VISIT_TANGENT_IMPULSE}} 1 (local.get $p) (local.get $nT))
                    ;; P = (dN·nx + dT·(−ny), dN·ny + dT·nx)
                    (local.set $pX (f64x2.add (f64x2.mul (local.get $dN2) (local.get $nX))
                                              (f64x2.mul (local.get $dT2) (f64x2.neg (local.get $nY)))))
                    (local.set $pY (f64x2.add (f64x2.mul (local.get $dN2) (local.get $nY))
                                              (f64x2.mul (local.get $dT2) (local.get $nX))))
                    (local.set $vaX (f64x2.add (local.get $vaX) (f64x2.mul (local.get $pX) (local.get $iA))))
                    (local.set $vaY (f64x2.add (local.get $vaY) (f64x2.mul (local.get $pY) (local.get $iA))))
                    (local.set $vbX (f64x2.sub (local.get $vbX) (f64x2.mul (local.get $pX) (local.get $iB))))
                    (local.set $vbY (f64x2.sub (local.get $vbY) (f64x2.mul (local.get $pY) (local.get $iB))))
                    (v128.store (local.get $a) (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $vaX) (local.get $vaY)))
                    (v128.store (local.get $a1) (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $vaX) (local.get $vaY)))
                    (v128.store (local.get $b) (i8x16.shuffle 0 1 2 3 4 5 6 7 16 17 18 19 20 21 22 23 (local.get $vbX) (local.get $vbY)))
                    (v128.store (local.get $b1) (i8x16.shuffle 8 9 10 11 12 13 14 15 24 25 26 27 28 29 30 31 (local.get $vbX) (local.get $vbY)))
                    (local.set $p (i32.add (local.get $p) (i32.const {{2 * VISIT_BYTES}})))
                    (br $visit)))))
            (local.set $n (v128.load offset={{VISIT_NORMAL_X}} (local.get $p)))
            ;; (ny, nx)
            (local.set $swapped (i8x16.shuffle 8 9 10 11 12 13 14 15 0 1 2 3 4 5 6 7
                                  (local.get $n) (local.get $n)))
            (local.set $mass (f64.load offset={{VISIT_NORMAL_MASS}} (local.get $p)))
            (local.set $va (v128.load (local.get $a)))
            (local.set $vb (v128.load (local.get $b)))
            (local.set $rel (f64x2.sub (local.get $va) (local.get $vb)))
            ;; Normal: λ' = max(0, λ − vn·mN), as `if (λ' < 0) λ' = 0`; vn = rvx·nx + rvy·ny.
            (local.set $q (f64x2.mul (local.get $rel) (local.get $n)))
            (local.set $oldN (f64.load offset={{VISIT_NORMAL_IMPULSE}} (local.get $p)))
            (local.set $newN (f64.sub (local.get $oldN)
              (f64.mul (f64.add (f64x2.extract_lane 0 (local.get $q)) (f64x2.extract_lane 1 (local.get $q)))
                       (local.get $mass))))
            (local.set $newN (select (f64.const 0) (local.get $newN)
                                     (f64.lt (local.get $newN) (f64.const 0))))
            (local.set $dN (f64.sub (local.get $newN) (local.get $oldN)))
            (f64.store offset={{VISIT_NORMAL_IMPULSE}} (local.get $p) (local.get $newN))
            ;; Friction: τ' = clamp(τ − vt·mN, ±μλ'); vt = rvy·nx − rvx·ny.
            (local.set $q (f64x2.mul (local.get $rel) (local.get $swapped)))
            (local.set $oldT (f64.load offset={{VISIT_TANGENT_IMPULSE}} (local.get $p)))
            (local.set $maxF (f64.mul (local.get $mu) (local.get $newN)))
            (local.set $newT (f64.sub (local.get $oldT)
              (f64.mul (f64.sub (f64x2.extract_lane 1 (local.get $q)) (f64x2.extract_lane 0 (local.get $q)))
                       (local.get $mass))))
            (local.set $newT
              (select (local.get $maxF)
                (select (f64.neg (local.get $maxF)) (local.get $newT)
                        (f64.lt (local.get $newT) (f64.neg (local.get $maxF))))
                (f64.gt (local.get $newT) (local.get $maxF))))
            (local.set $dT (f64.sub (local.get $newT) (local.get $oldT)))
            (f64.store offset={{VISIT_TANGENT_IMPULSE}} (local.get $p) (local.get $newT))
            ;; P = (dN·nx − dT·ny, dN·ny + dT·nx): dN·n + dT·(−ny, nx).
            (local.set $impulse
              (f64x2.add (f64x2.mul (f64x2.splat (local.get $dN)) (local.get $n))
                         (f64x2.mul (f64x2.splat (local.get $dT))
                                    (v128.xor (local.get $swapped)
                                              (v128.const i64x2 0x8000000000000000 0)))))
            (v128.store (local.get $a)
              (f64x2.add (local.get $va)
                         (f64x2.mul (local.get $impulse) (f64x2.splat (f64.load offset={{VISIT_INVERSE_MASS_A}} (local.get $p))))))
            (v128.store (local.get $b)
              (f64x2.sub (local.get $vb)
                         (f64x2.mul (local.get $impulse) (f64x2.splat (f64.load offset={{VISIT_INVERSE_MASS_B}} (local.get $p))))))
            (local.set $p (i32.add (local.get $p) (i32.const {{VISIT_BYTES}})))
            (br $visit)))
        (local.set $it (i32.add (local.get $it) (i32.const 1)))
        (br $iteration))))

  ;; `iterations` sweeps of the position relaxation; positions start at byte `positions`. A body's
  ;; (movedX, movedY) is one f64x2 and its (x, y) the next, and so is a normal: every lane does what
  ;; the JavaScript does to that component (no fused operations), and the predicted separation adds
  ;; lane 0, then lane 1, as the JavaScript does. The JavaScript skips a visit with s ≥ −slop; here
  ;; every visit computes its push and `keep` (all ones where s ≥ −slop) selects the old values
  ;; instead: the same bits, and no branch to mispredict (in a pile about two visits in three keep).
  (func (export "iteratePositions") (param $first i32) (param $count i32) (param $positions i32)
        (param $iterations i32) (param $slop f64) (param $beta f64)
    (local $p i32) (local $end i32) (local $it i32) (local $a i32) (local $b i32)
    (local $n v128) (local $movedA v128) (local $movedB v128) (local $q v128) (local $push v128)
    (local $keep v128) (local $s f64) (local $ia f64) (local $ib f64) (local $c f64)
    (local.set $end (i32.add (local.get $first) (i32.shl (local.get $count) (i32.const {{VISIT_SHIFT}}))))
    (block $done
      (loop $iteration
        (br_if $done (i32.ge_u (local.get $it) (local.get $iterations)))
        (local.set $p (local.get $first))
        (block $swept
          (loop $visit
            (br_if $swept (i32.ge_u (local.get $p) (local.get $end)))
            ;; A position's offset is a velocity's shifted by POSITION_SHIFT − VELOCITY_SHIFT.
            (local.set $a (i32.add (local.get $positions) (i32.shl (i32.load offset={{VISIT_VELOCITY_A}} (local.get $p)) (i32.const {{POSITION_SHIFT - VELOCITY_SHIFT}}))))
            (local.set $b (i32.add (local.get $positions) (i32.shl (i32.load offset={{VISIT_VELOCITY_B}} (local.get $p)) (i32.const {{POSITION_SHIFT - VELOCITY_SHIFT}}))))
            (local.set $n (v128.load offset={{VISIT_NORMAL_X}} (local.get $p)))
            (local.set $movedA (v128.load (local.get $a)))
            (local.set $movedB (v128.load (local.get $b)))
            ;; s = s0 + (ΔAx − ΔBx)·nx + (ΔAy − ΔBy)·ny
            (local.set $q (f64x2.mul (f64x2.sub (local.get $movedA) (local.get $movedB)) (local.get $n)))
            (local.set $s (f64.add (f64.add (f64.load offset={{VISIT_SEPARATION}} (local.get $p)) (f64x2.extract_lane 0 (local.get $q)))
                                   (f64x2.extract_lane 1 (local.get $q))))
            (local.set $keep (f64x2.ge (f64x2.splat (local.get $s)) (f64x2.splat (f64.neg (local.get $slop)))))
            (local.set $ia (f64.load offset={{VISIT_INVERSE_MASS_A}} (local.get $p)))
            (local.set $ib (f64.load offset={{VISIT_INVERSE_MASS_B}} (local.get $p)))
            (local.set $c (f64.div (f64.mul (f64.neg (f64.add (local.get $s) (local.get $slop))) (local.get $beta))
                                   (f64.add (local.get $ia) (local.get $ib))))
            ;; A moves by (c·ia)·n, B by −(c·ib)·n: its motion and its position alike.
            (local.set $push (f64x2.mul (f64x2.splat (f64.mul (local.get $c) (local.get $ia))) (local.get $n)))
            (v128.store (local.get $a) (v128.bitselect (local.get $movedA) (f64x2.add (local.get $movedA) (local.get $push)) (local.get $keep)))
            (local.set $q (v128.load offset={{POSITION_XY}} (local.get $a)))
            (v128.store offset={{POSITION_XY}} (local.get $a) (v128.bitselect (local.get $q) (f64x2.add (local.get $q) (local.get $push)) (local.get $keep)))
            (local.set $push (f64x2.mul (f64x2.splat (f64.mul (local.get $c) (local.get $ib))) (local.get $n)))
            (v128.store (local.get $b) (v128.bitselect (local.get $movedB) (f64x2.sub (local.get $movedB) (local.get $push)) (local.get $keep)))
            (local.set $q (v128.load offset={{POSITION_XY}} (local.get $b)))
            (v128.store offset={{POSITION_XY}} (local.get $b) (v128.bitselect (local.get $q) (f64x2.sub (local.get $q) (local.get $push)) (local.get $keep)))
            (local.set $p (i32.add (local.get $p) (i32.const {{VISIT_BYTES}})))
            (br $visit)))
        (local.set $it (i32.add (local.get $it) (i32.const 1)))
        (br $iteration))))

  ;; SolverSchedule.plan's waves, order and visits (contact-solver.ts does the same in JavaScript,
  ;; and still does it when restitution needs the approach speeds). The contacts in columns at
  ;; $bodyA, $bodyB (i32), $nx, $ny (f64); the solver inverse masses (f64) by body; the $cached
  ;; entries of the warm-start cache in columns at $cachedA, $cachedB (i32), $cachedN, $cachedT
  ;; (f64). Scratch: the cache's chains ($head by body, $next by entry: made here, as
  ;; WarmStartCache.link makes them), $lastWave by body, $waveOf by contact, $waveStart by wave
  ;; (count + 2 of them). Writes the visiting order at $order (i32) and the visits at $visits.
  (func (export "planVisits") (param $count i32) (param $pairs i32) (param $slots i32)
        (param $bodyA i32) (param $bodyB i32) (param $nx i32) (param $ny i32) (param $im i32)
        (param $cached i32) (param $head i32) (param $next i32) (param $cachedA i32) (param $cachedB i32)
        (param $cachedN i32) (param $cachedT i32)
        (param $lastWave i32) (param $waveOf i32) (param $waveStart i32) (param $order i32)
        (param $visits i32)
    (local $k i32) (local $a i32) (local $b i32) (local $wave i32) (local $waveB i32) (local $waves i32)
    (local $w i32) (local $s i32) (local $p i32) (local $q i32) (local $cursor i32)
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
    ;; Each contact's wave, and contacts per wave.
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
        (local.set $p (i32.add (local.get $waveStart) (i32.shl (i32.add (local.get $wave) (i32.const 1)) (i32.const 2))))
        (i32.store (local.get $p) (i32.add (i32.load (local.get $p)) (i32.const 1)))
        (local.set $k (i32.add (local.get $k) (i32.const 1)))
        (br $waveLoop)))
    ;; Where each wave starts (a prefix sum), then the order, stable within a wave.
    (local.set $w (i32.const 1))
    (block $sumDone
      (loop $sum
        (br_if $sumDone (i32.gt_s (local.get $w) (local.get $waves)))
        (local.set $p (i32.add (local.get $waveStart) (i32.shl (local.get $w) (i32.const 2))))
        (i32.store offset=4 (local.get $p) (i32.add (i32.load offset=4 (local.get $p)) (i32.load (local.get $p))))
        (local.set $w (i32.add (local.get $w) (i32.const 1)))
        (br $sum)))
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
        (local.set $p (i32.add (local.get $visits) (i32.shl (local.get $s) (i32.const {{VISIT_SHIFT}}))))
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
        (br $visit))))

  ;; solvePositions' preparation of the visits: each visit's separation (from the column at $sep,
  ;; by contact; $order gives the contact of each visit) over its normal mass, and the inverse
  ;; masses again from the column at $im (by body) — 1 and 0 for a wall, whose correction is whole.
  (func (export "preparePositions") (param $first i32) (param $count i32) (param $pairs i32)
        (param $order i32) (param $sep i32) (param $im i32)
    (local $s i32) (local $p i32) (local $k i32)
    (block $done
      (loop $visit
        (br_if $done (i32.ge_s (local.get $s) (local.get $count)))
        (local.set $p (i32.add (local.get $first) (i32.shl (local.get $s) (i32.const {{VISIT_SHIFT}}))))
        (local.set $k (i32.load (i32.add (local.get $order) (i32.shl (local.get $s) (i32.const 2)))))
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
            (f64.store offset={{VISIT_INVERSE_MASS_B}} (local.get $p) (f64.const 0))))
        (local.set $s (i32.add (local.get $s) (i32.const {{VELOCITY_SHIFT - 3}})))
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
  ;; body); each visit's impulses into the columns at $jn, $jt by contact ($order: each visit's),
  ;; the tangent one + 0 (a −0 becomes +0: the warm-start cache keeps it as it is).
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
        (local.set $p (i32.add (local.get $first) (i32.shl (local.get $s) (i32.const {{VISIT_SHIFT}}))))
        (local.set $k (i32.shl (i32.load (i32.add (local.get $order) (i32.shl (local.get $s) (i32.const 2)))) (i32.const 3)))
        (f64.store (i32.add (local.get $jn) (local.get $k)) (f64.load offset={{VISIT_NORMAL_IMPULSE}} (local.get $p)))
        (f64.store (i32.add (local.get $jt) (local.get $k)) (f64.add (f64.load offset={{VISIT_TANGENT_IMPULSE}} (local.get $p)) (f64.const 0)))
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
