;; The 2D spring kernel of SpringModel in WebAssembly: the source of kernels-wasm.ts, which holds
;; its bytes (regenerate with `npm run build:wasm`; a unit test assembles this file and checks the
;; bytes match). The same float operations in the same order as `accelerations2` in springs.ts,
;; so both give the same bits (WebAssembly's f64 add, sub, mul, div and sqrt are IEEE 754
;; correctly rounded in every engine, like JavaScript's).
;;
;; Every array is a byte offset into the memory the caller provides (SpringModel owns one memory
;; per model: its constants, then the state arrays it hands out).
(module
  (import "env" "memory" (memory 1))

  ;; out[0 .. size) = base[0 .. size); then for each of the n springs, with idx = (dim·a, dim·b)
  ;; as i32 pairs and data = (k, L, c, 1/m_a, 1/m_b) as f64s: d = x_a − x_b, ℓ = |d|, u = d/ℓ,
  ;; f = k·(ℓ − L) + c·u·(v_a − v_b), out_a −= f/m_a·u, out_b += f/m_b·u (skipped when ℓ² = 0).
  (func (export "accelerations2")
    (param $n i32) (param $size i32)
    (param $x i32) (param $v i32) (param $out i32)
    (param $base i32) (param $idx i32) (param $data i32)
    (local $s i32) (local $ia i32) (local $ib i32) (local $o i32)
    (local $ex f64) (local $ey f64) (local $len2 f64) (local $len f64) (local $inv f64)
    (local $ux f64) (local $uy f64) (local $uw f64) (local $f f64) (local $fa f64) (local $fb f64)
    (memory.copy (local.get $out) (local.get $base) (i32.shl (local.get $size) (i32.const 3)))
    (block $done
      (loop $next
        (br_if $done (i32.ge_u (local.get $s) (local.get $n)))
        (local.set $o (i32.add (local.get $idx) (i32.shl (local.get $s) (i32.const 3))))
        (local.set $ia (i32.shl (i32.load (local.get $o)) (i32.const 3)))
        (local.set $ib (i32.shl (i32.load offset=4 (local.get $o)) (i32.const 3)))
        (local.set $ex (f64.sub
          (f64.load (i32.add (local.get $x) (local.get $ia)))
          (f64.load (i32.add (local.get $x) (local.get $ib)))))
        (local.set $ey (f64.sub
          (f64.load offset=8 (i32.add (local.get $x) (local.get $ia)))
          (f64.load offset=8 (i32.add (local.get $x) (local.get $ib)))))
        (local.set $len2 (f64.add
          (f64.add (f64.const 0) (f64.mul (local.get $ex) (local.get $ex)))
          (f64.mul (local.get $ey) (local.get $ey))))
        (if (f64.ne (local.get $len2) (f64.const 0))
          (then
            (local.set $len (f64.sqrt (local.get $len2)))
            (local.set $inv (f64.div (f64.const 1) (local.get $len)))
            (local.set $ux (f64.mul (local.get $ex) (local.get $inv)))
            (local.set $uy (f64.mul (local.get $ey) (local.get $inv)))
            (local.set $uw (f64.add
              (f64.add (f64.const 0) (f64.mul (local.get $ux) (f64.sub
                (f64.load (i32.add (local.get $v) (local.get $ia)))
                (f64.load (i32.add (local.get $v) (local.get $ib))))))
              (f64.mul (local.get $uy) (f64.sub
                (f64.load offset=8 (i32.add (local.get $v) (local.get $ia)))
                (f64.load offset=8 (i32.add (local.get $v) (local.get $ib)))))))
            (local.set $o (i32.add (local.get $data) (i32.mul (local.get $s) (i32.const 40))))
            (local.set $f (f64.add
              (f64.mul (f64.load (local.get $o)) (f64.sub (local.get $len) (f64.load offset=8 (local.get $o))))
              (f64.mul (f64.load offset=16 (local.get $o)) (local.get $uw))))
            (local.set $fa (f64.mul (local.get $f) (f64.load offset=24 (local.get $o))))
            (local.set $fb (f64.mul (local.get $f) (f64.load offset=32 (local.get $o))))
            (local.set $ia (i32.add (local.get $out) (local.get $ia)))
            (local.set $ib (i32.add (local.get $out) (local.get $ib)))
            (f64.store (local.get $ia)
              (f64.sub (f64.load (local.get $ia)) (f64.mul (local.get $fa) (local.get $ux))))
            (f64.store (local.get $ib)
              (f64.add (f64.load (local.get $ib)) (f64.mul (local.get $fb) (local.get $ux))))
            (f64.store offset=8 (local.get $ia)
              (f64.sub (f64.load offset=8 (local.get $ia)) (f64.mul (local.get $fa) (local.get $uy))))
            (f64.store offset=8 (local.get $ib)
              (f64.add (f64.load offset=8 (local.get $ib)) (f64.mul (local.get $fb) (local.get $uy))))))
        (local.set $s (i32.add (local.get $s) (i32.const 1)))
        (br $next))))

  ;; The integrators' kick-drift: v += a·kick, then x += v·drift, element by element.
  (func (export "kickDrift")
    (param $size i32) (param $x i32) (param $v i32) (param $a i32) (param $kick f64) (param $drift f64)
    (local $i i32) (local $end i32) (local $vi f64) (local $p i32)
    (local.set $end (i32.shl (local.get $size) (i32.const 3)))
    (block $done
      (loop $next
        (br_if $done (i32.ge_u (local.get $i) (local.get $end)))
        (local.set $vi (f64.add
          (f64.load (i32.add (local.get $v) (local.get $i)))
          (f64.mul (f64.load (i32.add (local.get $a) (local.get $i))) (local.get $kick))))
        (f64.store (i32.add (local.get $v) (local.get $i)) (local.get $vi))
        (local.set $p (i32.add (local.get $x) (local.get $i)))
        (f64.store (local.get $p) (f64.add (f64.load (local.get $p)) (f64.mul (local.get $vi) (local.get $drift))))
        (local.set $i (i32.add (local.get $i) (i32.const 8)))
        (br $next))))
)
