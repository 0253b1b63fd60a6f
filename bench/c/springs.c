/*
 * The spring-world step of fixedstep's SpringModel (2D) with semi-implicit Euler or velocity
 * Verlet, as a plain C loop: the reference the `physics-springs` benchmark measures the library
 * against. Compiled at bench time by bench/c/springs.ts with
 *
 *     gcc -O2 -ffp-contract=off -std=c11 springs.c -lm
 *
 * (`-ffp-contract=off`: no fused multiply-add, which would round differently from JavaScript).
 *
 * Same data layout as the library (flat x, v, a of 2·N doubles; springs as parallel arrays) and
 * the same arithmetic in the same order as SpringModel.accelerations and the integrators, so the
 * state after any number of steps is bit-identical to the library's.
 *
 * Usage: springs SCENE_FILE, then one command per line on stdin, one reply line each on stdout:
 *   time K      K steps, timed with clock_gettime(CLOCK_MONOTONIC)  -> "time <ns>"
 *   step K      K steps, untimed                                    -> "ok"
 *   hash        FNV-1a 64 of the bytes of x then v                 -> "hash <16 hex digits>"
 *   dump PATH   write x then v (raw little-endian doubles) to PATH  -> "ok"
 *   reset       back to the scene's start state                     -> "ok"
 *   gc          nothing to collect (the JS program has a gc)        -> "ok"
 *   quit
 * After loading the scene it prints "ready <particles> <springs>"; on any error "error <text>".
 *
 * Scene file (little-endian): u32 magic "FSSP", u32 version 1, u32 method (0 semi-implicit
 * Euler, 1 velocity Verlet), u32 dim (2), u32 particles N, u32 springs S, f64 dt, f64 gx, f64 gy,
 * f64 x[2N], f64 v[2N], f64 inverseMass[N], i32 a[S], i32 b[S], f64 rest[S], f64 k[S], f64 c[S].
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAGIC 0x50535346u /* "FSSP" */

static uint32_t method, count, springs;
static double dt, gx, gy;
static double *x, *v, *a, *x0, *v0, *im, *rest, *stiff, *damp;
static int32_t *sa, *sb;

static void die(const char *what) {
  printf("error %s\n", what);
  fflush(stdout);
  exit(1);
}

static void *alloc(size_t n, size_t size) {
  void *p = calloc(n > 0 ? n : 1, size);
  if (p == NULL) die("out of memory");
  return p;
}

static void readAll(FILE *f, void *p, size_t size, size_t n) {
  if (n > 0 && fread(p, size, n, f) != n) die("scene file too short");
}

/* SpringModel.accelerations, dim = 2. */
static void accelerations(void) {
  for (uint32_t p = 0; p < count; p++) {
    const int free = im[p] > 0;
    a[2 * p] = free ? gx : 0;
    a[2 * p + 1] = free ? gy : 0;
  }
  for (uint32_t s = 0; s < springs; s++) {
    const int32_t pa = sa[s];
    const int32_t pb = sb[s];
    const int32_t ia = 2 * pa;
    const int32_t ib = 2 * pb;
    double len2 = 0;
    const double ex = x[ia] - x[ib];
    len2 += ex * ex;
    const double ey = x[ia + 1] - x[ib + 1];
    len2 += ey * ey;
    if (len2 == 0) continue;
    const double len = sqrt(len2);
    const double inv = 1 / len;
    double uw = 0;
    const double ux = ex * inv;
    uw += ux * (v[ia] - v[ib]);
    const double uy = ey * inv;
    uw += uy * (v[ia + 1] - v[ib + 1]);
    const double f = stiff[s] * (len - rest[s]) + damp[s] * uw;
    const double fa = f * im[pa];
    const double fb = f * im[pb];
    a[ia] = a[ia] - fa * ux;
    a[ib] = a[ib] + fb * ux;
    a[ia + 1] = a[ia + 1] - fa * uy;
    a[ib + 1] = a[ib + 1] + fb * uy;
  }
}

/* v += a(x, v)·dt; x += v·dt. */
static void stepSemiImplicit(void) {
  const uint32_t n = 2 * count;
  accelerations();
  for (uint32_t i = 0; i < n; i++) {
    const double vi = v[i] + a[i] * dt;
    v[i] = vi;
    x[i] = x[i] + vi * dt;
  }
}

/* Kick, drift, a(x, v½), kick; `a` carries over between steps. */
static void stepVelocityVerlet(void) {
  const uint32_t n = 2 * count;
  const double half = 0.5 * dt;
  for (uint32_t i = 0; i < n; i++) {
    const double vh = v[i] + a[i] * half;
    v[i] = vh;
    x[i] = x[i] + vh * dt;
  }
  accelerations();
  for (uint32_t i = 0; i < n; i++) v[i] = v[i] + a[i] * half;
}

static void run(long steps) {
  if (method == 0)
    for (long k = 0; k < steps; k++) stepSemiImplicit();
  else
    for (long k = 0; k < steps; k++) stepVelocityVerlet();
}

static void reset(void) {
  memcpy(x, x0, 2 * count * sizeof(double));
  memcpy(v, v0, 2 * count * sizeof(double));
  memset(a, 0, 2 * count * sizeof(double));
  if (method == 1) accelerations(); /* velocity Verlet's start */
}

static void fnv(uint64_t *h, const void *p, size_t n) {
  const unsigned char *b = p;
  for (size_t i = 0; i < n; i++) {
    *h ^= b[i];
    *h *= 0x100000001b3ull;
  }
}

static void load(const char *path) {
  FILE *f = fopen(path, "rb");
  if (f == NULL) die("cannot open the scene file");
  uint32_t head[6];
  readAll(f, head, sizeof head[0], 6);
  if (head[0] != MAGIC || head[1] != 1) die("not a version 1 scene file");
  if (head[2] > 1 || head[3] != 2) die("unsupported method or dimension");
  method = head[2];
  count = head[4];
  springs = head[5];
  double params[3];
  readAll(f, params, sizeof params[0], 3);
  dt = params[0];
  gx = params[1];
  gy = params[2];
  const size_t n = 2 * (size_t)count;
  x = alloc(n, sizeof *x);
  v = alloc(n, sizeof *v);
  a = alloc(n, sizeof *a);
  x0 = alloc(n, sizeof *x0);
  v0 = alloc(n, sizeof *v0);
  im = alloc(count, sizeof *im);
  sa = alloc(springs, sizeof *sa);
  sb = alloc(springs, sizeof *sb);
  rest = alloc(springs, sizeof *rest);
  stiff = alloc(springs, sizeof *stiff);
  damp = alloc(springs, sizeof *damp);
  readAll(f, x0, sizeof *x0, n);
  readAll(f, v0, sizeof *v0, n);
  readAll(f, im, sizeof *im, count);
  readAll(f, sa, sizeof *sa, springs);
  readAll(f, sb, sizeof *sb, springs);
  readAll(f, rest, sizeof *rest, springs);
  readAll(f, stiff, sizeof *stiff, springs);
  readAll(f, damp, sizeof *damp, springs);
  if (fgetc(f) != EOF) die("scene file too long");
  fclose(f);
  for (uint32_t s = 0; s < springs; s++) {
    if (sa[s] < 0 || (uint32_t)sa[s] >= count || sb[s] < 0 || (uint32_t)sb[s] >= count)
      die("spring end out of range");
  }
}

int main(int argc, char **argv) {
  if (argc != 2) die("usage: springs SCENE_FILE");
  load(argv[1]);
  reset();
  printf("ready %u %u\n", count, springs);
  fflush(stdout);
  char line[4096];
  while (fgets(line, sizeof line, stdin) != NULL) {
    line[strcspn(line, "\r\n")] = 0;
    long k = 0;
    if (sscanf(line, "time %ld", &k) == 1) {
      struct timespec t0, t1;
      clock_gettime(CLOCK_MONOTONIC, &t0);
      run(k);
      clock_gettime(CLOCK_MONOTONIC, &t1);
      const long long ns =
          (long long)(t1.tv_sec - t0.tv_sec) * 1000000000LL + (t1.tv_nsec - t0.tv_nsec);
      printf("time %lld\n", ns);
    } else if (sscanf(line, "step %ld", &k) == 1) {
      run(k);
      printf("ok\n");
    } else if (strcmp(line, "hash") == 0) {
      uint64_t h = 0xcbf29ce484222325ull;
      fnv(&h, x, 2 * count * sizeof(double));
      fnv(&h, v, 2 * count * sizeof(double));
      printf("hash %016llx\n", (unsigned long long)h);
    } else if (strncmp(line, "dump ", 5) == 0) {
      FILE *f = fopen(line + 5, "wb");
      if (f == NULL) die("cannot write the dump file");
      fwrite(x, sizeof *x, 2 * count, f);
      fwrite(v, sizeof *v, 2 * count, f);
      fclose(f);
      printf("ok\n");
    } else if (strcmp(line, "gc") == 0) {
      printf("ok\n");
    } else if (strcmp(line, "reset") == 0) {
      reset();
      printf("ok\n");
    } else if (strcmp(line, "quit") == 0) {
      break;
    } else {
      printf("error unknown command\n");
    }
    fflush(stdout);
  }
  return 0;
}
