;; The broad phase's loops; broad-phase.ts has each in JavaScript under the same name (gridBounds,
;; gridCells, bodyPairs), which give the same bits: the grid's bounds and counting sort, and the
;; body–body pairs of a world of circles. A module of its own beside contact-solver.wat (the two
;; share one memory, laid out as kernel-layout.ts says), so each stays under the 4 KB a browser
;; compiles synchronously on its main thread.
(module
  (import "env" "memory" (memory 1))

  ;; Grid.build's first pass (gridBounds in broad-phase.ts): the bounds of the live bodies' centres (the columns
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
    (f64.store offset={{BOUNDS_MIN_X}} (local.get $out) (local.get $minX))
    (f64.store offset={{BOUNDS_MIN_Y}} (local.get $out) (local.get $minY))
    (f64.store offset={{BOUNDS_MAX_X}} (local.get $out) (local.get $maxX))
    (f64.store offset={{BOUNDS_MAX_Y}} (local.get $out) (local.get $maxY))
    (i32.store offset={{BOUNDS_FLAGS}} (local.get $out) (local.get $union)))

  ;; Grid.build's counting sort (Grid.gridCells): each live body's cell, floor((x − minX)·inv) + floor((y − minY)·inv)
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

  ;; One pair of circles of hashedBodyPairs that passed the distance test (bodyPairs has the same
  ;; inline: a call there cost a few per cent of a rollback): skipped (both
  ;; immovable), or its contact (circleCircle) into the columns at $out as contact number $count.
  ;; Returns the new count (the same when skipped), or -1 when contact number $room was due (its two
  ;; bodies at $out − 8).
  (func $pair (param $i i32) (param $j i32) (param $fi i32) (param $ii f64) (param $pj i32)
        (param $im i32) (param $flags i32) (param $dx f64) (param $dy f64) (param $sumW f64)
        (param $d2 f64) (param $count i32) (param $out i32) (param $room i32) (result i32)
    (local $fj i32) (local $q i32) (local $r i32) (local $d f64) (local $nx f64) (local $ny f64) (local $sep f64)
    (block $none
      (local.set $fj (i32.load8_u (i32.add (local.get $flags) (local.get $j))))
      ;; Both immovable: skip — unless a kinematic body touches a sleeping one.
      (br_if $none (i32.and
        (i32.and (f64.eq (local.get $ii) (f64.const 0))
                 (f64.eq (f64.load (i32.add (local.get $im) (local.get $pj))) (f64.const 0)))
        (i32.or (i32.eqz (i32.and (i32.or (local.get $fi) (local.get $fj)) (i32.const {{BODY_ASLEEP}})))
                (i32.eqz (i32.and (i32.or (local.get $fi) (local.get $fj)) (i32.const {{BODY_KINEMATIC}}))))))
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
      (f64.store (i32.add (local.get $r) (i32.shl (local.get $room) (i32.const 4))) (local.get $sep))
      (return (local.get $count)))
    (local.get $count))

  ;; The body–body pairs of a world of circles only, as broad-phase.ts's bodyPairs finds them
  ;; (same cells, same order, same arithmetic). Bodies by id in columns of f64 at $x, $y, $hw (the
  ;; radius), $im (solver inverse mass) and u8 at $flags; the grid's cellStart and cellItems (i32). Contacts
  ;; out in columns of $room from $out: bodyA, bodyB (i32), then nx, ny, separation (f64), lower id
  ;; first. Returns the count, or -1 when contact number $room was due (its two bodies at $out − 8).
  ;; $scratch: room for a body's candidates (i32, as many as there are bodies).
  (func (export "bodyPairs") (param $x i32) (param $y i32) (param $hw i32)
        (param $im i32) (param $flags i32) (param $start i32) (param $items i32)
        (param $rows i32) (param $cols i32) (param $out i32) (param $room i32) (param $scratch i32) (result i32)
    (local $w i32) (local $cy i32) (local $cx i32) (local $c i32) (local $s i32) (local $e i32)
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
                    ;; First the candidates of both passes that pass the distance test, in order, into
                    ;; the list at $scratch — without a branch: each is written, and the end moves on
                    ;; only for one that passes (about a third) — then their contacts.
                    (local.set $w (local.get $scratch))
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
                            (i32.store (local.get $w) (local.get $j))
                            ;; One test where findContacts has five: circles (sumH = sumW) whose
                            ;; d² < sumW² pass its box test (|dx| ≥ sumW gives dx² ≥ sumW², so
                            ;; d² ≥ sumW², rounding being monotonic), and positions are finite.
                            (local.set $w (i32.add (local.get $w) (i32.shl
                              (i32.eqz (f64.ge (f64.add (f64.mul (local.get $dx) (local.get $dx)) (f64.mul (local.get $dy) (local.get $dy)))
                                               (f64.mul (local.get $sumW) (local.get $sumW))))
                              (i32.const 2))))
                            (local.set $m (i32.add (local.get $m) (i32.const 1)))
                            (br $candidate)))
                        (local.set $pass (i32.add (local.get $pass) (i32.const 1)))
                        (br $passLoop)))
                    (local.set $m (local.get $scratch))
                    (block $candidatesDone
                      (loop $candidate
                        (br_if $candidatesDone (i32.ge_u (local.get $m) (local.get $w)))
                        (local.set $j (i32.load (local.get $m)))
                        (local.set $pj (i32.shl (local.get $j) (i32.const 3)))
                        (local.set $dx (f64.sub (local.get $xi) (f64.load (i32.add (local.get $x) (local.get $pj)))))
                        (local.set $dy (f64.sub (local.get $yi) (f64.load (i32.add (local.get $y) (local.get $pj)))))
                        (local.set $sumW (f64.add (local.get $wi) (f64.load (i32.add (local.get $hw) (local.get $pj)))))
                        (local.set $d2 (f64.add (f64.mul (local.get $dx) (local.get $dx)) (f64.mul (local.get $dy) (local.get $dy))))
                        (block $skip
                          (local.set $fj (i32.load8_u (i32.add (local.get $flags) (local.get $j))))
                          ;; Both immovable: skip — unless a kinematic body touches a sleeping one.
                          (br_if $skip (i32.and
                            (i32.and (f64.eq (local.get $ii) (f64.const 0))
                                     (f64.eq (f64.load (i32.add (local.get $im) (local.get $pj))) (f64.const 0)))
                            (i32.or (i32.eqz (i32.and (i32.or (local.get $fi) (local.get $fj)) (i32.const {{BODY_ASLEEP}})))
                                    (i32.eqz (i32.and (i32.or (local.get $fi) (local.get $fj)) (i32.const {{BODY_KINEMATIC}}))))))
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
                          ;; Lower id first, without a branch: the normal times −1 (exact: −n) when j < i.
                          (local.set $fj (i32.lt_s (local.get $j) (local.get $i)))
                          (i32.store (local.get $q) (select (local.get $j) (local.get $i) (local.get $fj)))
                          (i32.store (i32.add (local.get $q) (i32.shl (local.get $room) (i32.const 2))) (select (local.get $i) (local.get $j) (local.get $fj)))
                          (local.set $d (f64.convert_i32_s (i32.sub (i32.const 1) (i32.shl (local.get $fj) (i32.const 1)))))
                          (f64.store (local.get $r) (f64.mul (local.get $nx) (local.get $d)))
                          (f64.store (i32.add (local.get $r) (i32.shl (local.get $room) (i32.const 3))) (f64.mul (local.get $ny) (local.get $d)))
                          (f64.store (i32.add (local.get $r) (i32.shl (local.get $room) (i32.const 4))) (local.get $sep)))
                        (local.set $m (i32.add (local.get $m) (i32.const 4)))
                        (br $candidate)))
                    (local.set $k (i32.add (local.get $k) (i32.const 1)))
                    (br $item)))))
            (local.set $cx (i32.add (local.get $cx) (i32.const 1)))
            (br $col)))
        (local.set $cy (i32.add (local.get $cy) (i32.const 1)))
        (br $row)))
    (local.get $count))

  ;; The body–body pairs of a world of circles only through the hashed grid, as broad-phase.ts's
  ;; hashedBodyPairs finds them (same buckets, cells, order and arithmetic): bucket order, then id
  ;; order; each body meets the bodies after it in its own cell, then those of the cells east,
  ;; north-west, north and north-east (a bucket's bodies filtered by $cellX, $cellY: i32 by body).
  ;; Bucket of cell (cx, cy): (cy·$cols + cx) & $mask in i32. Columns and result as bodyPairs'.
  (func (export "hashedBodyPairs") (param $x i32) (param $y i32) (param $hw i32)
        (param $im i32) (param $flags i32) (param $start i32) (param $items i32)
        (param $cellX i32) (param $cellY i32) (param $mask i32) (param $rows i32) (param $cols i32)
        (param $out i32) (param $room i32) (result i32)
    (local $b i32) (local $e i32) (local $k i32) (local $m i32) (local $to i32) (local $q i32)
    (local $i i32) (local $j i32) (local $pi i32) (local $pj i32) (local $fi i32) (local $count i32)
    (local $cx i32) (local $cy i32) (local $qx i32) (local $qy i32) (local $bucket i32)
    (local $xi f64) (local $yi f64) (local $wi f64) (local $ii f64)
    (local $dx f64) (local $dy f64) (local $sumW f64) (local $d2 f64)
    (block $bucketsDone
      (loop $bucketLoop
        (br_if $bucketsDone (i32.gt_u (local.get $b) (local.get $mask)))
        (local.set $k (i32.load (i32.add (local.get $start) (i32.shl (local.get $b) (i32.const 2)))))
        (local.set $e (i32.load offset=4 (i32.add (local.get $start) (i32.shl (local.get $b) (i32.const 2)))))
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
            (local.set $cx (i32.load (i32.add (local.get $cellX) (i32.shl (local.get $i) (i32.const 2)))))
            (local.set $cy (i32.load (i32.add (local.get $cellY) (i32.shl (local.get $i) (i32.const 2)))))
            ;; Cell 0: its own, from the next body on; 1–4: east, north-west, north, north-east.
            (local.set $q (i32.const 0))
            (block $cellsDone
              (loop $cell
                (br_if $cellsDone (i32.ge_s (local.get $q) (i32.const 5)))
                (local.set $qx (if (result i32) (i32.eqz (local.get $q)) (then (local.get $cx))
                  (else (if (result i32) (i32.eq (local.get $q) (i32.const 1))
                    (then (i32.add (local.get $cx) (i32.const 1)))
                    (else (i32.sub (i32.add (local.get $cx) (local.get $q)) (i32.const 3)))))))
                (local.set $qy (i32.add (local.get $cy) (i32.gt_s (local.get $q) (i32.const 1))))
                (if (i32.eqz (i32.or (i32.or (i32.lt_s (local.get $qx) (i32.const 0))
                                             (i32.ge_s (local.get $qx) (local.get $cols)))
                                     (i32.ge_s (local.get $qy) (local.get $rows))))
                  (then
                    (local.set $bucket
                      (if (result i32) (i32.eqz (local.get $q)) (then (local.get $b))
                        (else (i32.and (i32.add (i32.mul (local.get $qy) (local.get $cols)) (local.get $qx))
                                       (local.get $mask)))))
                    (local.set $m
                      (if (result i32) (i32.eqz (local.get $q)) (then (i32.add (local.get $k) (i32.const 1)))
                        (else (i32.load (i32.add (local.get $start) (i32.shl (local.get $bucket) (i32.const 2)))))))
                    (local.set $to (i32.load offset=4 (i32.add (local.get $start) (i32.shl (local.get $bucket) (i32.const 2)))))
                    (block $candidatesDone
                      (loop $candidate
                        (br_if $candidatesDone (i32.ge_s (local.get $m) (local.get $to)))
                        (local.set $j (i32.load (i32.add (local.get $items) (i32.shl (local.get $m) (i32.const 2)))))
                        (block $skip
                          (br_if $skip (i32.ne (i32.load (i32.add (local.get $cellX) (i32.shl (local.get $j) (i32.const 2))))
                                               (local.get $qx)))
                          (br_if $skip (i32.ne (i32.load (i32.add (local.get $cellY) (i32.shl (local.get $j) (i32.const 2))))
                                               (local.get $qy)))
                          (local.set $pj (i32.shl (local.get $j) (i32.const 3)))
                          (local.set $dx (f64.sub (local.get $xi) (f64.load (i32.add (local.get $x) (local.get $pj)))))
                          (local.set $dy (f64.sub (local.get $yi) (f64.load (i32.add (local.get $y) (local.get $pj)))))
                          (local.set $sumW (f64.add (local.get $wi) (f64.load (i32.add (local.get $hw) (local.get $pj)))))
                          (local.set $d2 (f64.add (f64.mul (local.get $dx) (local.get $dx)) (f64.mul (local.get $dy) (local.get $dy))))
                          ;; bodyPairs' one test for its five.
                          (br_if $skip (f64.ge (local.get $d2) (f64.mul (local.get $sumW) (local.get $sumW))))
                          (local.set $count (call $pair (local.get $i) (local.get $j) (local.get $fi) (local.get $ii)
                            (local.get $pj) (local.get $im) (local.get $flags) (local.get $dx) (local.get $dy)
                            (local.get $sumW) (local.get $d2) (local.get $count) (local.get $out) (local.get $room)))
                          (br_if $skip (i32.ge_s (local.get $count) (i32.const 0)))
                          (return (i32.const -1)))
                        (local.set $m (i32.add (local.get $m) (i32.const 1)))
                        (br $candidate)))))
                (local.set $q (i32.add (local.get $q) (i32.const 1)))
                (br $cell)))
            (local.set $k (i32.add (local.get $k) (i32.const 1)))
            (br $item)))
        (local.set $b (i32.add (local.get $b) (i32.const 1)))
        (br $bucketLoop)))
    (local.get $count))
)
