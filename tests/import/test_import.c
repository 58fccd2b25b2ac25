/* test_import.c - strands to clusters (satf/import.h): k-means, recovery of
 * a known generalized cylinder from strands generated around it, density
 * mass (per cluster and in the world-space .vdb, read back with OpenVDB),
 * macro-clusters from copies under known similarity transforms, and scene
 * files that satf_scene_load accepts. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "import_internal.h"
#include "satf/common.h"
#include "test_util.h"

#define PI_F 3.14159265358979f

/* The known cylinder: a bent trajectory about 21 long, A from 1.8 to 1.2
 * along n1, B from 0.9 to 0.6 along n2 and a twist of 2 radians (all
 * linear, so control values are function values). */
static satf_cluster *known_cluster(void) {
  static const float traj[] = {0, 0,   0,    0,    -4,  1, 1, -8,  3,
                               2, -12, 3.5f, 2.5f, -16, 3, 3, -20, 2};
  float a[2] = {1.8f, 1.2f}, b[2] = {0.9f, 0.6f}, tw[2] = {0.0f, 2.0f};
  satf_cluster_desc d = {6, traj, 2, a, b, tw};
  satf_cluster *c;
  satf_error err;
  assert_int_equal(satf_cluster_create(&d, &c, &err), SATF_OK);
  return c;
}

/* n strands of m points at fixed (v, u), v = sqrt(uniform) so they fill
 * the cross-section uniformly, optionally mapped by the 3x4 matrix mat. */
static void gc_strands(const satf_cluster *c, int n, int m, uint64_t seed,
                       const double *mat, float *pts, int *counts) {
  satf_rng rng;
  satf_rng_seed(&rng, seed, 0);
  for (int i = 0; i < n; i++) {
    float v = (float)sqrt(satf_rng_uniform(&rng));
    float u = (float)(2.0 * 3.14159265358979323846 * satf_rng_uniform(&rng));
    counts[i] = m;
    for (int k = 0; k < m; k++) {
      float p[3], *q = pts + 3 * ((size_t)i * m + k);
      satf_cluster_point(c, (float)k / (float)(m - 1), v, u, p);
      for (int r = 0; r < 3; r++)
        q[r] = mat ? (float)(mat[4 * r] * p[0] + mat[4 * r + 1] * p[1] +
                             mat[4 * r + 2] * p[2] + mat[4 * r + 3])
                   : p[r];
    }
  }
}

static satf_strand_set *known_strands(int n, int m) {
  satf_cluster *c = known_cluster();
  float *pts = malloc(3 * (size_t)n * m * sizeof(float));
  int *counts = malloc((size_t)n * sizeof(int));
  gc_strands(c, n, m, 42, NULL, pts, counts);
  satf_strand_set *s;
  satf_error err;
  assert_int_equal(satf_strand_set_create(n, counts, pts, NULL, &s, &err),
                   SATF_OK);
  free(pts);
  free(counts);
  satf_cluster_destroy(c);
  return s;
}

static int *all_members(int n) {
  int *m = malloc((size_t)n * sizeof(int));
  for (int i = 0; i < n; i++)
    m[i] = i;
  return m;
}

/* Straight parallel strands along -y within the unit disc, N of M points:
 * strand i begins root_step * i down and is 9 + len_step * i long
 * (i / (N - 1) of each step); the cluster fitted to them all. */
enum { PARALLEL_N = 200, PARALLEL_M = 20 };
typedef struct parallel {
  float pts[3 * PARALLEL_N * PARALLEL_M];
  satf_strand_set *set;
  satf_import_fit fit;
  satf_cluster *cluster;
} parallel;

static parallel *parallel_fit(float root_step, float len_base, float len_step) {
  enum { N = PARALLEL_N, M = PARALLEL_M };
  parallel *p = calloc(1, sizeof *p);
  int *counts = malloc((size_t)N * sizeof(int));
  assert_non_null(p);
  assert_non_null(counts);
  satf_rng rng;
  satf_rng_seed(&rng, 7, 0);
  for (int i = 0; i < N; i++) {
    float r = (float)sqrt(satf_rng_uniform(&rng));
    float u = (float)(2.0 * 3.14159265358979323846 * satf_rng_uniform(&rng));
    float f = (float)i / (float)(N - 1);
    float root = -root_step * f, len = len_base + len_step * f;
    counts[i] = M;
    for (int k = 0; k < M; k++) {
      float *q = p->pts + 3 * ((size_t)i * M + k);
      q[0] = r * cosf(u);
      q[1] = root - len * (float)k / (float)(M - 1);
      q[2] = r * sinf(u);
    }
  }
  satf_error err;
  assert_int_equal(
      satf_strand_set_create(N, counts, p->pts, NULL, &p->set, &err), SATF_OK);
  free(counts);
  int *members = all_members(N);
  satf_import_fit_params fp = satf_import_fit_params_default();
  assert_int_equal(
      satf_import_fit_cluster(p->set, members, N, &fp, &p->fit, &err), SATF_OK);
  free(members);
  assert_int_equal(satf_import_fit_cluster_create(&p->fit, &p->cluster, &err),
                   SATF_OK);
  return p;
}

static void parallel_free(parallel *p) {
  satf_cluster_destroy(p->cluster);
  satf_import_fit_free(&p->fit);
  satf_strand_set_destroy(p->set);
  free(p);
}

/* Where point k of strand i of p projects onto its cluster (t). */
static float parallel_t(const parallel *p, int i, int k) {
  float t, d, xy[2];
  satf_import_project_point(
      p->cluster, p->pts + 3 * ((size_t)i * PARALLEL_M + k), &t, &d, xy);
  return t;
}

/* Straight parallel strands of lengths 9 to 10: the cluster runs to the
 * longest tip, so t = 1 is where the last strand ends and every tip lies
 * at its own t (the mean strand, 9.5 long, cut the longer half square at
 * t = 1, where their tips all projected). */
static void fit_reaches_last_tip(void **state) {
  (void)state;
  enum { N = PARALLEL_N };
  parallel *p = parallel_fit(0.0f, 9.0f, 1.0f);
  printf("cluster length %.3f for strands 9 to 10 long\n",
         (double)p->fit.length);
  assert_float_equal(p->fit.length, 10.0f, 0.05f);
  int at_end = 0;
  for (int i = 0; i < N; i++) {
    float t = parallel_t(p, i, PARALLEL_M - 1);
    float want = (9.0f + (float)i / (float)(N - 1)) / 10.0f;
    if (fabsf(t - want) > 0.01f)
      fail_msg("strand %d: tip at t = %g, expected %g", i, (double)t,
               (double)want);
    at_end += t >= 0.995f;
  }
  printf("%d of %d tips at t >= 0.995\n", at_end, N);
  assert_true(at_end <= N / 10 + 1);
  parallel_free(p);
}

/* Straight parallel strands 10 long whose roots lie 0 to 0.3 along the
 * flow (a curtain's roots, jittered where they leave the scalp): the
 * cluster begins at the first root, so every root lies at its own t (the
 * mean strand began at the mean root, cutting the half of the strands
 * that began before it square at t = 0). */
static void fit_reaches_first_root(void **state) {
  (void)state;
  enum { N = PARALLEL_N };
  parallel *p = parallel_fit(0.3f, 10.0f, 0.0f);
  printf("cluster length %.3f for roots 0 to 0.3 down, tips 10.0 to 10.3\n",
         (double)p->fit.length);
  assert_float_equal(p->fit.length, 10.3f, 0.05f);
  int at_start = 0;
  for (int i = 0; i < N; i++) {
    float t = parallel_t(p, i, 0);
    float want = 0.3f * (float)i / (float)(N - 1) / 10.3f;
    if (fabsf(t - want) > 0.005f)
      fail_msg("strand %d: root at t = %g, expected %g", i, (double)t,
               (double)want);
    at_start += t <= 0.001f;
  }
  printf("%d of %d roots at t <= 0.001\n", at_start, N);
  assert_true(at_start <= N / 10 + 1);
  parallel_free(p);
}

static void fit_recovers_known_cylinder(void **state) {
  (void)state;
  enum { N = 400, M = 25 };
  satf_strand_set *s = known_strands(N, M);
  int *members = all_members(N);
  satf_import_fit fit;
  satf_error err;
  satf_import_fit_params p = satf_import_fit_params_default();
  assert_int_equal(satf_import_fit_cluster(s, members, N, &p, &fit, &err),
                   SATF_OK);
  assert_int_equal(fit.strands, N);
  assert_int_equal(fit.points, N * M);
  /* envelope coverage at least 95% */
  assert_true((double)fit.inside >= 0.95 * (double)fit.points);
  satf_cluster *truth = known_cluster(), *got;
  assert_int_equal(satf_import_fit_cluster_create(&fit, &got, &err), SATF_OK);
  assert_float_equal(fit.length, satf_cluster_length(truth),
                     0.01f * satf_cluster_length(truth));
  satf_cluster_section s0, g0;
  satf_cluster_section_at(truth, 0.0f, &s0);
  satf_cluster_section_at(got, 0.0f, &g0);
  for (int k = 0; k <= 20; k++) {
    float t = (float)k / 20.0f, p3[3], tf, d, xy[2];
    satf_cluster_trajectory(truth, t, p3, NULL);
    satf_import_project_point(got, p3, &tf, &d, xy);
    /* the trajectory within 0.08 (4% of the smallest radius x 2) */
    if (d > 0.08f)
      fail_msg("t = %g: trajectory off by %g", (double)t, (double)d);
    if (k < 2 || k > 18)
      continue; /* radii and twist: away from the ends */
    satf_cluster_section st, sg;
    satf_cluster_section_at(truth, t, &st);
    satf_cluster_section_at(got, tf, &sg);
    /* 95% of a uniform disk lies within sqrt(0.95) = 0.975 of its edge */
    if (fabsf(sg.a / (0.975f * st.a) - 1.0f) > 0.08f ||
        fabsf(sg.b / (0.975f * st.b) - 1.0f) > 0.08f)
      fail_msg("t = %g: axes %g x %g, expected %g x %g", (double)t,
               (double)sg.a, (double)sg.b, (double)(0.975f * st.a),
               (double)(0.975f * st.b));
    float tw_true = st.theta - s0.theta, tw_got = sg.theta - g0.theta;
    if (fabsf(tw_true - tw_got) > 0.12f)
      fail_msg("t = %g: twist %g, expected %g", (double)t, (double)tw_got,
               (double)tw_true);
  }
  /* mean distance of points to the trajectory: about 2/3 of the mean
   * radius for a uniform disk */
  double mean = fit.distance_sum / (double)fit.points;
  assert_true(mean > 0.5 && mean < 1.0);
  satf_cluster_destroy(truth);
  satf_cluster_destroy(got);
  satf_import_fit_free(&fit);
  free(members);
  satf_strand_set_destroy(s);
}

/* A ribbon (A = 1.6, B = 0.3) on the known trajectory twisted one full
 * turn, built here from the untwisted rotation-minimising frame (n1, n2)
 * rather than by the geometry under test: the major axis at t is
 * cos(2 pi t) n1 + sin(2 pi t) n2, and the point at (t, v, u) is
 * T + v (A cos u, B sin u) on the turned axes. */
enum { RIBBON_N = 400, RIBBON_M = 49 };
static const float kRibbonA = 1.6f, kRibbonB = 0.3f;

static void ribbon_axes(const satf_cluster *c, float t, float T[3], float e1[3],
                        float e2[3]) {
  float tan[3], n1[3], n2[3];
  double th = 2.0 * PI_F * t;
  satf_cluster_trajectory(c, t, T, NULL);
  satf_cluster_frame(c, t, tan, n1, n2);
  for (int r = 0; r < 3; r++) {
    e1[r] = (float)(cos(th) * n1[r] + sin(th) * n2[r]);
    e2[r] = (float)(-sin(th) * n1[r] + cos(th) * n2[r]);
  }
}

static satf_strand_set *ribbon_strands(const satf_cluster *c) {
  enum { N = RIBBON_N, M = RIBBON_M };
  float *pts = malloc(3 * (size_t)N * M * sizeof(float));
  int *counts = malloc((size_t)N * sizeof(int));
  satf_rng rng;
  satf_rng_seed(&rng, 7, 0);
  for (int i = 0; i < N; i++) {
    double v = sqrt(satf_rng_uniform(&rng));
    double u = 2.0 * PI_F * satf_rng_uniform(&rng);
    double x = kRibbonA * v * cos(u), y = kRibbonB * v * sin(u);
    counts[i] = M;
    for (int k = 0; k < M; k++) {
      float T[3], e1[3], e2[3], *q = pts + 3 * ((size_t)i * M + k);
      ribbon_axes(c, (float)k / (float)(M - 1), T, e1, e2);
      for (int r = 0; r < 3; r++)
        q[r] = (float)(T[r] + x * e1[r] + y * e2[r]);
    }
  }
  satf_strand_set *s;
  satf_error err;
  assert_int_equal(satf_strand_set_create(N, counts, pts, NULL, &s, &err),
                   SATF_OK);
  free(pts);
  free(counts);
  return s;
}

/* theta - expect wrapped into [-pi/2, pi/2): an ellipse turned by pi is
 * the same ellipse. */
static double half_turn_error(double theta, double expect) {
  double e = theta - expect;
  return e - PI_F * floor((e + 0.5 * PI_F) / PI_F);
}

/* How far the fit is from the ribbon at the ribbon's t: the angle between
 * the major axes, theta(t) - theta(0.1) against 2 pi (t - 0.1), and the
 * ratio of the envelope areas pi A B. */
typedef struct ribbon_error {
  double axis, twist, area_lo, area_hi;
} ribbon_error;

static ribbon_error ribbon_compare(const satf_cluster *truth,
                                   const satf_cluster *got) {
  ribbon_error e = {0.0, 0.0, 1e9, 0.0};
  float theta0 = 0.0f;
  for (int k = 2; k <= 18; k++) { /* away from the ends */
    float t = (float)k / 20.0f, T[3], e1[3], e2[3], tf, d, xy[2];
    ribbon_axes(truth, t, T, e1, e2);
    satf_import_project_point(got, T, &tf, &d, xy);
    satf_cluster_section sg;
    satf_cluster_section_at(got, tf, &sg);
    if (k == 2)
      theta0 = sg.theta;
    /* the fitted major axis, whichever of A and B the fit put on it */
    const float *major = sg.a >= sg.b ? sg.n1 : sg.n2;
    double c = fabs(test_dot3(e1, major));
    e.axis = fmax(e.axis, acos(c < 1.0 ? c : 1.0));
    e.twist =
        fmax(e.twist,
             fabs(half_turn_error(sg.theta - theta0, 2.0 * PI_F * (t - 0.1))));
    double ratio = (double)sg.a * sg.b / ((double)kRibbonA * kRibbonB);
    e.area_lo = fmin(e.area_lo, ratio);
    e.area_hi = fmax(e.area_hi, ratio);
  }
  return e;
}

/* Strands around a twisted ribbon: the fit turns its ellipse with them.
 * The fitted major axis lies along the ribbon's and theta(t) advances as
 * the ribbon turns (from t = 0.1, away from the spline's end), both within
 * 0.1 rad: the twist is read from 32 bins of t, each about 600 points
 * whose principal axis is good to ~0.01 rad, averaged about the bin's
 * centre, and a linear twist is reproduced exactly by the spline; measured
 * 0.02-0.03 rad (the fitted trajectory is not exactly the generating one),
 * while a bin is 0.2 rad of twist and a fit that did not turn would be off
 * by up to pi/2. The envelope then holds 95% of the points and is tight:
 * its area pi A B stays within 0.8x-1.5x of the ribbon's (0.95x for a
 * uniformly filled ellipse scaled to 95%); an envelope left on the
 * untwisted axes must be about as wide as A in every direction (~2.7x). */
static void fit_recovers_twisted_ribbon(void **state) {
  (void)state;
  enum { N = RIBBON_N };
  satf_cluster *truth = known_cluster(), *got;
  satf_strand_set *s = ribbon_strands(truth);
  int *members = all_members(N);
  satf_import_fit fit;
  satf_error err;
  satf_import_fit_params p = satf_import_fit_params_default();
  assert_int_equal(satf_import_fit_cluster(s, members, N, &p, &fit, &err),
                   SATF_OK);
  assert_true((double)fit.inside >= 0.95 * (double)fit.points);
  assert_int_equal(satf_import_fit_cluster_create(&fit, &got, &err), SATF_OK);
  ribbon_error e = ribbon_compare(truth, got);
  print_message("twisted ribbon: axis off by %.4f rad, twist by %.4f rad, "
                "area ratio %.3f..%.3f\n",
                e.axis, e.twist, e.area_lo, e.area_hi);
  assert_true(e.axis < 0.1);
  assert_true(e.twist < 0.1);
  assert_true(e.area_lo > 0.8 && e.area_hi < 1.5);
  /* every point, projected onto the fitted cluster, by its v */
  satf_import_projection proj;
  assert_int_equal(satf_import_project(s, members, N, got, &proj, &err),
                   SATF_OK);
  size_t in = 0, np = proj.offset[N];
  for (size_t k = 0; k < np; k++)
    in += hypot(proj.txy[3 * k + 1], proj.txy[3 * k + 2]) <= 1.0;
  assert_true((double)in >= 0.94 * (double)np);
  satf_import_projection_free(&proj);
  satf_cluster_destroy(got);
  satf_cluster_destroy(truth);
  satf_import_fit_free(&fit);
  free(members);
  satf_strand_set_destroy(s);
}

static void density_mass(void **state) {
  (void)state;
  enum { N = 300, M = 25 };
  satf_strand_set *s = known_strands(N, M);
  int *members = all_members(N);
  int *labels = calloc(N, sizeof(int));
  satf_import_fit fit;
  satf_error err;
  satf_import_fit_params p = satf_import_fit_params_default();
  assert_int_equal(satf_import_fit_cluster(s, members, N, &p, &fit, &err),
                   SATF_OK);
  satf_cluster *cl;
  assert_int_equal(satf_import_fit_cluster_create(&fit, &cl, &err), SATF_OK);
  satf_import_projection proj;
  assert_int_equal(satf_import_project(s, members, N, cl, &proj, &err),
                   SATF_OK);
  satf_import_estimate_density(&proj, &fit);
  /* uniform disk: mean nearest-neighbour distance ~ 0.5 / sqrt(N / pi) */
  float expect_w = 2.0f * 0.5f / sqrtf((float)N / PI_F);
  assert_true(fit.strand_width > 0.7f * expect_w &&
              fit.strand_width < 1.3f * expect_w);
  assert_int_equal(fit.layout, SATF_SCENE_LAYOUT_UNIFORM);
  /* per cluster, in (t, v, u): every slice holds N strands of pi sigma^2 */
  satf_import_density d;
  float sigma = 0.04f;
  assert_int_equal(
      satf_import_cluster_density(&proj, 10, 64, 1.5f, sigma, &d, &err),
      SATF_OK);
  for (int i = 0; i < 10; i++)
    assert_float_equal(satf_import_density_slice_mass(&d, i),
                       N * PI_F * sigma * sigma,
                       0.01 * N * PI_F * sigma * sigma);
  satf_import_density_free(&d);
  /* world space: strand count x per-strand mass pi sigma^2 L */
  float ws = satf_import_world_sigma(&fit);
  double expect = 0.0;
  for (int i = 0; i < N; i++)
    expect += PI_F * ws * ws * satf_strand_set_length(s, i);
  satf_vdb_builder *b;
  assert_int_equal(
      satf_import_build_vdb(s, labels, &fit, 0.25f, &b, NULL, NULL, &err),
      SATF_OK);
  satf_vdb_grid *mem, *disk;
  assert_int_equal(satf_vdb_builder_to_grid(b, &mem, &err), SATF_OK);
  assert_float_equal(satf_vdb_total_mass(mem), expect, 0.01 * expect);
  char path[512];
  test_path(path, sizeof path, "import_density.vdb");
  assert_int_equal(satf_vdb_builder_write(b, path, "density", &err), SATF_OK);
  assert_int_equal(satf_vdb_read(path, "density", &disk, &err), SATF_OK);
  assert_float_equal(satf_vdb_total_mass(disk), satf_vdb_total_mass(mem),
                     1e-5 * expect);
  for (int i = 0; i < N; i += 7) {
    const float *q = satf_strand_set_strand(s, i, NULL);
    float at[3] = {q[36], q[37] + 0.05f, q[38]};
    float dm = satf_vdb_sample(mem, at), dd = satf_vdb_sample(disk, at);
    assert_true(dm > 0.0f);
    assert_float_equal(dd, dm, 1e-6f * dm);
  }
  satf_vdb_grid_destroy(mem);
  satf_vdb_grid_destroy(disk);
  satf_vdb_builder_destroy(b);
  satf_import_projection_free(&proj);
  satf_cluster_destroy(cl);
  satf_import_fit_free(&fit);
  free(labels);
  free(members);
  satf_strand_set_destroy(s);
}

/* 3 x 4 similarity: scale s, rotation of `angle` about unit `axis`, then
 * translation. */
static void similarity(double s, const double axis[3], double angle,
                       const double t[3], double m[16]) {
  double c = cos(angle), n = sin(angle), x = axis[0], y = axis[1], z = axis[2];
  double r[9] = {
      c + x * x * (1 - c),     x * y * (1 - c) - z * n, x * z * (1 - c) + y * n,
      y * x * (1 - c) + z * n, c + y * y * (1 - c),     y * z * (1 - c) - x * n,
      z * x * (1 - c) - y * n, z * y * (1 - c) + x * n, c + z * z * (1 - c)};
  memset(m, 0, 16 * sizeof(double));
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++)
      m[4 * i + j] = s * r[3 * i + j];
    m[4 * i + 3] = t[i];
  }
  m[15] = 1.0;
}

static void similarity_recovered(void **state) {
  (void)state;
  double from[30], to[30], m[16], got[16];
  double axis[3] = {0.48, 0.6, 0.64}, t[3] = {3, -2, 7};
  similarity(1.7, axis, 2.2, t, m);
  satf_rng rng;
  satf_rng_seed(&rng, 5, 0);
  for (int i = 0; i < 10; i++) {
    for (int c = 0; c < 3; c++)
      from[3 * i + c] = satf_rng_range(&rng, -5, 5);
    for (int r = 0; r < 3; r++)
      to[3 * i + r] = m[4 * r] * from[3 * i] + m[4 * r + 1] * from[3 * i + 1] +
                      m[4 * r + 2] * from[3 * i + 2] + m[4 * r + 3];
  }
  assert_true(satf_import_similarity(from, to, 10, got) < 1e-9);
  for (int k = 0; k < 16; k++)
    assert_float_equal(got[k], m[k], 1e-9);
}

/* Records satf_import_find_macro's last progress call. */
static void macro_progress(void *ctx, size_t done, size_t total) {
  size_t *seen = ctx;
  seen[0] = done;
  seen[1] = total;
}
static void macro_clusters_from_copies(void **state) {
  (void)state;
  enum { N = 150, M = 16, COPIES = 4 };
  satf_cluster *c = known_cluster();
  double mats[COPIES][16];
  double axes[COPIES][3] = {{0, 1, 0},
                            {0, 1, 0},
                            {0.7071067811865476, 0.7071067811865476, 0},
                            {0, 0, 1}};
  double angles[COPIES] = {0.0, 1.5707963267948966, 0.7853981633974483,
                           3.141592653589793};
  double scales[COPIES] = {1.0, 1.0, 0.7, 1.3};
  double moves[COPIES][3] = {{0, 0, 0}, {40, 0, 0}, {0, 0, 50}, {-40, 10, 0}};
  float *pts = malloc(3 * (size_t)COPIES * N * M * sizeof(float));
  int *counts = malloc((size_t)COPIES * N * sizeof(int));
  for (int k = 0; k < COPIES; k++) {
    similarity(scales[k], axes[k], angles[k], moves[k], mats[k]);
    gc_strands(c, N, M, 100 + (uint64_t)k, mats[k], pts + 3 * (size_t)k * N * M,
               counts + k * N);
  }
  satf_cluster_destroy(c);
  satf_strand_set *s;
  satf_error err;
  assert_int_equal(
      satf_strand_set_create(COPIES * N, counts, pts, NULL, &s, &err), SATF_OK);
  free(pts);
  free(counts);
  /* k-means separates the copies exactly */
  satf_import_cluster_params cp = satf_import_cluster_params_default();
  cp.clusters = COPIES;
  int *labels = malloc((size_t)COPIES * N * sizeof(int)), n_clusters;
  assert_int_equal(
      satf_import_kmeans(s, &cp, labels, &n_clusters, NULL, NULL, NULL, &err),
      SATF_OK);
  assert_int_equal(n_clusters, COPIES);
  for (int i = 0; i < COPIES * N; i++)
    assert_int_equal(labels[i], i / N); /* renumbered in strand order */
  satf_import_fit fits[COPIES];
  satf_import_fit_params fp = satf_import_fit_params_default();
  for (int k = 0; k < COPIES; k++) {
    int *members, n;
    assert_int_equal(
        satf_import_members(labels, COPIES * N, k, &members, &n, &err),
        SATF_OK);
    assert_int_equal(n, N);
    assert_int_equal(
        satf_import_fit_cluster(s, members, n, &fp, &fits[k], &err), SATF_OK);
    free(members);
  }
  satf_import_macro macro;
  size_t seen[2] = {0, 0}; /* the last progress: done, total */
  assert_int_equal(satf_import_find_macro(fits, COPIES, 0.05f, macro_progress,
                                          seen, &macro, &err),
                   SATF_OK);
  assert_int_equal(seen[0], COPIES);
  assert_int_equal(seen[1], COPIES);
  assert_int_equal(macro.n_macro, 1);
  assert_int_equal(macro.prototype[0], 0);
  for (int k = 0; k < COPIES; k++) {
    assert_int_equal(macro.macro_of[k], 0);
    const float *m = macro.transform + 16 * k;
    for (int r = 0; r < 3; r++) {
      for (int e = 0; e < 3; e++)
        if (fabs(m[4 * r + e] - mats[k][4 * r + e]) > 0.04)
          fail_msg("copy %d: matrix[%d][%d] = %g, expected %g", k, r, e,
                   (double)m[4 * r + e], mats[k][4 * r + e]);
      if (fabs(m[4 * r + 3] - mats[k][4 * r + 3]) > 0.3)
        fail_msg("copy %d: translation[%d] = %g, expected %g", k, r,
                 (double)m[4 * r + 3], mats[k][4 * r + 3]);
    }
  }
  assert_true(macro.bytes_shared < macro.bytes_separate);
  assert_int_equal(macro.bytes_separate, 4 * (24 + 24) * sizeof(float));
  assert_int_equal(macro.bytes_shared, (48 + 3 * 12) * sizeof(float));

  /* the scene: one macro-cluster of 4 instances, N strands each */
  satf_import_scene_options o = {0};
  char *json;
  assert_int_equal(
      satf_import_scene_json(fits, COPIES, &macro, &o, &json, &err), SATF_OK);
  satf_scene *scene;
  assert_int_equal(
      satf_scene_parse(json, strlen(json), "import.json", &scene, &err),
      SATF_OK);
  free(json);
  assert_int_equal(scene->n_macro_clusters, 1);
  assert_int_equal(scene->macro_clusters[0].n_instances, COPIES);
  assert_int_equal(satf_scene_strand_count(scene), COPIES * N);
  assert_int_equal(satf_scene_warning_count(scene), 0);
  /* instance 2 maps the prototype's first control point where the fit of
   * copy 2 put it */
  float p0[3];
  satf_scene_instance_apply(&scene->macro_clusters[0].instances[2],
                            scene->macro_clusters[0].prototype.trajectory, p0);
  for (int r = 0; r < 3; r++)
    assert_float_equal(p0[r], fits[2].traj[r], 0.2);
  satf_scene_destroy(scene);

  /* no tolerance: every cluster its own prototype */
  satf_import_macro_free(&macro);
  assert_int_equal(
      satf_import_find_macro(fits, COPIES, 0.0f, NULL, NULL, &macro, &err),
      SATF_OK);
  assert_int_equal(macro.n_macro, COPIES);
  assert_int_equal(macro.bytes_shared, macro.bytes_separate);
  satf_import_macro_free(&macro);
  for (int k = 0; k < COPIES; k++)
    satf_import_fit_free(&fits[k]);
  free(labels);
  satf_strand_set_destroy(s);
}

static void kmeans_chooses_count(void **state) {
  (void)state;
  /* four tight bundles of 30 parallel strands, 50 apart */
  enum { B = 4, N = 30, M = 10 };
  float pts[B * N * M * 3];
  int counts[B * N];
  satf_rng rng;
  satf_rng_seed(&rng, 9, 0);
  for (int i = 0; i < B * N; i++) {
    float ox = 50.0f * (float)(i / N) + (float)satf_rng_range(&rng, -1, 1);
    float oz = (float)satf_rng_range(&rng, -1, 1);
    counts[i] = M;
    for (int k = 0; k < M; k++) {
      float *p = pts + 3 * (i * M + k);
      p[0] = ox;
      p[1] = -(float)k * 3.0f;
      p[2] = oz + 0.1f * (float)k;
    }
  }
  satf_strand_set *s;
  satf_error err;
  assert_int_equal(satf_strand_set_create(B * N, counts, pts, NULL, &s, &err),
                   SATF_OK);
  satf_import_cluster_params cp = satf_import_cluster_params_default();
  int k;
  assert_int_equal(satf_import_choose_clusters(s, &cp, &k, &err), SATF_OK);
  assert_int_equal(k, 4);
  int labels[B * N], n;
  float rms;
  assert_int_equal(
      satf_import_kmeans(s, &cp, labels, &n, &rms, NULL, NULL, &err), SATF_OK);
  assert_int_equal(n, 4);
  for (int i = 0; i < B * N; i++)
    assert_int_equal(labels[i], i / N);
  /* RMS of a uniform square of half-width 1: sqrt(2/3) */
  assert_true(rms > 0.6f && rms < 1.0f);
  /* an absurd count is refused */
  cp.clusters = SATF_IMPORT_MAX_CLUSTERS + 1;
  assert_int_equal(
      satf_import_kmeans(s, &cp, labels, &n, &rms, NULL, NULL, &err),
      SATF_ERR_ARGUMENT);
  satf_strand_set_destroy(s);
}

/* The sectors around follow the strands: the aspect sets 16, 24 or 32,
 * but a ring of su x layers sectors gets at least two strands each, in
 * steps of 4, down to half the aspect's count: 40 strands in 3 layers ->
 * 8, 100 in 4 -> 12, 400 in 4 keep the aspect's 16; a flat cluster
 * (aspect 4) of 250 in 4 layers 32 -> 28, of 40 in 3 -> 16. */
static void shell_sectors_follow_strands(void **state) {
  (void)state;
  float a1[1] = {1.0f}, b1[1] = {1.0f}, a4[1] = {4.0f};
  satf_import_fit fit;
  memset(&fit, 0, sizeof fit);
  fit.n_radius = 1;
  fit.a = a1;
  fit.b = b1;
  fit.radius = 1.0f;
  fit.length = 20.0f;
  fit.core = 0.1f;
  const int strands[5] = {40, 100, 400, 250, 40};
  const int layers[5] = {3, 4, 4, 4, 3}, su[5] = {8, 12, 16, 28, 16};
  for (int k = 0; k < 5; k++) {
    fit.strands = strands[k];
    fit.points = (size_t)strands[k] * 20;
    fit.a = k >= 3 ? a4 : a1;
    satf_scene_shell sh = satf_import_choose_shell(&fit);
    printf("%d strands: %d layers, su %d\n", strands[k], sh.layers, sh.su);
    assert_int_equal(sh.layers, layers[k]);
    assert_int_equal(sh.su, su[k]);
  }
}

static void scene_file_with_vdb(void **state) {
  (void)state;
  enum { N = 200, M = 20 };
  satf_strand_set *s = known_strands(N, M);
  int *members = all_members(N);
  satf_import_fit fit;
  satf_error err;
  satf_import_fit_params p = satf_import_fit_params_default();
  assert_int_equal(satf_import_fit_cluster(s, members, N, &p, &fit, &err),
                   SATF_OK);
  satf_scene_shell sh = satf_import_choose_shell(&fit);
  assert_true(sh.layers >= 3 && sh.layers <= 6);
  assert_true(sh.st >= 8 && sh.st <= 64);
  assert_true(sh.su >= 16 && sh.su <= 32);
  satf_import_scene_options o = {"hair.vdb", "density", "db.exr", "test", 320,
                                 200,        7,         NULL,     NULL,   NULL};
  char path[512];
  test_path(path, sizeof path, "import_scene.json");
  assert_int_equal(satf_import_write_scene(path, &fit, 1, NULL, &o, &err),
                   SATF_OK);
  satf_scene *scene;
  assert_int_equal(satf_scene_load(path, &scene, &err), SATF_OK);
  const satf_scene_cluster *c = &scene->macro_clusters[0].prototype;
  assert_int_equal(c->density.type, SATF_SCENE_DENSITY_VDB);
  const char *f = c->density.vdb_file;
  assert_string_equal(f + strlen(f) - 9, "/hair.vdb");
  assert_string_equal(c->density.vdb_grid, "density");
  assert_int_equal(c->n_points, 8);
  assert_int_equal(c->shell.layers, sh.layers);
  assert_int_equal(scene->image.width, 320);
  assert_int_equal(scene->camera.automatic, 0);
  /* the camera looks at the middle of the hair */
  float lo[3], hi[3];
  satf_scene_bounds(scene, lo, hi);
  for (int k = 0; k < 3; k++)
    assert_float_equal(scene->camera.target[k], 0.5f * (lo[k] + hi[k]), 1e-3);
  satf_scene_destroy(scene);
  /* given a box (the strands' bounds: satf_import_run), the camera frames
   * it whatever the clusters, from the same direction and farther for a
   * larger box */
  float box_lo[3] = {-1.0f, 2.0f, 3.0f}, box_hi[3] = {1.0f, 6.0f, 5.0f};
  o.frame_lo = box_lo;
  o.frame_hi = box_hi;
  assert_int_equal(satf_import_write_scene(path, &fit, 1, NULL, &o, &err),
                   SATF_OK);
  assert_int_equal(satf_scene_load(path, &scene, &err), SATF_OK);
  const float mid[3] = {0.0f, 4.0f, 4.0f};
  for (int k = 0; k < 3; k++)
    assert_float_equal(scene->camera.target[k], mid[k], 1e-5);
  float far0 = scene->camera.position[2] - mid[2];
  satf_scene_destroy(scene);
  box_hi[1] = 10.0f; /* twice the largest half-extent */
  assert_int_equal(satf_import_write_scene(path, &fit, 1, NULL, &o, &err),
                   SATF_OK);
  assert_int_equal(satf_scene_load(path, &scene, &err), SATF_OK);
  assert_float_equal(scene->camera.position[2] - scene->camera.target[2],
                     2.0f * far0, 1e-3);
  satf_scene_destroy(scene);
  satf_import_fit_free(&fit);
  free(members);
  satf_strand_set_destroy(s);
}

/* A TressFX file of g guides of v vertices whose header asks for `follow`
 * follow strands per guide, at path. */
static void write_tfx_guides(const char *path, int g, int v, int follow) {
  int *counts = malloc((size_t)g * sizeof *counts);
  float *pts = malloc((size_t)g * (size_t)v * 3 * sizeof *pts);
  for (int i = 0; i < g; i++) {
    counts[i] = v;
    for (int k = 0; k < v; k++) {
      float *p = pts + 3 * ((size_t)i * (size_t)v + (size_t)k);
      p[0] = 0.01f * (float)(i % 32);
      p[1] = -0.05f * (float)k;
      p[2] = 0.01f * (float)(i / 32);
    }
  }
  satf_strand_set *s;
  satf_error err;
  assert_int_equal(satf_strand_set_create(g, counts, pts, NULL, &s, &err),
                   SATF_OK);
  assert_int_equal(satf_tfx_write(path, s, 3, follow, &err), SATF_OK);
  satf_strand_set_destroy(s);
  free(counts);
  free(pts);
}

/* The memory budget: a 0.4 MB TressFX file whose header asks for 1024 follow
 * strands per guide (33.6 M points, 205 s and 1.25 GB before the budget)
 * is refused at once, naming the file, the numbers and the --follow that
 * fits; with that --follow it imports. */
static void follow_strands_within_budget(void **state) {
  (void)state;
  char path[512];
  test_path(path, sizeof path, "budget_follow.tfx");
  write_tfx_guides(path, 1024, 32, 1024);
  satf_import_options o = satf_import_options_default();
  satf_strand_set *s = NULL;
  satf_error err;
  double t0 = satf_now_seconds();
  assert_int_equal(satf_import_read_strands(path, &o, &s, &err),
                   SATF_ERR_ARGUMENT);
  assert_true(satf_now_seconds() - t0 < 1.0);
  assert_null(s);
  assert_non_null(strstr(err.message, path));
  assert_non_null(
      strstr(err.message, "its header asks for 1024 follow strands per guide"));
  assert_non_null(strstr(err.message, "1024 guides of 32768 points become "
                                      "33587200 points"));
  /* 2 GB / 128 B = 15.6 M points: 476 per guide point, 475 followers */
  assert_non_null(strstr(err.message, "(--follow 475)"));
  o.follow = 15;
  assert_int_equal(satf_import_read_strands(path, &o, &s, &err), SATF_OK);
  assert_int_equal(satf_strand_set_count(s), 1024 * 16);
  satf_strand_set_destroy(s);
  /* A raised budget lets the header's count through the check (the strands
   * themselves are not made here: the budget check alone). */
  o.memory_budget = 8e9;
  assert_int_equal(satf_import_check_budget(&o, path, 33587200, &err), SATF_OK);
}

/* TressFX guides draw as TressFX draws them: the header's follow strands
 * per guide, SATF_IMPORT_TFX_FOLLOW (AMD's loader's default) where it
 * names none, --follow's when given. */
static void tressfx_followers_default(void **state) {
  (void)state;
  char path[512];
  test_path(path, sizeof path, "followers.tfx");
  satf_import_options o = satf_import_options_default();
  satf_strand_set *s = NULL;
  satf_error err;
  const int header[3] = {0, 2, 0}, given[3] = {-1, -1, 0};
  const int expect[3] = {SATF_IMPORT_TFX_FOLLOW, 2, 0};
  for (int k = 0; k < 3; k++) {
    write_tfx_guides(path, 64, 8, header[k]);
    o.follow = given[k];
    int followers = -7;
    assert_int_equal(
        satf_import_read_strands_followed(path, &o, &s, &followers, &err),
        SATF_OK);
    assert_int_equal(followers, expect[k]);
    assert_int_equal(satf_strand_set_count(s), 64 * (expect[k] + 1));
    satf_strand_set_destroy(s);
  }
  assert_int_equal(SATF_IMPORT_TFX_FOLLOW, 4);
}

/* Strands whose file gives no thickness are drawn as hair fibres,
 * SATF_IMPORT_FIBRE_WIDTH of the hair's bounding-box diagonal (followers
 * included), whatever their spacing; the summary's figures count them. */
static void default_width_is_a_fibre(void **state) {
  (void)state;
  char path[512], out[512];
  test_path(path, sizeof path, "fibre_width.tfx");
  test_path(out, sizeof out, "fibre_width.json");
  write_tfx_guides(path, 256, 16, 0);
  satf_import_options o = satf_import_options_default();
  satf_strand_set *s = NULL;
  satf_error err;
  int followers;
  assert_int_equal(
      satf_import_read_strands_followed(path, &o, &s, &followers, &err),
      SATF_OK);
  float lo[3], hi[3];
  satf_strand_set_bounds(s, lo, hi);
  double diag = 0.0;
  for (int c = 0; c < 3; c++)
    diag += ((double)hi[c] - lo[c]) * ((double)hi[c] - lo[c]);
  diag = sqrt(diag);
  satf_strand_set_destroy(s);
  o.inputs[0] = path;
  o.n_inputs = 1;
  o.output = out;
  o.quiet = 1;
  o.threads = 2;
  o.no_strands = 1;
  satf_import_result r;
  satf_status st = satf_import_run(&o, &r, &err);
  if (st != SATF_OK)
    print_error("%s\n", err.message);
  assert_int_equal(st, SATF_OK);
  assert_int_equal(r.follow, SATF_IMPORT_TFX_FOLLOW);
  assert_int_equal(r.guides, 256);
  assert_int_equal(r.n_strands, 256 * (SATF_IMPORT_TFX_FOLLOW + 1));
  assert_float_equal(r.spacing_width[1], 1e-3 * diag, 1e-6 * diag);
  assert_false(r.strand_width_given);
  assert_int_equal(r.fit.strands, r.n_strands);
  assert_true(r.fit.shell_strands >= 0 && r.fit.shell_strands <= r.fit.strands);
}

/* Strands read from files are held to the budget before anything grows
 * with them: a whole import stops after reading, fast, naming the file. */
static void import_within_budget(void **state) {
  (void)state;
  char path[512], out[512];
  test_path(path, sizeof path, "budget_guides.tfx");
  test_path(out, sizeof out, "budget_never.json");
  remove(out);
  write_tfx_guides(path, 256, 32, 0); /* 8192 points, about 1 MB */
  satf_import_options o = satf_import_options_default();
  o.follow = 0; /* the guides alone */
  o.inputs[0] = path;
  o.n_inputs = 1;
  o.output = out;
  o.quiet = 1;
  o.memory_budget = 5e5; /* 3906 points */
  satf_import_result r;
  satf_error err;
  double t0 = satf_now_seconds();
  assert_int_equal(satf_import_run(&o, &r, &err), SATF_ERR_ARGUMENT);
  assert_true(satf_now_seconds() - t0 < 1.0);
  assert_non_null(strstr(err.message, path));
  assert_non_null(strstr(err.message, "8192 strand points would need about"));
  assert_non_null(strstr(err.message, "over the memory budget of"));
  assert_non_null(strstr(err.message, "--memory-budget"));
  FILE *f = fopen(out, "rb");
  assert_null(f); /* nothing written */
}

/* A one-strand cluster narrower than its strand grows round it to the
 * strand's width (A and B up, the track down by as much: the strand stays
 * where it was); a cluster of several strands keeps its radius and takes
 * their mean width over it. */
static void lone_strand_grows_to_its_width(void **state) {
  (void)state;
  const int counts[2] = {3, 3};
  const float pts[18] = {0, 0, 0, 0, 0, 1, 0, 0, 2, 1, 0, 0, 1, 0, 1, 1, 0, 2};
  const float th[6] = {0.8f, 0.8f, 0.8f, 0.2f, 0.2f, 0.2f};
  satf_strand_set *s = NULL;
  satf_error err;
  assert_int_equal(satf_strand_set_create(2, counts, pts, th, &s, &err),
                   SATF_OK);
  float a[2] = {0.2f, 0.2f}, b[2] = {0.1f, 0.4f};
  float xy[4] = {0.5f, -0.25f, 0.2f, 0.4f}; /* 2 slices of one track */
  float ends[6] = {0.0f, 0.5f, -0.25f, 1.0f, 0.2f, 0.4f};
  int first = 0, count = 2;
  satf_import_fit f;
  memset(&f, 0, sizeof f);
  f.n_radius = 2;
  f.a = a;
  f.b = b;
  f.radius = 0.2f;
  f.strands = 1;
  f.strand_width = 0.5f;
  f.n_tracks = 1;
  f.track_slices = 2;
  f.track_first = &first;
  f.track_count = &count;
  f.track_xy = xy;
  f.track_ends = ends;
  float before[4] = {xy[0] * a[0], xy[1] * b[0], xy[2] * a[1], xy[3] * b[1]};
  int lone = 0;
  satf_import_width_from_thickness(s, &lone, 1, &f);
  /* 0.8 wide against a radius of 0.2: the cluster grows by 2 */
  assert_float_equal(f.radius, 0.4f, 1e-6f);
  assert_float_equal(f.strand_width, 2.0f, 0.0f);
  assert_float_equal(a[0], 0.4f, 1e-6f);
  assert_float_equal(b[1], 0.8f, 1e-6f);
  float after[4] = {xy[0] * a[0], xy[1] * b[0], xy[2] * a[1], xy[3] * b[1]};
  for (int i = 0; i < 4; i++)
    assert_float_equal(after[i], before[i], 1e-6f);
  assert_float_equal(ends[0], 0.0f, 0.0f); /* t stays */
  assert_float_equal(ends[1] * a[0], 0.5f * 0.2f, 1e-6f);
  /* two strands (0.8 and 0.2 wide) in a cluster of radius 1: the mean */
  satf_import_fit g;
  memset(&g, 0, sizeof g);
  float ga[1] = {1.0f}, gb[1] = {1.0f};
  g.n_radius = 1;
  g.a = ga;
  g.b = gb;
  g.radius = 1.0f;
  g.strands = 2;
  const int both[2] = {0, 1};
  satf_import_width_from_thickness(s, both, 2, &g);
  assert_float_equal(g.strand_width, 0.5f, 1e-6f);
  assert_float_equal(g.radius, 1.0f, 0.0f);
  assert_float_equal(ga[0], 1.0f, 0.0f);
  satf_strand_set_destroy(s);
}

/* Strands without a thickness get twice the spacing of their neighbours:
 * parallel strands 0.1 apart are 0.2 wide; two strands that nearly touch
 * are held to a quarter of the median, and a strand with no neighbour
 * within a segment length gets the median. */
static void widths_from_spacing(void **state) {
  (void)state;
  enum { N = 7, M = 8 };
  const float x[N] = {0.0f, 0.1f, 0.2f, 0.3f, 0.4f, 0.41f, 50.0f};
  int counts[N];
  float pts[3 * N * M];
  for (int i = 0; i < N; i++) {
    counts[i] = M;
    for (int k = 0; k < M; k++) {
      pts[3 * (M * i + k)] = x[i];
      pts[3 * (M * i + k) + 1] = 0.0f;
      pts[3 * (M * i + k) + 2] = (float)k;
    }
  }
  satf_strand_set *s = NULL;
  satf_error err;
  assert_int_equal(satf_strand_set_create(N, counts, pts, NULL, &s, &err),
                   SATF_OK);
  for (int threads = 1; threads <= 2; threads++) {
    float w[N];
    assert_int_equal(satf_import_spacing_widths(s, threads, w, &err), SATF_OK);
    for (int i = 0; i < 4; i++)
      assert_float_equal(w[i], 0.2f, 1e-5f);
    /* 0.01 apart: 0.02, held to a quarter of the median 0.2 */
    assert_float_equal(w[4], 0.05f, 1e-5f);
    assert_float_equal(w[5], 0.05f, 1e-5f);
    assert_float_equal(w[6], 0.2f, 1e-5f); /* alone: the median */
  }
  satf_strand_set_destroy(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(follow_strands_within_budget),
      cmocka_unit_test(tressfx_followers_default),
      cmocka_unit_test(default_width_is_a_fibre),
      cmocka_unit_test(import_within_budget),
      cmocka_unit_test(fit_recovers_known_cylinder),
      cmocka_unit_test(fit_reaches_last_tip),
      cmocka_unit_test(fit_reaches_first_root),
      cmocka_unit_test(fit_recovers_twisted_ribbon),
      cmocka_unit_test(density_mass),
      cmocka_unit_test(similarity_recovered),
      cmocka_unit_test(macro_clusters_from_copies),
      cmocka_unit_test(kmeans_chooses_count),
      cmocka_unit_test(shell_sectors_follow_strands),
      cmocka_unit_test(scene_file_with_vdb),
      cmocka_unit_test(lone_strand_grows_to_its_width),
      cmocka_unit_test(widths_from_spacing),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
