;; The contact solver's inner loops (contact-solver.ts has the same three in JavaScript, which give
;; the same bits: the same IEEE-754 operations in the same order, and `select` exactly where the
;; JavaScript branches). Everything lives in the imported memory, laid out as SolverSchedule
;; describes: velocities (vx, vy) 16 bytes a body, positions (movedX, movedY, x, y) 32 bytes a body,
;; visits 64 bytes each — nx, ny, normal mass (the separation for positions), inverse masses of A
;; and B, normal and tangent impulse (f64), then the byte offsets of A's and B's velocities (i32).
(module
  (import "env" "memory" (memory 1))

  ;; Warm start: each visit's impulses applied once (a visit whose two impulses are 0 is skipped).
  (func (export "warmStart") (param $p i32) (param $count i32)
    (local $end i32) (local $a i32) (local $b i32)
    (local $jn f64) (local $jt f64) (local $nx f64) (local $ny f64)
    (local $px f64) (local $py f64) (local $ia f64) (local $ib f64)
    (local.set $end (i32.add (local.get $p) (i32.shl (local.get $count) (i32.const 6))))
    (block $done
      (loop $visit
        (br_if $done (i32.ge_u (local.get $p) (local.get $end)))
        (local.set $jn (f64.load offset=40 (local.get $p)))
        (local.set $jt (f64.load offset=48 (local.get $p)))
        (if (i32.eqz (i32.and (f64.eq (local.get $jn) (f64.const 0))
                              (f64.eq (local.get $jt) (f64.const 0))))
          (then
            (local.set $a (i32.load offset=56 (local.get $p)))
            (local.set $b (i32.load offset=60 (local.get $p)))
            (local.set $nx (f64.load (local.get $p)))
            (local.set $ny (f64.load offset=8 (local.get $p)))
            (local.set $px (f64.sub (f64.mul (local.get $jn) (local.get $nx))
                                    (f64.mul (local.get $jt) (local.get $ny))))
            (local.set $py (f64.add (f64.mul (local.get $jn) (local.get $ny))
                                    (f64.mul (local.get $jt) (local.get $nx))))
            (local.set $ia (f64.load offset=24 (local.get $p)))
            (local.set $ib (f64.load offset=32 (local.get $p)))
            (f64.store (local.get $a)
              (f64.add (f64.load (local.get $a)) (f64.mul (local.get $px) (local.get $ia))))
            (f64.store offset=8 (local.get $a)
              (f64.add (f64.load offset=8 (local.get $a)) (f64.mul (local.get $py) (local.get $ia))))
            (f64.store (local.get $b)
              (f64.sub (f64.load (local.get $b)) (f64.mul (local.get $px) (local.get $ib))))
            (f64.store offset=8 (local.get $b)
              (f64.sub (f64.load offset=8 (local.get $b)) (f64.mul (local.get $py) (local.get $ib))))))
        (local.set $p (i32.add (local.get $p) (i32.const 64)))
        (br $visit))))

  ;; `iterations` sweeps of sequential impulses over `count` visits from byte `first`. A body's
  ;; (vx, vy) is one f64x2, and so is a normal: every lane does what the JavaScript does to that
  ;; component (IEEE-754 per lane, no fused operations), and the dot products add lane 0 and lane 1
  ;; in the JavaScript's order. The impulse is P = λ·(nx, ny) + τ·(−ny, nx): lane 0 adds −(τ·ny),
  ;; which is subtracting τ·ny.
  (func (export "velocities") (param $first i32) (param $count i32) (param $iterations i32) (param $mu f64)
    (local $p i32) (local $end i32) (local $it i32) (local $a i32) (local $b i32)
    (local $n v128) (local $swapped v128) (local $va v128) (local $vb v128) (local $rel v128)
    (local $q v128) (local $impulse v128) (local $mass f64)
    (local $oldN f64) (local $newN f64) (local $dN f64) (local $oldT f64) (local $newT f64)
    (local $dT f64) (local $maxF f64)
    (local.set $end (i32.add (local.get $first) (i32.shl (local.get $count) (i32.const 6))))
    (block $done
      (loop $iteration
        (br_if $done (i32.ge_u (local.get $it) (local.get $iterations)))
        (local.set $p (local.get $first))
        (block $swept
          (loop $visit
            (br_if $swept (i32.ge_u (local.get $p) (local.get $end)))
            (local.set $a (i32.load offset=56 (local.get $p)))
            (local.set $b (i32.load offset=60 (local.get $p)))
            (local.set $n (v128.load (local.get $p)))
            ;; (ny, nx)
            (local.set $swapped (i8x16.shuffle 8 9 10 11 12 13 14 15 0 1 2 3 4 5 6 7
                                  (local.get $n) (local.get $n)))
            (local.set $mass (f64.load offset=16 (local.get $p)))
            (local.set $va (v128.load (local.get $a)))
            (local.set $vb (v128.load (local.get $b)))
            (local.set $rel (f64x2.sub (local.get $va) (local.get $vb)))
            ;; Normal: λ' = max(0, λ − vn·mN), as `if (λ' < 0) λ' = 0`; vn = rvx·nx + rvy·ny.
            (local.set $q (f64x2.mul (local.get $rel) (local.get $n)))
            (local.set $oldN (f64.load offset=40 (local.get $p)))
            (local.set $newN (f64.sub (local.get $oldN)
              (f64.mul (f64.add (f64x2.extract_lane 0 (local.get $q)) (f64x2.extract_lane 1 (local.get $q)))
                       (local.get $mass))))
            (local.set $newN (select (f64.const 0) (local.get $newN)
                                     (f64.lt (local.get $newN) (f64.const 0))))
            (local.set $dN (f64.sub (local.get $newN) (local.get $oldN)))
            (f64.store offset=40 (local.get $p) (local.get $newN))
            ;; Friction: τ' = clamp(τ − vt·mN, ±μλ'); vt = rvy·nx − rvx·ny.
            (local.set $q (f64x2.mul (local.get $rel) (local.get $swapped)))
            (local.set $oldT (f64.load offset=48 (local.get $p)))
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
            (f64.store offset=48 (local.get $p) (local.get $newT))
            ;; P = (dN·nx − dT·ny, dN·ny + dT·nx): dN·n + dT·(−ny, nx).
            (local.set $impulse
              (f64x2.add (f64x2.mul (f64x2.splat (local.get $dN)) (local.get $n))
                         (f64x2.mul (f64x2.splat (local.get $dT))
                                    (v128.xor (local.get $swapped)
                                              (v128.const i64x2 0x8000000000000000 0)))))
            (v128.store (local.get $a)
              (f64x2.add (local.get $va)
                         (f64x2.mul (local.get $impulse) (f64x2.splat (f64.load offset=24 (local.get $p))))))
            (v128.store (local.get $b)
              (f64x2.sub (local.get $vb)
                         (f64x2.mul (local.get $impulse) (f64x2.splat (f64.load offset=32 (local.get $p))))))
            (local.set $p (i32.add (local.get $p) (i32.const 64)))
            (br $visit)))
        (local.set $it (i32.add (local.get $it) (i32.const 1)))
        (br $iteration))))

  ;; `iterations` sweeps of the position relaxation; positions start at byte `positions`. A body's
  ;; (movedX, movedY) is one f64x2 and its (x, y) the next, and so is a normal: every lane does what
  ;; the JavaScript does to that component (no fused operations), and the predicted separation adds
  ;; lane 0, then lane 1, as the JavaScript does.
  (func (export "positions") (param $first i32) (param $count i32) (param $positions i32)
        (param $iterations i32) (param $slop f64) (param $beta f64)
    (local $p i32) (local $end i32) (local $it i32) (local $a i32) (local $b i32)
    (local $n v128) (local $movedA v128) (local $movedB v128) (local $q v128) (local $push v128)
    (local $s f64) (local $ia f64) (local $ib f64) (local $c f64)
    (local.set $end (i32.add (local.get $first) (i32.shl (local.get $count) (i32.const 6))))
    (block $done
      (loop $iteration
        (br_if $done (i32.ge_u (local.get $it) (local.get $iterations)))
        (local.set $p (local.get $first))
        (block $swept
          (loop $visit
            (br_if $swept (i32.ge_u (local.get $p) (local.get $end)))
            ;; 32 bytes a body here, twice a velocity's 16.
            (local.set $a (i32.add (local.get $positions) (i32.shl (i32.load offset=56 (local.get $p)) (i32.const 1))))
            (local.set $b (i32.add (local.get $positions) (i32.shl (i32.load offset=60 (local.get $p)) (i32.const 1))))
            (local.set $n (v128.load (local.get $p)))
            (local.set $movedA (v128.load (local.get $a)))
            (local.set $movedB (v128.load (local.get $b)))
            ;; s = s0 + (ΔAx − ΔBx)·nx + (ΔAy − ΔBy)·ny
            (local.set $q (f64x2.mul (f64x2.sub (local.get $movedA) (local.get $movedB)) (local.get $n)))
            (local.set $s (f64.add (f64.add (f64.load offset=16 (local.get $p)) (f64x2.extract_lane 0 (local.get $q)))
                                   (f64x2.extract_lane 1 (local.get $q))))
            (if (i32.eqz (f64.ge (local.get $s) (f64.neg (local.get $slop))))
              (then
                (local.set $ia (f64.load offset=24 (local.get $p)))
                (local.set $ib (f64.load offset=32 (local.get $p)))
                (local.set $c (f64.div (f64.mul (f64.neg (f64.add (local.get $s) (local.get $slop))) (local.get $beta))
                                       (f64.add (local.get $ia) (local.get $ib))))
                ;; A moves by (c·ia)·n, B by −(c·ib)·n: its motion and its position alike.
                (local.set $push (f64x2.mul (f64x2.splat (f64.mul (local.get $c) (local.get $ia))) (local.get $n)))
                (v128.store (local.get $a) (f64x2.add (local.get $movedA) (local.get $push)))
                (v128.store offset=16 (local.get $a) (f64x2.add (v128.load offset=16 (local.get $a)) (local.get $push)))
                (local.set $push (f64x2.mul (f64x2.splat (f64.mul (local.get $c) (local.get $ib))) (local.get $n)))
                (v128.store (local.get $b) (f64x2.sub (local.get $movedB) (local.get $push)))
                (v128.store offset=16 (local.get $b) (f64x2.sub (v128.load offset=16 (local.get $b)) (local.get $push)))))
            (local.set $p (i32.add (local.get $p) (i32.const 64)))
            (br $visit)))
        (local.set $it (i32.add (local.get $it) (i32.const 1)))
        (br $iteration))))

  ;; The body–body pairs of a world of circles only, as broad-phase.ts's findContacts finds them
  ;; (same cells, same order, same arithmetic). Bodies by id in columns of f64 at $x, $y, $hw (the
  ;; radius), $im (solver inverse mass) and u8 at $flags; the grid's cellStart and cellItems (i32). Contacts
  ;; out in columns of $room from $out: bodyA, bodyB (i32), then nx, ny, separation (f64), lower id
  ;; first. Returns the count, or -1 when contact number $room was due (its two bodies at $out − 8).
  (func (export "circlePairs") (param $x i32) (param $y i32) (param $hw i32)
        (param $im i32) (param $flags i32) (param $start i32) (param $items i32)
        (param $rows i32) (param $cols i32) (param $out i32) (param $room i32) (result i32)
    (local $cy i32) (local $cx i32) (local $c i32) (local $s i32) (local $e i32)
    (local $sameRowEnd i32) (local $upStart i32) (local $upEnd i32) (local $up i32)
    (local $k i32) (local $m i32) (local $to i32) (local $pass i32)
    (local $i i32) (local $j i32) (local $pi i32) (local $pj i32) (local $fi i32) (local $fj i32)
    (local $count i32) (local $q i32) (local $r i32)
    (local $xi f64) (local $yi f64) (local $wi f64) (local $ii f64)
    (local $dx f64) (local $dy f64) (local $sumW f64) (local $d2 f64) (local $d f64)
    (local $nx f64) (local $ny f64) (local $sep f64)
    (block $rowsDone
      (loop $row
        (br_if $rowsDone (i32.ge_s (local.get $cy) (local.get $rows)))
        (local.set $cx (i32.const 0))
        (block $colsDone
          (loop $col
            (br_if $colsDone (i32.ge_s (local.get $cx) (local.get $cols)))
            (local.set $c (i32.add (i32.mul (local.get $cy) (local.get $cols)) (local.get $cx)))
            (local.set $s (i32.load (i32.add (local.get $start) (i32.shl (local.get $c) (i32.const 2)))))
            (local.set $e (i32.load offset=4 (i32.add (local.get $start) (i32.shl (local.get $c) (i32.const 2)))))
            (if (i32.ne (local.get $s) (local.get $e))
              (then
                (local.set $sameRowEnd
                  (if (result i32) (i32.lt_s (i32.add (local.get $cx) (i32.const 1)) (local.get $cols))
                    (then (i32.load offset=8 (i32.add (local.get $start) (i32.shl (local.get $c) (i32.const 2)))))
                    (else (local.get $e))))
                (local.set $upStart (i32.const 0))
                (local.set $upEnd (i32.const 0))
                (if (i32.lt_s (i32.add (local.get $cy) (i32.const 1)) (local.get $rows))
                  (then
                    (local.set $up (i32.add (local.get $c) (local.get $cols)))
                    (local.set $upStart (i32.load (i32.add (local.get $start) (i32.shl
                      (if (result i32) (i32.gt_s (local.get $cx) (i32.const 0))
                        (then (i32.sub (local.get $up) (i32.const 1))) (else (local.get $up)))
                      (i32.const 2)))))
                    (local.set $upEnd (i32.load (i32.add (local.get $start) (i32.shl
                      (if (result i32) (i32.lt_s (i32.add (local.get $cx) (i32.const 1)) (local.get $cols))
                        (then (i32.add (local.get $up) (i32.const 2))) (else (i32.add (local.get $up) (i32.const 1))))
                      (i32.const 2)))))))
                (local.set $k (local.get $s))
                (block $itemsDone
                  (loop $item
                    (br_if $itemsDone (i32.ge_s (local.get $k) (local.get $e)))
                    (local.set $i (i32.load (i32.add (local.get $items) (i32.shl (local.get $k) (i32.const 2)))))
                    (local.set $pi (i32.shl (local.get $i) (i32.const 3)))
                    (local.set $fi (i32.load8_u (i32.add (local.get $flags) (local.get $i))))
                    (local.set $xi (f64.load (i32.add (local.get $x) (local.get $pi))))
                    (local.set $yi (f64.load (i32.add (local.get $y) (local.get $pi))))
                    (local.set $wi (f64.load (i32.add (local.get $hw) (local.get $pi))))
                    (local.set $ii (f64.load (i32.add (local.get $im) (local.get $pi))))
                    (local.set $pass (i32.const 0))
                    (block $passesDone
                      (loop $passLoop
                        (br_if $passesDone (i32.ge_s (local.get $pass) (i32.const 2)))
                        (if (i32.eqz (local.get $pass))
                          (then (local.set $m (i32.add (local.get $k) (i32.const 1))) (local.set $to (local.get $sameRowEnd)))
                          (else (local.set $m (local.get $upStart)) (local.set $to (local.get $upEnd))))
                        (block $candidatesDone
                          (loop $candidate
                            (br_if $candidatesDone (i32.ge_s (local.get $m) (local.get $to)))
                            (local.set $j (i32.load (i32.add (local.get $items) (i32.shl (local.get $m) (i32.const 2)))))
                            (local.set $pj (i32.shl (local.get $j) (i32.const 3)))
                            (local.set $dx (f64.sub (local.get $xi) (f64.load (i32.add (local.get $x) (local.get $pj)))))
                            (local.set $dy (f64.sub (local.get $yi) (f64.load (i32.add (local.get $y) (local.get $pj)))))
                            (local.set $sumW (f64.add (local.get $wi) (f64.load (i32.add (local.get $hw) (local.get $pj)))))
                            (local.set $d2 (f64.add (f64.mul (local.get $dx) (local.get $dx)) (f64.mul (local.get $dy) (local.get $dy))))
                            (block $skip
                              ;; One test where findContacts has five: circles (sumH = sumW) whose
                              ;; d² < sumW² pass its box test (|dx| ≥ sumW gives dx² ≥ sumW², so
                              ;; d² ≥ sumW², rounding being monotonic), and positions are finite.
                              (br_if $skip (f64.ge (local.get $d2) (f64.mul (local.get $sumW) (local.get $sumW))))
                              (local.set $fj (i32.load8_u (i32.add (local.get $flags) (local.get $j))))
                              ;; Both immovable: skip — unless a kinematic body touches a sleeping one.
                              (br_if $skip (i32.and
                                (i32.and (f64.eq (local.get $ii) (f64.const 0))
                                         (f64.eq (f64.load (i32.add (local.get $im) (local.get $pj))) (f64.const 0)))
                                (i32.or (i32.eqz (i32.and (i32.or (local.get $fi) (local.get $fj)) (i32.const 16)))
                                        (i32.eqz (i32.and (i32.or (local.get $fi) (local.get $fj)) (i32.const 8))))))
                              ;; circleCircle
                              (local.set $d (f64.sqrt (local.get $d2)))
                              (if (f64.gt (local.get $d) (f64.const 0))
                                (then
                                  (local.set $nx (f64.div (local.get $dx) (local.get $d)))
                                  (local.set $ny (f64.div (local.get $dy) (local.get $d)))
                                  (local.set $sep (f64.sub (local.get $d) (local.get $sumW))))
                                (else
                                  (local.set $nx (f64.const 0))
                                  (local.set $ny (f64.const 1))
                                  (local.set $sep (f64.neg (local.get $sumW)))))
                              (if (i32.eq (local.get $count) (local.get $room))
                                (then
                                  (i32.store offset=0 (i32.sub (local.get $out) (i32.const 8)) (local.get $i))
                                  (i32.store offset=4 (i32.sub (local.get $out) (i32.const 8)) (local.get $j))
                                  (return (i32.const -1))))
                              ;; Columns: bodyA at $out, bodyB 4·room on, then nx, ny, separation 8·room apart.
                              (local.set $q (i32.add (local.get $out) (i32.shl (local.get $count) (i32.const 2))))
                              (local.set $r (i32.add (i32.add (local.get $out) (i32.shl (local.get $room) (i32.const 3)))
                                                     (i32.shl (local.get $count) (i32.const 3))))
                              (local.set $count (i32.add (local.get $count) (i32.const 1)))
                              (if (i32.lt_s (local.get $j) (local.get $i))
                                (then
                                  (i32.store (local.get $q) (local.get $j))
                                  (i32.store (i32.add (local.get $q) (i32.shl (local.get $room) (i32.const 2))) (local.get $i))
                                  (f64.store (local.get $r) (f64.neg (local.get $nx)))
                                  (f64.store (i32.add (local.get $r) (i32.shl (local.get $room) (i32.const 3))) (f64.neg (local.get $ny))))
                                (else
                                  (i32.store (local.get $q) (local.get $i))
                                  (i32.store (i32.add (local.get $q) (i32.shl (local.get $room) (i32.const 2))) (local.get $j))
                                  (f64.store (local.get $r) (local.get $nx))
                                  (f64.store (i32.add (local.get $r) (i32.shl (local.get $room) (i32.const 3))) (local.get $ny))))
                              (f64.store (i32.add (local.get $r) (i32.shl (local.get $room) (i32.const 4))) (local.get $sep)))
                            (local.set $m (i32.add (local.get $m) (i32.const 1)))
                            (br $candidate)))
                        (local.set $pass (i32.add (local.get $pass) (i32.const 1)))
                        (br $passLoop)))
                    (local.set $k (i32.add (local.get $k) (i32.const 1)))
                    (br $item)))))
            (local.set $cx (i32.add (local.get $cx) (i32.const 1)))
            (br $col)))
        (local.set $cy (i32.add (local.get $cy) (i32.const 1)))
        (br $row)))
    (local.get $count))

  ;; SolverSchedule.plan's waves, order and visits (contact-solver.ts does the same in JavaScript,
  ;; and still does it when restitution needs the approach speeds). The contacts in columns at
  ;; $bodyA, $bodyB (i32), $nx, $ny (f64); the solver inverse masses (f64) and the warm-start
  ;; cache's head (i32) by body; its next, bodyB (i32), normal and tangent impulses (f64) by entry.
  ;; Scratch: $lastWave by body, $waveOf by contact, $waveStart by wave (count + 2 of them).
  ;; Writes the visiting order at $order (i32) and the visits at $visits.
  (func (export "plan") (param $count i32) (param $pairs i32) (param $slots i32)
        (param $bodyA i32) (param $bodyB i32) (param $nx i32) (param $ny i32) (param $im i32)
        (param $head i32) (param $next i32) (param $cachedB i32) (param $cachedN i32) (param $cachedT i32)
        (param $lastWave i32) (param $waveOf i32) (param $waveStart i32) (param $order i32)
        (param $visits i32)
    (local $k i32) (local $a i32) (local $b i32) (local $wave i32) (local $waveB i32) (local $waves i32)
    (local $w i32) (local $s i32) (local $p i32) (local $q i32)
    (local $ia f64) (local $ib f64) (local $mass f64) (local $jn f64) (local $jt f64)
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
    (local.set $k (i32.const 0))
    (block $orderDone
      (loop $orderLoop
        (br_if $orderDone (i32.ge_s (local.get $k) (local.get $count)))
        (local.set $p (i32.add (local.get $waveStart)
          (i32.shl (i32.load (i32.add (local.get $waveOf) (i32.shl (local.get $k) (i32.const 2)))) (i32.const 2))))
        (local.set $s (i32.load (local.get $p)))
        (i32.store (local.get $p) (i32.add (local.get $s) (i32.const 1)))
        (i32.store (i32.add (local.get $order) (i32.shl (local.get $s) (i32.const 2))) (local.get $k))
        (local.set $k (i32.add (local.get $k) (i32.const 1)))
        (br $orderLoop)))
    ;; The visits, in order.
    (local.set $s (i32.const 0))
    (block $visitsDone
      (loop $visit
        (br_if $visitsDone (i32.ge_s (local.get $s) (local.get $count)))
        (local.set $k (i32.load (i32.add (local.get $order) (i32.shl (local.get $s) (i32.const 2)))))
        (local.set $a (i32.load (i32.add (local.get $bodyA) (i32.shl (local.get $k) (i32.const 2)))))
        (local.set $b (i32.load (i32.add (local.get $bodyB) (i32.shl (local.get $k) (i32.const 2)))))
        (local.set $p (i32.add (local.get $visits) (i32.shl (local.get $s) (i32.const 6))))
        (local.set $ia (f64.load (i32.add (local.get $im) (i32.shl (local.get $a) (i32.const 3)))))
        (if (i32.lt_s (local.get $k) (local.get $pairs))
          (then
            (local.set $ib (f64.load (i32.add (local.get $im) (i32.shl (local.get $b) (i32.const 3)))))
            (local.set $mass (f64.div (f64.const 1) (f64.add (local.get $ia) (local.get $ib))))
            (f64.store offset=32 (local.get $p) (local.get $ib))
            (i32.store offset=60 (local.get $p) (i32.shl (local.get $b) (i32.const 4))))
          (else
            (local.set $mass (f64.div (f64.const 1) (local.get $ia)))
            (f64.store offset=32 (local.get $p) (f64.const 0))
            (i32.store offset=60 (local.get $p)
              (i32.shl (i32.sub (i32.add (local.get $slots) (local.get $k)) (local.get $pairs)) (i32.const 4)))))
        ;; Last step's impulses for the same pair: the first entry of A's chain with B.
        (local.set $jn (f64.const 0))
        (local.set $jt (f64.const 0))
        (local.set $w (i32.load (i32.add (local.get $head) (i32.shl (local.get $a) (i32.const 2)))))
        (block $found
          (loop $chain
            (br_if $found (i32.eq (local.get $w) (i32.const -1)))
            (if (i32.eq (i32.load (i32.add (local.get $cachedB) (i32.shl (local.get $w) (i32.const 2)))) (local.get $b))
              (then
                (local.set $jn (f64.load (i32.add (local.get $cachedN) (i32.shl (local.get $w) (i32.const 3)))))
                (local.set $jt (f64.load (i32.add (local.get $cachedT) (i32.shl (local.get $w) (i32.const 3)))))
                (br $found)))
            (local.set $w (i32.load (i32.add (local.get $next) (i32.shl (local.get $w) (i32.const 2)))))
            (br $chain)))
        (local.set $q (i32.shl (local.get $k) (i32.const 3)))
        (f64.store (local.get $p) (f64.load (i32.add (local.get $nx) (local.get $q))))
        (f64.store offset=8 (local.get $p) (f64.load (i32.add (local.get $ny) (local.get $q))))
        (f64.store offset=16 (local.get $p) (local.get $mass))
        (f64.store offset=24 (local.get $p) (local.get $ia))
        (f64.store offset=40 (local.get $p) (local.get $jn))
        (f64.store offset=48 (local.get $p) (local.get $jt))
        (i32.store offset=56 (local.get $p) (i32.shl (local.get $a) (i32.const 4)))
        (local.set $s (i32.add (local.get $s) (i32.const 1)))
        (br $visit))))

  ;; solvePositions' preparation of the visits: each visit's separation (from the column at $sep,
  ;; by contact; $order gives the contact of each visit) over its normal mass, and the inverse
  ;; masses again from the column at $im (by body) — 1 and 0 for a wall, whose correction is whole.
  (func (export "positionsPrep") (param $first i32) (param $count i32) (param $pairs i32)
        (param $order i32) (param $sep i32) (param $im i32)
    (local $s i32) (local $p i32) (local $k i32)
    (block $done
      (loop $visit
        (br_if $done (i32.ge_s (local.get $s) (local.get $count)))
        (local.set $p (i32.add (local.get $first) (i32.shl (local.get $s) (i32.const 6))))
        (local.set $k (i32.load (i32.add (local.get $order) (i32.shl (local.get $s) (i32.const 2)))))
        (f64.store offset=16 (local.get $p)
          (f64.load (i32.add (local.get $sep) (i32.shl (local.get $k) (i32.const 3)))))
        (if (i32.lt_s (local.get $k) (local.get $pairs))
          (then
            ;; A velocity's byte offset is 16 a body; an inverse mass's is 8.
            (f64.store offset=24 (local.get $p)
              (f64.load (i32.add (local.get $im) (i32.shr_u (i32.load offset=56 (local.get $p)) (i32.const 1)))))
            (f64.store offset=32 (local.get $p)
              (f64.load (i32.add (local.get $im) (i32.shr_u (i32.load offset=60 (local.get $p)) (i32.const 1))))))
          (else
            (f64.store offset=24 (local.get $p) (f64.const 1))
            (f64.store offset=32 (local.get $p) (f64.const 0))))
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
        (f64.store (i32.shl (local.get $p) (i32.const 1)) (f64.load (i32.add (local.get $vx) (local.get $p))))
        (f64.store offset=8 (i32.shl (local.get $p) (i32.const 1)) (f64.load (i32.add (local.get $vy) (local.get $p))))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $body)))
    (memory.fill (i32.shl (local.get $slots) (i32.const 4)) (i32.const 0) (i32.shl (local.get $standIns) (i32.const 4))))

  ;; Velocities and impulses out: the velocities from byte 0 into the columns at $vx, $vy (by
  ;; body); each visit's impulses into the columns at $jn, $jt by contact ($order: each visit's).
  (func (export "velocitiesOut") (param $first i32) (param $count i32) (param $slots i32)
        (param $order i32) (param $vx i32) (param $vy i32) (param $jn i32) (param $jt i32)
    (local $i i32) (local $p i32) (local $s i32) (local $k i32)
    (block $done
      (loop $body
        (br_if $done (i32.ge_s (local.get $i) (local.get $slots)))
        (local.set $p (i32.shl (local.get $i) (i32.const 3)))
        (f64.store (i32.add (local.get $vx) (local.get $p)) (f64.load (i32.shl (local.get $p) (i32.const 1))))
        (f64.store (i32.add (local.get $vy) (local.get $p)) (f64.load offset=8 (i32.shl (local.get $p) (i32.const 1))))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $body)))
    (block $visitsDone
      (loop $visit
        (br_if $visitsDone (i32.ge_s (local.get $s) (local.get $count)))
        (local.set $p (i32.add (local.get $first) (i32.shl (local.get $s) (i32.const 6))))
        (local.set $k (i32.shl (i32.load (i32.add (local.get $order) (i32.shl (local.get $s) (i32.const 2)))) (i32.const 3)))
        (f64.store (i32.add (local.get $jn) (local.get $k)) (f64.load offset=40 (local.get $p)))
        (f64.store (i32.add (local.get $jt) (local.get $k)) (f64.load offset=48 (local.get $p)))
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
        (f64.store offset=16 (local.get $p) (local.get $px))
        (f64.store offset=24 (local.get $p) (local.get $py))
        (local.set $p (i32.add (local.get $p) (i32.const 32)))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $body)))
    (memory.fill (local.get $p) (i32.const 0) (i32.shl (local.get $standIns) (i32.const 5))))

  ;; Positions out: each body's x and y from the 32 bytes a body from $at into the columns at $x, $y.
  (func (export "positionsOut") (param $slots i32) (param $at i32) (param $x i32) (param $y i32)
    (local $i i32) (local $q i32) (local $p i32)
    (local.set $p (local.get $at))
    (block $done
      (loop $body
        (br_if $done (i32.ge_s (local.get $i) (local.get $slots)))
        (local.set $q (i32.shl (local.get $i) (i32.const 3)))
        (f64.store (i32.add (local.get $x) (local.get $q)) (f64.load offset=16 (local.get $p)))
        (f64.store (i32.add (local.get $y) (local.get $q)) (f64.load offset=24 (local.get $p)))
        (local.set $p (i32.add (local.get $p) (i32.const 32)))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $body))))

  ;; Grid.build's first pass (broad-phase.ts): the bounds of the live bodies' centres (the columns
  ;; at $x, $y, f64, and $flags, u8, by body) into 4 f64 at $out (min x, min y, max x, max y), each
  ;; compared as the JavaScript compares (`if (v < min) min = v`), then every flag or-ed (i32);
  ;; $cellOf (i32 by body) gets −1 for a free slot, else 0.
  (func (export "gridBounds") (param $n i32) (param $x i32) (param $y i32) (param $flags i32)
        (param $cellOf i32) (param $out i32)
    (local $i i32) (local $q i32) (local $f i32) (local $union i32) (local $a f64) (local $b f64)
    (local $minX f64) (local $minY f64) (local $maxX f64) (local $maxY f64)
    (local.set $minX (f64.const inf))
    (local.set $minY (f64.const inf))
    (local.set $maxX (f64.const -inf))
    (local.set $maxY (f64.const -inf))
    (block $done
      (loop $body
        (br_if $done (i32.ge_s (local.get $i) (local.get $n)))
        (local.set $f (i32.load8_u (i32.add (local.get $flags) (local.get $i))))
        (local.set $union (i32.or (local.get $union) (local.get $f)))
        (if (i32.eqz (local.get $f))
          (then (i32.store (i32.add (local.get $cellOf) (i32.shl (local.get $i) (i32.const 2))) (i32.const -1)))
          (else
            (i32.store (i32.add (local.get $cellOf) (i32.shl (local.get $i) (i32.const 2))) (i32.const 0))
            (local.set $q (i32.shl (local.get $i) (i32.const 3)))
            (local.set $a (f64.load (i32.add (local.get $x) (local.get $q))))
            (local.set $b (f64.load (i32.add (local.get $y) (local.get $q))))
            (local.set $minX (select (local.get $a) (local.get $minX) (f64.lt (local.get $a) (local.get $minX))))
            (local.set $maxX (select (local.get $a) (local.get $maxX) (f64.gt (local.get $a) (local.get $maxX))))
            (local.set $minY (select (local.get $b) (local.get $minY) (f64.lt (local.get $b) (local.get $minY))))
            (local.set $maxY (select (local.get $b) (local.get $maxY) (f64.gt (local.get $b) (local.get $maxY))))))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $body)))
    (f64.store (local.get $out) (local.get $minX))
    (f64.store offset=8 (local.get $out) (local.get $minY))
    (f64.store offset=16 (local.get $out) (local.get $maxX))
    (f64.store offset=24 (local.get $out) (local.get $maxY))
    (i32.store offset=32 (local.get $out) (local.get $union)))

  ;; Grid.build's counting sort: each live body's cell, floor((x − minX)·inv) + floor((y − minY)·inv)
  ;; · cols, into $cellOf; the cells' starts (i32, $cells + 1 of them) at $start; the body ids in cell
  ;; order, id order within a cell, at $items; $cursor is scratch ($cells of i32).
  (func (export "gridCells") (param $n i32) (param $x i32) (param $y i32) (param $cellOf i32)
        (param $minX f64) (param $minY f64) (param $inv f64) (param $cols i32) (param $cells i32)
        (param $start i32) (param $cursor i32) (param $items i32)
    (local $i i32) (local $q i32) (local $c i32) (local $at i32) (local $s i32) (local $colsF f64)
    (local.set $colsF (f64.convert_i32_s (local.get $cols)))
    (memory.fill (local.get $start) (i32.const 0) (i32.shl (i32.add (local.get $cells) (i32.const 1)) (i32.const 2)))
    (block $done
      (loop $body
        (br_if $done (i32.ge_s (local.get $i) (local.get $n)))
        (local.set $at (i32.add (local.get $cellOf) (i32.shl (local.get $i) (i32.const 2))))
        (if (i32.ne (i32.load (local.get $at)) (i32.const -1))
          (then
            (local.set $q (i32.shl (local.get $i) (i32.const 3)))
            (local.set $c (i32.trunc_f64_s
              (f64.add
                (f64.floor (f64.mul (f64.sub (f64.load (i32.add (local.get $x) (local.get $q))) (local.get $minX)) (local.get $inv)))
                (f64.mul
                  (f64.floor (f64.mul (f64.sub (f64.load (i32.add (local.get $y) (local.get $q))) (local.get $minY)) (local.get $inv)))
                  (local.get $colsF)))))
            (i32.store (local.get $at) (local.get $c))
            (local.set $at (i32.add (local.get $start) (i32.shl (i32.add (local.get $c) (i32.const 1)) (i32.const 2))))
            (i32.store (local.get $at) (i32.add (i32.load (local.get $at)) (i32.const 1)))))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $body)))
    (local.set $c (i32.const 0))
    (block $done
      (loop $cell
        (br_if $done (i32.ge_s (local.get $c) (local.get $cells)))
        (local.set $at (i32.add (local.get $start) (i32.shl (local.get $c) (i32.const 2))))
        (local.set $s (i32.load (local.get $at)))
        (i32.store offset=4 (local.get $at) (i32.add (i32.load offset=4 (local.get $at)) (local.get $s)))
        (i32.store (i32.add (local.get $cursor) (i32.shl (local.get $c) (i32.const 2))) (local.get $s))
        (local.set $c (i32.add (local.get $c) (i32.const 1)))
        (br $cell)))
    (local.set $i (i32.const 0))
    (block $done
      (loop $body
        (br_if $done (i32.ge_s (local.get $i) (local.get $n)))
        (local.set $c (i32.load (i32.add (local.get $cellOf) (i32.shl (local.get $i) (i32.const 2)))))
        (if (i32.ne (local.get $c) (i32.const -1))
          (then
            (local.set $at (i32.add (local.get $cursor) (i32.shl (local.get $c) (i32.const 2))))
            (local.set $s (i32.load (local.get $at)))
            (i32.store (local.get $at) (i32.add (local.get $s) (i32.const 1)))
            (i32.store (i32.add (local.get $items) (i32.shl (local.get $s) (i32.const 2))) (local.get $i))))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $body))))
)
