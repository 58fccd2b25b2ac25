/* test_vdb.c - the OpenVDB density shim against closed-form Gaussians: mass
 * conservation, peak and cross-section values, seamless strand joints, and
 * clean errors on bad files. Also reports sampler throughput. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include "satf/common.h"
#include "satf/density.h"
#include "satf/math.h"

/* Peak density of an untruncated isotropic 3-D Gaussian of mass m. */
static double gaussian_peak(double mass, double sigma) {
  return mass / (pow(2.0 * SATF_PI, 1.5) * sigma * sigma * sigma);
}

/* Fraction of a 1-D Gaussian within +-3 sigma: the builder renormalises each
 * axis by it. */
static double axis_kept_fraction(void) { return erf(3.0 / sqrt(2.0)); }

/* Density at distance r from an infinite line of mass lambda per length whose
 * cross-section is a circular Gaussian (SATF sec. 3.3). */
static double tube_density(double lambda, double sigma, double r) {
  return lambda / (2.0 * SATF_PI * sigma * sigma) *
         exp(-r * r / (2.0 * sigma * sigma));
}

static void tmp_path(char *buf, size_t size, const char *name) {
  const char *dir = getenv("SATF_TEST_TMP");
  snprintf(buf, size, "%s/%s", dir ? dir : ".", name);
}

static double seconds_now(void) {
  struct timespec ts;
  timespec_get(&ts, TIME_UTC);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double rel_err(double got, double want) {
  return fabs(got - want) / fabs(want);
}

static satf_vdb_builder *new_builder(float voxel) {
  satf_vdb_builder *b = NULL;
  satf_error err;
  assert_int_equal(satf_vdb_builder_create(voxel, &b, &err), SATF_OK);
  return b;
}

static satf_vdb_grid *to_grid(const satf_vdb_builder *b) {
  satf_vdb_grid *g = NULL;
  satf_error err;
  assert_int_equal(satf_vdb_builder_to_grid(b, &g, &err), SATF_OK);
  return g;
}

static float sample3(const satf_vdb_grid *g, double x, double y, double z) {
  const float p[3] = {(float)x, (float)y, (float)z};
  return satf_vdb_sample(g, p);
}

/* Writes one Gaussian (mass 2.5, sigma 0.4, voxels sigma/8) to path. */
static const float kCenter[3] = {0.13f, -0.21f, 0.07f};
static const double kSigma = 0.4, kMass = 2.5;
static void write_gaussian_file(const char *path) {
  satf_vdb_builder *b = new_builder(0.05f);
  satf_error err;
  assert_int_equal(satf_vdb_builder_add_gaussian(b, kCenter, (float)kSigma,
                                                 (float)kMass, &err),
                   SATF_OK);
  assert_int_equal(satf_vdb_builder_write(b, path, "density", &err), SATF_OK);
  satf_vdb_builder_destroy(b);
}

static void test_gaussian_round_trip(void **state) {
  (void)state;
  char path[1024], leftover[1100];
  tmp_path(path, sizeof path, "vdb_gaussian.vdb");
  write_gaussian_file(path);

  satf_vdb_grid *g = NULL;
  satf_error err;
  assert_int_equal(satf_vdb_read(path, "density", &g, &err), SATF_OK);
  assert_float_equal(satf_vdb_voxel_size(g), 0.05f, 1e-7f);
  assert_true(rel_err(satf_vdb_total_mass(g), kMass) < 0.01);

  /* The truncated kernel is renormalised, so its peak sits above the
   * untruncated one by 1/erf(3/sqrt 2)^3 (0.8 %); voxel averaging lowers it by
   * 3 h^2 / (24 sigma^2) (0.2 %) and trilinear lookup by up to
   * 3 h^2 / (8 sigma^2) (0.6 %). */
  const double peak = gaussian_peak(kMass, kSigma);
  const double peak_truncated = peak / pow(axis_kept_fraction(), 3.0);
  const double centre = sample3(g, kCenter[0], kCenter[1], kCenter[2]);
  assert_true(rel_err(centre, peak_truncated) < 0.015);
  assert_true(rel_err(centre, peak) < 0.03);
  /* One sigma off-centre along each axis: exp(-1/2) of the peak. */
  for (int a = 0; a < 3; ++a) {
    double p[3] = {kCenter[0], kCenter[1], kCenter[2]};
    p[a] += kSigma;
    const double v = sample3(g, p[0], p[1], p[2]);
    assert_true(rel_err(v, peak_truncated * exp(-0.5)) < 0.015);
  }
  /* Beyond the voxels covering 3 sigma the density is exactly zero. */
  assert_float_equal(
      sample3(g, kCenter[0] + 3.2 * kSigma, kCenter[1], kCenter[2]), 0.0f,
      0.0f);

  /* The box covers centre +- 3 sigma and at most one voxel more. */
  float lo[3], hi[3];
  assert_int_equal(satf_vdb_bbox(g, lo, hi), 1);
  for (int a = 0; a < 3; ++a) {
    assert_true(lo[a] <= kCenter[a] - 3.0 * kSigma + 1e-5);
    assert_true(lo[a] >= kCenter[a] - 3.0 * kSigma - 0.05 - 1e-5);
    assert_true(hi[a] >= kCenter[a] + 3.0 * kSigma - 1e-5);
    assert_true(hi[a] <= kCenter[a] + 3.0 * kSigma + 0.05 + 1e-5);
  }
  satf_vdb_grid_destroy(g);

  /* The temporary file was renamed away. */
  assert_int_equal(satf_temp_path(path, leftover, sizeof leftover, &err),
                   SATF_OK);
  assert_null(fopen(leftover, "rb"));
}

/* A Gaussian much narrower than a voxel keeps its whole mass, in the voxel
 * that contains it. */
static void test_narrow_gaussian(void **state) {
  (void)state;
  satf_vdb_builder *b = new_builder(0.1f);
  satf_error err;
  const float c[3] = {0.31f, 0.02f, -0.04f};
  assert_int_equal(satf_vdb_builder_add_gaussian(b, c, 0.001f, 3.0f, &err),
                   SATF_OK);
  satf_vdb_grid *g = to_grid(b);
  assert_true(rel_err(satf_vdb_total_mass(g), 3.0) < 1e-5);
  /* Voxel centre (0.3, 0, 0) holds mass / h^3 = 3000. */
  assert_true(rel_err(sample3(g, 0.3, 0.0, 0.0), 3000.0) < 1e-4);
  float lo[3], hi[3];
  assert_int_equal(satf_vdb_bbox(g, lo, hi), 1);
  assert_float_equal(lo[0], 0.25f, 1e-5f);
  assert_float_equal(hi[0], 0.35f, 1e-5f);
  satf_vdb_grid_destroy(g);
  satf_vdb_builder_destroy(b);
}

/* Unit vector perpendicular to d. */
static void perpendicular(const double d[3], double out[3]) {
  double v[3] = {d[1], -d[0], 0.0}; /* d x (0,0,1) */
  if (fabs(v[0]) + fabs(v[1]) < 1e-9) {
    v[0] = 1.0;
    v[1] = 0.0;
  }
  const double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int a = 0; a < 3; ++a)
    out[a] = v[a] / n;
}

/* Checks the cross-section of the tube p0-p1 at its midpoint in two
 * perpendicular directions against the circular Gaussian. */
static void check_tube_profile(const float p0[3], const float p1[3],
                               double sigma, double lambda) {
  satf_vdb_builder *b = new_builder(0.05f);
  satf_error err;
  assert_int_equal(
      satf_vdb_builder_add_tube(b, p0, p1, (float)sigma, (float)lambda, &err),
      SATF_OK);
  satf_vdb_grid *g = to_grid(b);
  double d[3], mid[3], u[3], w[3];
  for (int a = 0; a < 3; ++a) {
    d[a] = (double)p1[a] - p0[a];
    mid[a] = 0.5 * ((double)p0[a] + p1[a]);
  }
  const double length = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  assert_true(rel_err(satf_vdb_total_mass(g), lambda * length) < 0.01);

  perpendicular(d, u);
  /* w = d x u / |d|, the second perpendicular direction. */
  w[0] = (d[1] * u[2] - d[2] * u[1]) / length;
  w[1] = (d[2] * u[0] - d[0] * u[2]) / length;
  w[2] = (d[0] * u[1] - d[1] * u[0]) / length;
  /* Each splat is renormalised for 3-sigma truncation on every axis, but
   * along the strand the neighbours' truncated tails make that up, so the
   * cross-section sits 1/erf(3/sqrt 2)^2 (0.5 %) high. Voxel averaging and
   * trilinear lookup then flatten the peak by up to about 1 %. */
  const double norm = 1.0 / pow(axis_kept_fraction(), 2.0);
  const double radii[] = {0.0, 0.5, 1.0, 1.5, 2.0};
  for (size_t i = 0; i < sizeof radii / sizeof radii[0]; ++i) {
    const double r = radii[i] * sigma;
    const double want = norm * tube_density(lambda, sigma, r);
    for (int dir = 0; dir < 2; ++dir) {
      const double *v = dir ? w : u;
      const double got =
          sample3(g, mid[0] + r * v[0], mid[1] + r * v[1], mid[2] + r * v[2]);
      if (rel_err(got, want) >= 0.02)
        fail_msg("tube r=%g sigma dir %d: density %g, want %g", radii[i], dir,
                 got, want);
    }
  }
  satf_vdb_grid_destroy(g);
  satf_vdb_builder_destroy(b);
}

static void test_tube_axis_aligned(void **state) {
  (void)state;
  const float p0[3] = {-1.0f, 0.013f, -0.021f}, p1[3] = {1.2f, 0.013f, -0.021f};
  check_tube_profile(p0, p1, 0.3, 0.7);
}

static void test_tube_oblique(void **state) {
  (void)state;
  const float p0[3] = {-0.6f, -0.5f, -0.4f}, p1[3] = {0.9f, 0.7f, 0.5f};
  check_tube_profile(p0, p1, 0.25, 1.3);
}

/* A strand split into two segments of unequal length gives the same density
 * as one segment, including around the joint. */
static void test_tube_joint_is_seamless(void **state) {
  (void)state;
  const float a[3] = {-1.0f, 0.2f, 0.1f}, m[3] = {0.137f, 0.2f, 0.1f},
              c[3] = {1.5f, 0.2f, 0.1f};
  const float sigma = 0.2f, lambda = 0.5f;
  satf_error err;
  satf_vdb_builder *one = new_builder(0.05f), *two = new_builder(0.05f);
  assert_int_equal(satf_vdb_builder_add_tube(one, a, c, sigma, lambda, &err),
                   SATF_OK);
  assert_int_equal(satf_vdb_builder_add_tube(two, a, m, sigma, lambda, &err),
                   SATF_OK);
  assert_int_equal(satf_vdb_builder_add_tube(two, m, c, sigma, lambda, &err),
                   SATF_OK);
  satf_vdb_grid *g1 = to_grid(one), *g2 = to_grid(two);
  const double axis = tube_density(lambda, sigma, 0.0);
  for (int i = -20; i <= 20; ++i) {
    const double x = m[0] + 0.02 * i;
    for (int k = 0; k < 3; ++k) {
      const double y = m[1] + 0.1 * k;
      const double v1 = sample3(g1, x, y, m[2]), v2 = sample3(g2, x, y, m[2]);
      if (fabs(v1 - v2) >= 0.01 * axis)
        fail_msg("joint x=%g y=%g: one segment %g, two segments %g", x, y, v1,
                 v2);
    }
  }
  assert_true(rel_err(satf_vdb_total_mass(g2), lambda * 2.5) < 0.01);
  satf_vdb_grid_destroy(g1);
  satf_vdb_grid_destroy(g2);
  satf_vdb_builder_destroy(one);
  satf_vdb_builder_destroy(two);
}

/* Real strands are far thinner than a voxel; their mass must still land in
 * the voxels the strand passes through. */
static void test_thin_tube(void **state) {
  (void)state;
  satf_vdb_builder *b = new_builder(0.1f);
  satf_error err;
  const float p0[3] = {0.03f, 0.04f, 0.05f}, p1[3] = {0.83f, 0.44f, 0.25f};
  assert_int_equal(satf_vdb_builder_add_tube(b, p0, p1, 0.004f, 2.0f, &err),
                   SATF_OK);
  satf_vdb_grid *g = to_grid(b);
  const double length = sqrt(0.8 * 0.8 + 0.4 * 0.4 + 0.2 * 0.2);
  assert_true(rel_err(satf_vdb_total_mass(g), 2.0 * length) < 0.01);
  float lo[3], hi[3];
  assert_int_equal(satf_vdb_bbox(g, lo, hi), 1);
  /* The box is the voxels within 3 sigma of the strand. */
  for (int a = 0; a < 3; ++a) {
    assert_true(lo[a] <= p0[a] && lo[a] > p0[a] - 0.012f - 0.1f);
    assert_true(hi[a] >= p1[a] && hi[a] < p1[a] + 0.012f + 0.1f);
  }
  satf_vdb_grid_destroy(g);
  satf_vdb_builder_destroy(b);
}

static void test_wrong_grid_name_and_type(void **state) {
  (void)state;
  char path[1024];
  tmp_path(path, sizeof path, "vdb_mixed.vdb");
  satf_error err;
  assert_int_equal(satf_vdb_write_mixed_test_file(path, &err), SATF_OK);

  satf_vdb_grid *g = NULL;
  assert_int_equal(satf_vdb_read(path, "rho", &g, &err), SATF_ERR_ARGUMENT);
  assert_null(g);
  assert_non_null(strstr(err.message, path));
  assert_non_null(strstr(err.message, "'rho'"));
  assert_non_null(strstr(err.message, "'density'"));
  assert_non_null(strstr(err.message, "'ids'"));
  assert_non_null(strstr(err.message, "'velocity'"));

  const char *not_float[] = {"ids", "velocity"};
  for (int i = 0; i < 2; ++i) {
    satf_error_clear(&err);
    assert_int_equal(satf_vdb_read(path, not_float[i], &g, &err),
                     SATF_ERR_FORMAT);
    assert_null(g);
    assert_non_null(strstr(err.message, path));
    assert_non_null(strstr(err.message, not_float[i]));
  }

  assert_int_equal(satf_vdb_read(path, "density", &g, &err), SATF_OK);
  assert_float_equal(sample3(g, 0.0, 0.0, 0.0), 1.0f, 0.0f);
  /* Half a voxel along x the trilinear weight is 1/2. */
  assert_float_equal(sample3(g, 0.5, 0.0, 0.0), 0.5f, 1e-6f);
  satf_vdb_grid_destroy(g);
}

static void test_missing_file(void **state) {
  (void)state;
  char path[1024];
  tmp_path(path, sizeof path, "vdb_no_such_file.vdb");
  satf_vdb_grid *g = NULL;
  satf_error err;
  assert_int_equal(satf_vdb_read(path, "density", &g, &err), SATF_ERR_IO);
  assert_null(g);
  assert_non_null(strstr(err.message, path));
  /* A NULL err is allowed. */
  assert_int_equal(satf_vdb_read(path, "density", &g, NULL), SATF_ERR_IO);
  /* A directory opens but is no file to read. */
  tmp_path(path, sizeof path, ".");
  assert_int_equal(satf_vdb_read(path, "density", &g, &err), SATF_ERR_IO);
  assert_non_null(strstr(err.message, path));
}

static void write_bytes(const char *path, const void *data, size_t n) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(data, 1, n, f), n);
  assert_int_equal(fclose(f), 0);
}

static void test_not_a_vdb(void **state) {
  (void)state;
  char path[1024];
  tmp_path(path, sizeof path, "vdb_not_vdb.vdb");
  const char text[] = "this is a text file, not a sparse volume\n";
  satf_vdb_grid *g = NULL;
  satf_error err;
  write_bytes(path, text, sizeof text - 1);
  assert_int_equal(satf_vdb_read(path, "density", &g, &err), SATF_ERR_FORMAT);
  assert_non_null(strstr(err.message, path));
  write_bytes(path, text, 0);
  assert_int_equal(satf_vdb_read(path, "density", &g, &err), SATF_ERR_FORMAT);
  assert_null(g);
}

/* Truncating a valid file anywhere must give an error, never a crash or a
 * silently partial grid. */
static void test_truncated_files(void **state) {
  (void)state;
  char path[1024], cut[1024];
  tmp_path(path, sizeof path, "vdb_full.vdb");
  tmp_path(cut, sizeof cut, "vdb_cut.vdb");
  write_gaussian_file(path);
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  static unsigned char data[1 << 22];
  const size_t size = fread(data, 1, sizeof data, f);
  fclose(f);
  assert_true(size > 256 && size < sizeof data);

  const size_t offsets[] = {0,        4,        8,         11,       12,
                            16,       40,       100,       200,      size / 8,
                            size / 4, size / 2, size - 64, size - 8, size - 1};
  for (size_t i = 0; i < sizeof offsets / sizeof offsets[0]; ++i) {
    write_bytes(cut, data, offsets[i]);
    satf_vdb_grid *g = NULL;
    satf_error err;
    satf_error_clear(&err);
    const satf_status st = satf_vdb_read(cut, "density", &g, &err);
    if (st == SATF_OK)
      fail_msg("file cut at %zu of %zu bytes was accepted", offsets[i], size);
    assert_null(g);
    assert_true(st == SATF_ERR_FORMAT || st == SATF_ERR_CORRUPT ||
                st == SATF_ERR_ARGUMENT || st == SATF_ERR_NOMEM);
    assert_non_null(strstr(err.message, cut));
  }
}

static void test_bad_arguments(void **state) {
  (void)state;
  satf_vdb_builder *b = NULL;
  satf_error err;
  assert_int_equal(satf_vdb_builder_create(0.0f, &b, &err), SATF_ERR_ARGUMENT);
  assert_null(b);
  assert_int_equal(satf_vdb_builder_create(NAN, &b, &err), SATF_ERR_ARGUMENT);
  b = new_builder(0.01f);
  const float c[3] = {0.0f, 0.0f, 0.0f}, bad[3] = {0.0f, NAN, 0.0f};
  const float far[3] = {1e9f, 0.0f, 0.0f};
  assert_int_equal(satf_vdb_builder_add_gaussian(b, c, 0.0f, 1.0f, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_vdb_builder_add_gaussian(b, c, 0.1f, -1.0f, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_vdb_builder_add_gaussian(b, bad, 0.1f, 1.0f, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_vdb_builder_add_gaussian(b, far, 0.1f, 1.0f, &err),
                   SATF_ERR_ARGUMENT);
  /* 6 sigma = 600 voxels: refused before allocating anything. */
  assert_int_equal(satf_vdb_builder_add_gaussian(b, c, 1.0f, 1.0f, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "sigma"));
  assert_int_equal(satf_vdb_builder_add_tube(b, c, bad, 0.1f, 1.0f, &err),
                   SATF_ERR_ARGUMENT);
  /* Nothing was added by the failed calls. */
  satf_vdb_grid *g = to_grid(b);
  assert_true(satf_vdb_total_mass(g) == 0.0);
  float lo[3], hi[3];
  assert_int_equal(satf_vdb_bbox(g, lo, hi), 0);
  /* Non-finite sample points read as empty space. */
  assert_float_equal(sample3(g, NAN, 0.0, 0.0), 0.0f, 0.0f);
  assert_float_equal(sample3(g, 1e30, 0.0, 0.0), 0.0f, 0.0f);
  satf_vdb_grid_destroy(g);

  char path[1024];
  tmp_path(path, sizeof path, "no_such_dir/out.vdb");
  assert_int_equal(satf_vdb_builder_write(b, path, "density", &err),
                   SATF_ERR_IO);
  assert_non_null(strstr(err.message, path));
  assert_int_equal(satf_vdb_builder_write(b, path, "", &err),
                   SATF_ERR_ARGUMENT);
  satf_vdb_builder_destroy(b);
}

/* fuzz_vdb.c, compiled in as fuzz_vdb_one. */
int fuzz_vdb_one(const uint8_t *data, size_t size);
const unsigned char *fuzz_vdb_base(size_t *size);

/* One fuzz input: xor byte `offset` of the base file with x. */
static void flip_one(size_t offset, unsigned char x) {
  const uint8_t edit[4] = {(uint8_t)offset, (uint8_t)(offset >> 8),
                           (uint8_t)(offset >> 16), x};
  assert_int_equal(fuzz_vdb_one(edit, sizeof edit), 0);
}

/* Two single-byte changes in the blosc-compressed leaf buffers of the fuzz
 * base file (77529 bytes with OpenVDB 10.0.1) that crashed OpenVDB 10's
 * reader every time, before satf read VDB files in a child process: at
 * 1252 bytes from the end xor 0xe2 (SIGSEGV in free, called from a
 * std::ios_base::failure thrown inside the reader) and at 2000 bytes from
 * the end xor 0x9c (SIGBUS). Both must now be a clean error naming the
 * file. */
static void test_damaged_voxel_data(void **state) {
  (void)state;
  size_t n;
  const unsigned char *base = fuzz_vdb_base(&n);
  assert_true(n > 4096);
  static const struct {
    size_t from_end;
    unsigned char x;
  } cases[] = {{1252, 0xe2}, {2000, 0x9c}};
  char path[1024];
  tmp_path(path, sizeof path, "vdb_damaged.vdb");
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
    unsigned char *d = malloc(n);
    assert_non_null(d);
    memcpy(d, base, n);
    d[n - cases[k].from_end] ^= cases[k].x;
    write_bytes(path, d, n);
    free(d);
    satf_vdb_grid *g = NULL;
    satf_error err;
    const satf_status st = satf_vdb_read(path, "density", &g, &err);
    printf("flip at end-%zu: %s\n", cases[k].from_end,
           st == SATF_OK ? "read" : err.message);
    if (n == 77529) { /* the file the cases were found on */
      assert_int_equal(st, SATF_ERR_CORRUPT);
      assert_non_null(strstr(err.message, path));
      assert_non_null(strstr(err.message, "damaged VDB file"));
    }
    flip_one(n - cases[k].from_end, cases[k].x);
  }
}

/* The fuzz body over byte flips (every 13th byte of the header, every 997th
 * of the topology and voxel data, each with a different xor) and over
 * truncations: each read must load or fail cleanly, never crash. */
static void test_flip_and_truncate_replay(void **state) {
  (void)state;
  size_t n;
  (void)fuzz_vdb_base(&n);
  int tries = 0;
  for (size_t off = 0; off < n; off += off < 512 ? 13 : 997, ++tries)
    flip_one(off, (unsigned char)(0xff >> (tries % 8)));
  for (size_t k = 0; k <= 16; ++k, ++tries) {
    const size_t len = n * k / 16;
    const uint8_t cut[3] = {(uint8_t)len, (uint8_t)(len >> 8),
                            (uint8_t)(len >> 16)};
    assert_int_equal(fuzz_vdb_one(cut, sizeof cut), 0);
  }
  printf("vdb replay: %d damaged files read or refused cleanly\n", tries);
}

/* The reader forks; TBB worker threads started by an earlier bounding box
 * (a threaded OpenVDB algorithm) must not make the child hang. */
static void test_read_with_threads_running(void **state) {
  (void)state;
  char path[1024];
  tmp_path(path, sizeof path, "vdb_threads.vdb");
  write_gaussian_file(path);
  satf_vdb_grid *g = NULL;
  satf_error err;
  float lo[3], hi[3];
  for (int i = 0; i < 3; ++i) {
    assert_int_equal(satf_vdb_read(path, "density", &g, &err), SATF_OK);
    assert_int_equal(satf_vdb_bbox(g, lo, hi), 1);
    assert_true(rel_err(satf_vdb_total_mass(g), kMass) < 1e-6);
    satf_vdb_grid_destroy(g);
  }
}

/* A write that runs out of space (here the file size limit, which fails
 * write() with EFBIG exactly like a full disk fails it with ENOSPC) must
 * fail with the reason, leave an existing file untouched and leave no
 * temporary file. OpenVDB's own writer ignored the error. */
static void test_write_failure(void **state) {
  (void)state;
  char path[1024], tmp[1100];
  tmp_path(path, sizeof path, "vdb_full_disk.vdb");
  snprintf(tmp, sizeof tmp, "%s.tmp-%ld", path, (long)getpid());
  write_bytes(path, "old", 3);
  satf_vdb_builder *b = new_builder(0.05f);
  satf_error err;
  assert_int_equal(satf_vdb_builder_add_gaussian(b, kCenter, (float)kSigma,
                                                 (float)kMass, &err),
                   SATF_OK);
  struct rlimit old_limit, small = {16384, 0};
  assert_int_equal(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  small.rlim_max = old_limit.rlim_max;
  void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
  assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
  const satf_status st = satf_vdb_builder_write(b, path, "density", &err);
  assert_int_equal(setrlimit(RLIMIT_FSIZE, &old_limit), 0);
  signal(SIGXFSZ, old_handler);
  assert_int_equal(st, SATF_ERR_IO);
  assert_non_null(strstr(err.message, path));
  assert_non_null(strstr(err.message, "File too large"));
  assert_int_equal(satf_file_size(path), 3);
  assert_int_equal(satf_file_size(tmp), -1);
  /* Without the limit the same write succeeds and reads back. */
  assert_int_equal(satf_vdb_builder_write(b, path, "density", &err), SATF_OK);
  satf_vdb_builder_destroy(b);
  satf_vdb_grid *g = NULL;
  assert_int_equal(satf_vdb_read(path, "density", &g, &err), SATF_OK);
  assert_true(rel_err(satf_vdb_total_mass(g), kMass) < 1e-6);
  satf_vdb_grid_destroy(g);
}

typedef struct sample_job {
  const satf_vdb_grid *grid;
  const float *xyz;
  float *out;
  size_t chunk, n;
} sample_job;

static int sample_chunk(void *ctx, size_t i, int thread) {
  (void)thread;
  const sample_job *job = ctx;
  const size_t first = i * job->chunk;
  const size_t count =
      first + job->chunk > job->n ? job->n - first : job->chunk;
  satf_vdb_sample_many(job->grid, count, job->xyz + 3 * first,
                       job->out + first);
  return 0;
}

/* Throughput, and two independent checks of the sampler: many threads give
 * the serial answer bit for bit, and the Monte Carlo mean density over the
 * bounding box times its volume recovers the mass (trilinear interpolation
 * integrates each voxel's value over exactly one voxel volume). */
static void test_sampler_speed_and_integral(void **state) {
  (void)state;
  satf_vdb_builder *b = new_builder(0.05f);
  satf_error err;
  assert_int_equal(satf_vdb_builder_add_gaussian(b, kCenter, (float)kSigma,
                                                 (float)kMass, &err),
                   SATF_OK);
  satf_vdb_grid *g = to_grid(b);
  satf_vdb_builder_destroy(b);
  float lo[3], hi[3];
  assert_int_equal(satf_vdb_bbox(g, lo, hi), 1);

  enum { N = 2000000 };
  float *xyz = malloc(sizeof(float) * 3 * N);
  float *serial = malloc(sizeof(float) * N);
  float *parallel = malloc(sizeof(float) * N);
  assert_non_null(xyz);
  assert_non_null(serial);
  assert_non_null(parallel);
  satf_rng rng;
  satf_rng_seed(&rng, 7, 0);
  for (size_t i = 0; i < 3 * (size_t)N; ++i)
    xyz[i] = (float)satf_rng_range(&rng, lo[i % 3], hi[i % 3]);

  double t0 = seconds_now();
  satf_vdb_sample_many(g, N, xyz, serial);
  const double t_many = seconds_now() - t0;
  t0 = seconds_now();
  double sum_single = 0.0;
  for (size_t i = 0; i < N; ++i)
    sum_single += satf_vdb_sample(g, xyz + 3 * i);
  const double t_single = seconds_now() - t0;
  printf("vdb sampler, one thread: sample_many %.1f M samples/s, "
         "sample %.1f M samples/s\n",
         N / t_many * 1e-6, N / t_single * 1e-6);

  double sum = 0.0;
  for (size_t i = 0; i < N; ++i)
    sum += serial[i];
  assert_true(sum == sum_single);
  const double volume = ((double)hi[0] - lo[0]) * ((double)hi[1] - lo[1]) *
                        ((double)hi[2] - lo[2]);
  const double mc_mass = sum / N * volume;
  if (rel_err(mc_mass, kMass) >= 0.01)
    fail_msg("Monte Carlo mass %g, want %g", mc_mass, kMass);

  sample_job job = {g, xyz, parallel, 10000, N};
  assert_int_equal(
      satf_parallel_for(N / 10000, 4, sample_chunk, &job, NULL, NULL), 0);
  assert_memory_equal(serial, parallel, sizeof(float) * N);
  free(xyz);
  free(serial);
  free(parallel);
  satf_vdb_grid_destroy(g);
}

static unsigned char *slurp(const char *path, long *size) {
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  assert_int_equal(fseek(f, 0, SEEK_END), 0);
  *size = ftell(f);
  rewind(f);
  unsigned char *data = malloc((size_t)*size);
  assert_non_null(data);
  assert_int_equal(fread(data, 1, (size_t)*size, f), (size_t)*size);
  fclose(f);
  return data;
}

/* The same density writes the same bytes (OpenVDB's random file UUID is
 * replaced by a digest of the file), other density other bytes and another
 * UUID; the files still read. */
static void test_write_is_reproducible(void **state) {
  (void)state;
  char a[1024], b[1024], c[1024];
  tmp_path(a, sizeof a, "vdb_same_a.vdb");
  tmp_path(b, sizeof b, "vdb_same_b.vdb");
  tmp_path(c, sizeof c, "vdb_same_c.vdb");
  write_gaussian_file(a);
  write_gaussian_file(b);
  satf_vdb_builder *other = new_builder(0.05f);
  satf_error err;
  assert_int_equal(
      satf_vdb_builder_add_gaussian(other, kCenter, 0.3f, 1.0f, &err), SATF_OK);
  assert_int_equal(satf_vdb_builder_write(other, c, "density", &err), SATF_OK);
  satf_vdb_builder_destroy(other);
  long na, nb, nc;
  unsigned char *da = slurp(a, &na), *db = slurp(b, &nb), *dc = slurp(c, &nc);
  assert_int_equal(na, nb);
  assert_memory_equal(da, db, (size_t)na);
  assert_true(na > 60 && nc > 60);
  assert_memory_not_equal(da + 21, dc + 21, 36); /* the UUIDs */
  free(da);
  free(db);
  free(dc);
  satf_vdb_grid *g = NULL;
  assert_int_equal(satf_vdb_read(a, "density", &g, &err), SATF_OK);
  assert_true(rel_err(satf_vdb_total_mass(g), kMass) < 0.01);
  satf_vdb_grid_destroy(g);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_gaussian_round_trip),
      cmocka_unit_test(test_narrow_gaussian),
      cmocka_unit_test(test_tube_axis_aligned),
      cmocka_unit_test(test_tube_oblique),
      cmocka_unit_test(test_tube_joint_is_seamless),
      cmocka_unit_test(test_thin_tube),
      cmocka_unit_test(test_wrong_grid_name_and_type),
      cmocka_unit_test(test_missing_file),
      cmocka_unit_test(test_not_a_vdb),
      cmocka_unit_test(test_truncated_files),
      cmocka_unit_test(test_damaged_voxel_data),
      cmocka_unit_test(test_flip_and_truncate_replay),
      cmocka_unit_test(test_read_with_threads_running),
      cmocka_unit_test(test_write_failure),
      cmocka_unit_test(test_bad_arguments),
      cmocka_unit_test(test_sampler_speed_and_integral),
      cmocka_unit_test(test_write_is_reproducible),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
