/* test_cluster.c - generalized cylinders (SATF eq. 1-2): validation, the
 * rotation-minimising frame, points in the normal plane, normals, hair
 * directions and arc length. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "satf/geometry.h"
#include "satf/math.h"

#include "test_util.h"

/* Control points of a helix of radius r, `turns` turns, rising `rise` per
 * turn, around the z axis. */
static void helix_ctrl(int n, double r, double turns, double rise, float *out) {
  for (int i = 0; i < n; i++) {
    double s = (double)i / (n - 1) * turns * 2.0 * SATF_PI;
    out[3 * i] = (float)(r * cos(s));
    out[3 * i + 1] = (float)(r * sin(s));
    out[3 * i + 2] = (float)(rise * s / (2.0 * SATF_PI));
  }
}

static satf_cluster *make_cluster(int n_ctrl, const float *traj, int n_radius,
                                  const float *a, const float *b,
                                  const float *twist) {
  satf_cluster_desc d = {n_ctrl, traj, n_radius, a, b, twist};
  satf_cluster *cl = NULL;
  satf_error err;
  satf_status st = satf_cluster_create(&d, &cl, &err);
  if (st)
    print_error("create: %s\n", err.message);
  assert_int_equal(st, SATF_OK);
  assert_non_null(cl);
  return cl;
}

static satf_cluster *make_helix(void) {
  static float traj[40 * 3];
  helix_ctrl(40, 1.0, 3.0, 0.8, traj);
  static const float a[4] = {0.30f, 0.25f, 0.20f, 0.12f};
  static const float b[4] = {0.15f, 0.14f, 0.10f, 0.08f};
  static const float tw[4] = {0.0f, 1.0f, 2.5f, 4.0f};
  return make_cluster(40, traj, 4, a, b, tw);
}

/* P - T(t) is normal to T'(t) for every (t, v, u): the ellipse lies in the
 * normal plane (SATF sec. 3.2). */
static void test_ellipse_in_normal_plane(void **state) {
  (void)state;
  satf_cluster *cl = make_helix();
  for (int i = 0; i <= 300; i++) {
    float t = i / 300.0f, T[3], dT[3];
    satf_cluster_trajectory(cl, t, T, dT);
    for (int k = 0; k < 24; k++)
      for (int vv = 1; vv <= 2; vv++) {
        float p[3], d[3], v = 0.5f * vv, u = (float)(2 * SATF_PI * k / 24);
        satf_cluster_point(cl, t, v, u, p);
        test_sub3(p, T, d);
        assert_true(fabs(test_dot3(d, dT)) < 1e-5);
        assert_true(test_len3(d) > 0.0);
      }
  }
  satf_cluster_destroy(cl);
}

static void test_helix_frames_do_not_flip(void **state) {
  (void)state;
  satf_cluster *cl = make_helix();
  float pt[3], p1[3], p2[3];
  satf_cluster_frame(cl, 0.0f, pt, p1, p2);
  double worst_dot = 1.0, worst_twist = 0.0;
  for (int i = 1; i <= 1000; i++) {
    float t = i / 1000.0f, tan[3], n1[3], n2[3], dT[3], pos[3];
    satf_cluster_frame(cl, t, tan, n1, n2);
    satf_cluster_trajectory(cl, t, pos, dT);
    /* orthonormal and right-handed */
    assert_near(test_len3(tan), 1.0, 1e-5);
    assert_near(test_len3(n1), 1.0, 1e-5);
    assert_near(test_len3(n2), 1.0, 1e-5);
    assert_near(test_dot3(tan, n1), 0.0, 1e-5);
    assert_near(test_dot3(tan, n2), 0.0, 1e-5);
    assert_near(test_dot3(n1, n2), 0.0, 1e-5);
    assert_near(test_dot3(tan, dT), test_len3(dT), 1e-5 * test_len3(dT));
    float c[3] = {tan[1] * n1[2] - tan[2] * n1[1],
                  tan[2] * n1[0] - tan[0] * n1[2],
                  tan[0] * n1[1] - tan[1] * n1[0]};
    assert_near(test_dot3(c, n2), 1.0, 1e-5);
    double d = test_dot3(n1, p1);
    worst_dot = fmin(worst_dot, d);
    /* Rotation-minimising: the new n1 gains (to first order) no component
     * along the old n2, unlike the Frenet frame, which turns by the torsion
     * (about 0.005 rad per step here). */
    worst_twist = fmax(worst_twist, fabs(test_dot3(n1, p2)));
    memcpy(p1, n1, sizeof p1);
    memcpy(p2, n2, sizeof p2);
  }
  assert_true(worst_dot > 0.9);
  print_message("helix: min consecutive n1 dot %.6f, max twist %.2e\n",
                worst_dot, worst_twist);
  assert_true(worst_twist < 5e-4);
  satf_cluster_destroy(cl);
}

static void test_straight_line_frame_constant(void **state) {
  (void)state;
  const float traj[5 * 3] = {0, 0, 0, 0.5f, 1, 1.5f, 1, 2, 3, 2, 4, 6, 3, 6, 9};
  const float r[1] = {0.2f}, tw[1] = {0.0f};
  satf_cluster *cl = make_cluster(5, traj, 1, r, r, tw);
  float tan0[3], n10[3], n20[3];
  satf_cluster_frame(cl, 0.0f, tan0, n10, n20);
  const double inv = 1.0 / sqrt(14.0);
  assert_near(tan0[0], 1 * inv, 1e-6);
  assert_near(tan0[1], 2 * inv, 1e-6);
  assert_near(tan0[2], 3 * inv, 1e-6);
  for (int i = 0; i <= 500; i++) {
    float tan[3], n1[3], n2[3];
    satf_cluster_frame(cl, i / 500.0f, tan, n1, n2);
    for (int c = 0; c < 3; c++) {
      assert_near(tan[c], tan0[c], 1e-6);
      assert_near(n1[c], n10[c], 1e-6);
      assert_near(n2[c], n20[c], 1e-6);
    }
  }
  /* arc length of a straight trajectory is the segment length */
  assert_near(satf_cluster_length(cl), 3.0 * sqrt(14.0), 1e-5);
  satf_cluster_destroy(cl);
}

/* SATF eq. 1 with theta turning the cross-section (satf/geometry.h): in
 * the untwisted rotation-minimising frame (n1, n2) of satf_cluster_frame,
 * the point at (v, u) is R(theta) (A v cos u, B v sin u), and the section's
 * own n1, n2 are that frame turned by theta. */
static void test_ellipse_axes_with_twist(void **state) {
  (void)state;
  float traj[12 * 3];
  helix_ctrl(12, 2.0, 0.5, 3.0, traj);
  const float a[3] = {0.4f, 0.4f, 0.4f}, b[3] = {0.1f, 0.1f, 0.1f};
  const float tw[3] = {0.7f, 0.7f, 0.7f};
  const double c = cos(0.7), s = sin(0.7);
  satf_cluster *cl = make_cluster(12, traj, 3, a, b, tw);
  for (int i = 0; i <= 20; i++) {
    float t = i / 20.0f, T[3], tan[3], n1[3], n2[3], p[3], d[3];
    satf_cluster_trajectory(cl, t, T, NULL);
    satf_cluster_frame(cl, t, tan, n1, n2);
    satf_cluster_section sec;
    satf_cluster_section_at(cl, t, &sec);
    for (int k = 0; k < 3; k++) {
      assert_near(sec.rmf_n1[k], n1[k], 1e-7);
      assert_near(sec.n1[k], c * n1[k] + s * n2[k], 1e-6);
      assert_near(sec.n2[k], -s * n1[k] + c * n2[k], 1e-6);
    }
    for (int k = 0; k < 8; k++) {
      float u = (float)k, v = 0.3f + 0.1f * k;
      double x = 0.4 * v * cos(u), y = 0.1 * v * sin(u);
      satf_cluster_point(cl, t, v, u, p);
      test_sub3(p, T, d);
      assert_near(test_dot3(d, n1), c * x - s * y, 1e-6);
      assert_near(test_dot3(d, n2), s * x + c * y, 1e-6);
    }
  }
  satf_cluster_destroy(cl);
}

/* How far the angle of d in the plane of (n1, n2) is from `expect`,
 * wrapped into [-pi, pi). */
static double angle_error(const float d[3], const float n1[3],
                          const float n2[3], double expect) {
  double e = atan2(test_dot3(d, n2), test_dot3(d, n1)) - expect;
  return e - 2.0 * SATF_PI * floor((e + SATF_PI) / (2.0 * SATF_PI));
}

/* A ribbon (A = 20 B) twisted one full turn, theta(t) = 2 pi t, along a
 * curved trajectory: its major axis, the direction of P(t, 1, 0) - T(t),
 * is A long and at angle 2 pi t in the untwisted frame; its minor axis
 * (u = pi/2) is B long, a quarter turn further. Read as a phase only
 * (theta + u), the point at u = 0 would be (A cos theta, B sin theta): at
 * t = 0.25 only B long, so the ribbon would never turn. The axes'
 * derivatives carry the twist rate: they match finite differences. */
static void test_ribbon_full_turn(void **state) {
  (void)state;
  float traj[12 * 3];
  helix_ctrl(12, 2.0, 0.5, 3.0, traj);
  const float a[2] = {1.0f, 1.0f}, b[2] = {0.05f, 0.05f};
  const float tw[2] = {0.0f, (float)(2.0 * SATF_PI)};
  satf_cluster *cl = make_cluster(12, traj, 2, a, b, tw);
  const float ts[5] = {0.0f, 0.125f, 0.25f, 0.375f, 0.5f};
  for (int i = 0; i < 5; i++) {
    float t = ts[i], T[3], tan[3], n1[3], n2[3], p[3], d[3];
    double expect = 2.0 * SATF_PI * t;
    satf_cluster_trajectory(cl, t, T, NULL);
    satf_cluster_frame(cl, t, tan, n1, n2);
    satf_cluster_point(cl, t, 1.0f, 0.0f, p);
    test_sub3(p, T, d);
    assert_near(test_len3(d), 1.0, 1e-5);
    assert_near(angle_error(d, n1, n2, expect), 0.0, 1e-5);
    satf_cluster_point(cl, t, 1.0f, (float)(0.5 * SATF_PI), p);
    test_sub3(p, T, d);
    assert_near(test_len3(d), 0.05, 1e-5);
    assert_near(angle_error(d, n1, n2, expect + 0.5 * SATF_PI), 0.0, 1e-4);
  }
  const float h = 1e-3f;
  for (int i = 1; i < 20; i++) {
    satf_cluster_section s, s0, s1;
    float t = i / 20.0f;
    satf_cluster_section_at(cl, t, &s);
    satf_cluster_section_at(cl, t - h, &s0);
    satf_cluster_section_at(cl, t + h, &s1);
    for (int k = 0; k < 3; k++) {
      /* |dn/dt| is about 2 pi here: 2e-3 is a relative 3e-4 */
      assert_near(s.dn1[k], (s1.n1[k] - s0.n1[k]) / (2.0 * h), 2e-3);
      assert_near(s.dn2[k], (s1.n2[k] - s0.n2[k]) / (2.0 * h), 2e-3);
    }
  }
  satf_cluster_destroy(cl);
}

/* The radius and twist splines interpolate their end control points. */
static void test_section_end_values(void **state) {
  (void)state;
  satf_cluster *cl = make_helix();
  satf_cluster_section s;
  satf_cluster_section_at(cl, 0.0f, &s);
  assert_near(s.a, 0.30, 1e-7);
  assert_near(s.b, 0.15, 1e-7);
  assert_near(s.theta, 0.0, 1e-7);
  satf_cluster_section_at(cl, 1.0f, &s);
  assert_near(s.a, 0.12, 1e-7);
  assert_near(s.b, 0.08, 1e-7);
  assert_near(s.theta, 4.0, 1e-6);
  satf_cluster_destroy(cl);
}

/* Hair direction = normalised central difference of P along t; surface
 * normal orthogonal to both surface derivatives, unit and outward. */
static void test_hair_tangent_and_normal(void **state) {
  (void)state;
  satf_cluster *cl = make_helix();
  const float h = 1e-3f;
  for (int i = 1; i < 40; i++)
    for (int k = 0; k < 12; k++) {
      float t = i / 40.0f, u = (float)(2 * SATF_PI * k / 12), v = 0.9f;
      float dir[3], n[3], pa[3], pb[3], pc[3], pd[3], p[3], T[3];
      satf_cluster_hair_tangent(cl, t, v, u, dir);
      satf_cluster_surface_normal(cl, t, v, u, n);
      satf_cluster_point(cl, t - h, v, u, pa);
      satf_cluster_point(cl, t + h, v, u, pb);
      satf_cluster_point(cl, t, v, u - h, pc);
      satf_cluster_point(cl, t, v, u + h, pd);
      float dt[3], du[3], r[3];
      test_sub3(pb, pa, dt);
      test_sub3(pd, pc, du);
      double ldt = test_len3(dt), ldu = test_len3(du);
      assert_near(test_len3(dir), 1.0, 1e-5);
      assert_near(test_dot3(dir, dt) / ldt, 1.0, 2e-3);
      assert_near(test_len3(n), 1.0, 1e-5);
      assert_near(test_dot3(n, dt) / ldt, 0.0, 2e-3);
      assert_near(test_dot3(n, du) / ldu, 0.0, 2e-3);
      satf_cluster_point(cl, t, v, u, p);
      satf_cluster_trajectory(cl, t, T, NULL);
      test_sub3(p, T, r);
      assert_true(test_dot3(n, r) > 0.0);
    }
  /* v = 0: the limit normal is the in-plane ellipse normal, still outward */
  float n[3], p[3], T[3], r[3];
  satf_cluster_surface_normal(cl, 0.5f, 0.0f, 1.0f, n);
  satf_cluster_point(cl, 0.5f, 1.0f, 1.0f, p);
  satf_cluster_trajectory(cl, 0.5f, T, NULL);
  test_sub3(p, T, r);
  assert_near(test_len3(n), 1.0, 1e-5);
  assert_true(test_dot3(n, r) > 0.0);
  satf_cluster_destroy(cl);
}

/* Arc length against a dense chord sum of the trajectory (independent of
 * the Simpson rule used inside). */
static void test_helix_length(void **state) {
  (void)state;
  satf_cluster *cl = make_helix();
  double chord = 0.0;
  float prev[3];
  satf_cluster_trajectory(cl, 0.0f, prev, NULL);
  for (int i = 1; i <= 100000; i++) {
    float p[3], d[3];
    satf_cluster_trajectory(cl, (float)(i / 100000.0), p, NULL);
    test_sub3(p, prev, d);
    chord += test_len3(d);
    memcpy(prev, p, sizeof prev);
  }
  /* near 3 turns of the helix (the cubic B-spline cuts inside the control
   * polygon by ~4% at 40 points over 3 turns) */
  assert_near(satf_cluster_length(cl), chord, 1e-4 * chord);
  assert_near(chord, 3 * 2 * SATF_PI * sqrt(1 + 0.64 / (4 * SATF_PI * SATF_PI)),
              0.05 * chord);
  satf_cluster_destroy(cl);
}

/* Repeated control points stop T' at the ends; frames stay finite and
 * orthonormal there. */
static void test_stationary_ends(void **state) {
  (void)state;
  const float traj[6 * 3] = {0, 0, 0, 0, 0, 0, 0, 0, 0,
                             1, 0, 0, 1, 1, 0, 1, 1, 1};
  const float r[2] = {0.1f, 0.1f}, tw[2] = {0, 0};
  satf_cluster *cl = make_cluster(6, traj, 2, r, r, tw);
  for (int i = 0; i <= 100; i++) {
    float tan[3], n1[3], n2[3], p[3];
    satf_cluster_frame(cl, i / 100.0f, tan, n1, n2);
    assert_near(test_len3(tan), 1.0, 1e-5);
    assert_near(test_len3(n1), 1.0, 1e-5);
    assert_near(test_dot3(tan, n1), 0.0, 1e-5);
    assert_near(test_dot3(n1, n2), 0.0, 1e-5);
    satf_cluster_hair_tangent(cl, i / 100.0f, 1.0f, 0.3f, p);
    assert_near(test_len3(p), 1.0, 1e-5);
  }
  /* the curve leaves the start along +x */
  float tan[3], n1[3], n2[3];
  satf_cluster_frame(cl, 0.0f, tan, n1, n2);
  assert_true(tan[0] > 0.99f);
  satf_cluster_destroy(cl);
}

static void expect_reject(const satf_cluster_desc *d, const char *needle) {
  satf_cluster *cl = (satf_cluster *)(uintptr_t)1;
  satf_error err;
  satf_status st = satf_cluster_create(d, &cl, &err);
  assert_int_equal(st, SATF_ERR_ARGUMENT);
  assert_int_equal(err.status, SATF_ERR_ARGUMENT);
  assert_null(cl);
  if (!strstr(err.message, needle)) {
    print_error("message '%s' lacks '%s'\n", err.message, needle);
    fail();
  }
}

static void test_invalid_descriptors(void **state) {
  (void)state;
  float traj[4 * 3] = {0, 0, 0, 1, 0, 0, 2, 1, 0, 3, 1, 1};
  float a[2] = {0.2f, 0.3f}, b[2] = {0.1f, 0.1f}, tw[2] = {0, 1};
  expect_reject(NULL, "desc is NULL");
  satf_cluster_desc d = {4, traj, 2, a, b, tw};
  d.n_ctrl = 1;
  expect_reject(&d, "n_ctrl");
  d.n_ctrl = 4;
  d.n_radius = 0;
  expect_reject(&d, "n_radius");
  d.n_radius = 2;
  d.traj = NULL;
  expect_reject(&d, "traj: array is NULL");
  d.traj = traj;
  traj[7] = NAN;
  expect_reject(&d, "traj[7]");
  traj[7] = 1;
  a[1] = 0.0f;
  expect_reject(&d, "a[1]");
  a[1] = 0.3f;
  b[0] = -0.1f;
  expect_reject(&d, "b[0]");
  b[0] = 0.1f;
  tw[1] = INFINITY;
  expect_reject(&d, "twist[1]");
  tw[1] = 1;
  float same[3 * 3] = {5, 5, 5, 5, 5, 5, 5, 5, 5};
  d.traj = same;
  d.n_ctrl = 3;
  expect_reject(&d, "zero length");
  /* NULL err is allowed */
  satf_cluster *cl = NULL;
  assert_int_equal(satf_cluster_create(&d, &cl, NULL), SATF_ERR_ARGUMENT);
  /* and the fixed descriptor is accepted */
  d.traj = traj;
  d.n_ctrl = 4;
  assert_int_equal(satf_cluster_create(&d, &cl, NULL), SATF_OK);
  satf_cluster_destroy(cl);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_ellipse_in_normal_plane),
      cmocka_unit_test(test_helix_frames_do_not_flip),
      cmocka_unit_test(test_straight_line_frame_constant),
      cmocka_unit_test(test_ellipse_axes_with_twist),
      cmocka_unit_test(test_ribbon_full_turn),
      cmocka_unit_test(test_section_end_values),
      cmocka_unit_test(test_hair_tangent_and_normal),
      cmocka_unit_test(test_helix_length),
      cmocka_unit_test(test_stationary_ends),
      cmocka_unit_test(test_invalid_descriptors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
