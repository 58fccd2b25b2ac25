/* test_bspline.c - clamped uniform B-splines against closed forms (Bezier,
 * lines), a naive Cox-de Boor recursion and finite differences. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>

#include "satf/geometry.h"

#include "test_util.h"

/* Knot j of the clamped uniform vector, written out independently. */
static double ref_knot(int j, int n, int p) {
  int m = n + p; /* last knot index */
  if (j <= p)
    return 0.0;
  if (j >= m - p)
    return 1.0;
  return (double)(j - p) / (double)(n - p);
}

/* N_{i,p}(t) by the Cox-de Boor recursion, half-open spans except that the
 * last non-empty span is closed so t = 1 is covered. */
static double ref_basis(int i, int p, int n, int deg, double t) {
  if (p == 0) {
    double a = ref_knot(i, n, deg), b = ref_knot(i + 1, n, deg);
    if (t >= a && t < b)
      return 1.0;
    if (t == 1.0 && b == 1.0 && a < 1.0)
      return 1.0;
    return 0.0;
  }
  double sum = 0.0;
  double a = ref_knot(i, n, deg), b = ref_knot(i + p, n, deg);
  if (b > a)
    sum += (t - a) / (b - a) * ref_basis(i, p - 1, n, deg, t);
  double c = ref_knot(i + 1, n, deg), d = ref_knot(i + p + 1, n, deg);
  if (d > c)
    sum += (d - t) / (d - c) * ref_basis(i + 1, p - 1, n, deg, t);
  return sum;
}

static double ref_eval(const float *ctrl, int n, double t) {
  int deg = n - 1 < 3 ? n - 1 : 3;
  double sum = 0.0;
  for (int i = 0; i < n; i++)
    sum += ref_basis(i, deg, n, deg, t) * ctrl[i];
  return sum;
}

static void test_degree(void **state) {
  (void)state;
  assert_int_equal(satf_bspline_degree(1), 0);
  assert_int_equal(satf_bspline_degree(2), 1);
  assert_int_equal(satf_bspline_degree(3), 2);
  assert_int_equal(satf_bspline_degree(4), 3);
  assert_int_equal(satf_bspline_degree(11), 3);
}

static void test_endpoints_interpolate(void **state) {
  (void)state;
  const float ctrl[8 * 3] = {1,  2,  3,  -4, 5, 0.5f, 7, -1, 2, 3, 3, 3,
                             -2, -2, 10, 0,  1, 4,    9, 8,  7, 6, 5, -3};
  for (int n = 2; n <= 8; n++) {
    double p0[3], p1[3];
    satf_bspline_eval(ctrl, n, 3, 0.0, p0, NULL, NULL);
    satf_bspline_eval(ctrl, n, 3, 1.0, p1, NULL, NULL);
    for (int c = 0; c < 3; c++) {
      assert_near(p0[c], ctrl[c], 1e-12);
      assert_near(p1[c], ctrl[(n - 1) * 3 + c], 1e-12);
    }
  }
}

/* Control points on a line, unevenly spaced: the curve stays on it. */
static void test_straight_polygon_stays_on_line(void **state) {
  (void)state;
  const double o[3] = {1.0, -2.0, 0.5}, d[3] = {0.6, 0.0, 0.8};
  const double s[6] = {0.0, 0.3, 1.7, 2.0, 4.5, 5.0};
  float ctrl[6 * 3];
  for (int i = 0; i < 6; i++)
    for (int c = 0; c < 3; c++)
      ctrl[i * 3 + c] = (float)(o[c] + s[i] * d[c]);
  for (int n = 2; n <= 6; n++)
    for (int k = 0; k <= 200; k++) {
      double p[3], q[3];
      satf_bspline_eval(ctrl, n, 3, k / 200.0, p, q, NULL);
      double w[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]};
      double along = w[0] * d[0] + w[1] * d[1] + w[2] * d[2];
      double off = 0.0;
      for (int c = 0; c < 3; c++)
        off += pow(w[c] - along * d[c], 2);
      assert_true(sqrt(off) < 1e-6);
      /* the derivative is parallel to the line as well */
      double dq = q[0] * d[0] + q[1] * d[1] + q[2] * d[2];
      double qq = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
      assert_near(fabs(dq), qq, 1e-6 * (1.0 + qq));
    }
}

/* With 4 control points the clamped cubic is the Bezier curve; 3 give the
 * quadratic Bezier curve, 2 the segment. */
static void test_bezier_closed_forms(void **state) {
  (void)state;
  const float c[4] = {0.5f, 2.0f, -1.0f, 3.0f};
  for (int k = 0; k <= 20; k++) {
    double t = k / 20.0, s = 1.0 - t, v, d1, d2;
    satf_bspline_eval(c, 4, 1, t, &v, &d1, &d2);
    double bez = s * s * s * c[0] + 3 * s * s * t * c[1] +
                 3 * s * t * t * c[2] + t * t * t * c[3];
    double dbez = 3 * (s * s * (c[1] - c[0]) + 2 * s * t * (c[2] - c[1]) +
                       t * t * (c[3] - c[2]));
    double ddbez =
        6 * (s * (c[2] - 2 * c[1] + c[0]) + t * (c[3] - 2 * c[2] + c[1]));
    assert_near(v, bez, 1e-12);
    assert_near(d1, dbez, 1e-11);
    assert_near(d2, ddbez, 1e-10);

    satf_bspline_eval(c, 3, 1, t, &v, &d1, &d2);
    assert_near(v, s * s * c[0] + 2 * s * t * c[1] + t * t * c[2], 1e-12);
    assert_near(d2, 2 * (c[2] - 2 * c[1] + c[0]), 1e-10);

    satf_bspline_eval(c, 2, 1, t, &v, &d1, &d2);
    assert_near(v, s * c[0] + t * c[1], 1e-12);
    assert_near(d1, c[1] - c[0], 1e-12);
    assert_near(d2, 0.0, 1e-12);
  }
  double v, d1;
  satf_bspline_eval(c, 1, 1, 0.37, &v, &d1, NULL);
  assert_near(v, c[0], 0.0);
  assert_near(d1, 0.0, 0.0);
}

static void test_matches_cox_de_boor(void **state) {
  (void)state;
  const float c[9] = {0.2f, 1.5f, -0.7f, 2.2f, 0.9f, -1.1f, 3.0f, 0.4f, 1.0f};
  for (int n = 2; n <= 9; n++)
    for (int k = 0; k <= 97; k++) {
      double t = k / 97.0, v;
      satf_bspline_eval(c, n, 1, t, &v, NULL, NULL);
      assert_near(v, ref_eval(c, n, t), 1e-12);
    }
}

static void test_derivatives_match_finite_differences(void **state) {
  (void)state;
  const float c[7 * 3] = {0, 0, 0, 1, 0.5f, 0, 2, 2,  1, 1.5f, 3,
                          2, 0, 4, 3, -1,   3, 5, -2, 1, 4};
  const double h = 1e-5;
  for (int n = 3; n <= 7; n++)
    for (int k = 1; k < 50; k++) {
      double t = k / 50.0 + 0.003, v[3], d1[3], d2[3];
      double pa[3], pb[3], da[3], db[3];
      satf_bspline_eval(c, n, 3, t, v, d1, d2);
      satf_bspline_eval(c, n, 3, t - h, pa, da, NULL);
      satf_bspline_eval(c, n, 3, t + h, pb, db, NULL);
      for (int a = 0; a < 3; a++) {
        double fd1 = (pb[a] - pa[a]) / (2 * h);
        double fd2 = (db[a] - da[a]) / (2 * h);
        assert_near(d1[a], fd1, 1e-5 * (1.0 + fabs(d1[a])));
        assert_near(d2[a], fd2, 1e-4 * (1.0 + fabs(d2[a])));
      }
    }
}

static void test_partition_of_unity(void **state) {
  (void)state;
  const float c[6] = {2.5f, 2.5f, 2.5f, 2.5f, 2.5f, 2.5f};
  for (int n = 1; n <= 6; n++)
    for (int k = 0; k <= 33; k++) {
      double v, d1, d2;
      satf_bspline_eval(c, n, 1, k / 33.0, &v, &d1, &d2);
      assert_near(v, 2.5, 1e-12);
      assert_near(d1, 0.0, 1e-9);
      assert_near(d2, 0.0, 1e-7);
    }
}

/* t outside [0,1] (and NaN) clamps to the ends instead of reading out of
 * the control polygon. */
static void test_parameter_clamped(void **state) {
  (void)state;
  const float c[5] = {1, 2, 3, 4, 5};
  double v;
  satf_bspline_eval(c, 5, 1, -3.0, &v, NULL, NULL);
  assert_near(v, 1.0, 1e-12);
  satf_bspline_eval(c, 5, 1, 7.0, &v, NULL, NULL);
  assert_near(v, 5.0, 1e-12);
  satf_bspline_eval(c, 5, 1, NAN, &v, NULL, NULL);
  assert_near(v, 1.0, 1e-12);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_degree),
      cmocka_unit_test(test_endpoints_interpolate),
      cmocka_unit_test(test_straight_polygon_stays_on_line),
      cmocka_unit_test(test_bezier_closed_forms),
      cmocka_unit_test(test_matches_cox_de_boor),
      cmocka_unit_test(test_derivatives_match_finite_differences),
      cmocka_unit_test(test_partition_of_unity),
      cmocka_unit_test(test_parameter_clamped),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
