/* test_strand_curve.c - strand_curve.c: coarse polylines refined along the
 * Catmull-Rom curve through their points, fine or straight ones kept. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
/* cmocka needs the headers above first */
#include <cmocka.h>
#include <math.h>
#include <stdio.h>

#include "renderer_internal.h"
#include "satf/common.h"
#include "satf/math.h"

#define R 10.0 /* the circle's radius */

/* Distance of (x, y) from the circle of radius R about the origin. */
static double off_circle(const float *p) { return fabs(hypot(p[0], p[1]) - R); }

/* A circle sampled every 45 degrees (9 points, 8 chords of 7.65 units)
 * with width 1: each chord's middle lies 0.76 inside the circle, the
 * width's 0.76. Refined, the original points stay where they were, in
 * order, and between the second and the second last of them (the end
 * segments continue straight, reflected, not round) every point the curve
 * gives lies within 0.1 of the circle (the uniform Catmull-Rom curve of
 * these points is (-p0 + 9 p1 + 9 p2 - p3) / 16 at a segment's middle,
 * 0.9914 R from the centre: 0.086 inside, worked out by hand) and every
 * refined chord's middle within STRAND_CURVE_TOLERANCE of the width, plus
 * that 0.1. */
static void test_coarse_circle_follows_its_curve(void **state) {
  (void)state;
  float xyz[27], w[9];
  int count = 9;
  for (int i = 0; i < 9; i++) {
    double a = i * SATF_PI / 4.0;
    xyz[3 * i] = (float)(R * cos(a));
    xyz[3 * i + 1] = (float)(R * sin(a));
    xyz[3 * i + 2] = 0.0f;
    w[i] = 1.0f;
  }
  strand_curve c;
  satf_error err;
  assert_int_equal(strand_curve_refine(1, &count, xyz, w, 0.0f, &c, &err),
                   SATF_OK);
  assert_int_equal(c.n, 1);
  assert_int_equal((size_t)c.counts[0], c.total);
  assert_true(c.counts[0] > 9);
  double worst_point = 0.0, worst_chord = 0.0;
  int found = 0;
  for (size_t k = 0; k < c.total; k++) {
    const float *p = c.xyz + 3 * k;
    if (found < 9 && p[0] == xyz[3 * found] && p[1] == xyz[3 * found + 1])
      found++;
    assert_true(c.width[k] == 1.0f);
    if (found < 2 || found >= 8)
      continue; /* within the end segments */
    worst_point = fmax(worst_point, off_circle(p));
    float mid[3] = {0.5f * (p[0] + p[3]), 0.5f * (p[1] + p[4]), 0.0f};
    worst_chord = fmax(worst_chord, off_circle(mid));
  }
  float mid0[3] = {0.5f * (xyz[3] + xyz[6]), 0.5f * (xyz[4] + xyz[7]), 0.0f};
  printf("%zu points from 9; off the circle inside the ends: points %.3f, "
         "chords' middles %.3f (unrefined %.3f)\n",
         c.total, worst_point, worst_chord, off_circle(mid0));
  assert_int_equal(found, 9);
  assert_true(worst_point < 0.1);
  assert_true(worst_chord < STRAND_CURVE_TOLERANCE * 1.0 + 0.1);
  assert_true(off_circle(mid0) > STRAND_CURVE_TOLERANCE * 1.0 + 0.1);
  strand_curve_free(&c);
}

/* A straight strand and a finely sampled arc (1 degree a point) keep
 * their points, byte for byte; a strand without widths takes the
 * default. */
static void test_straight_and_fine_kept(void **state) {
  (void)state;
  float xyz[3 * 91];
  int counts[2] = {5, 91};
  for (int i = 0; i < 5; i++) {
    xyz[3 * i] = 0.0f;
    xyz[3 * i + 1] = (float)i;
    xyz[3 * i + 2] = 0.0f;
  }
  for (int i = 0; i < 86; i++) {
    double a = i * SATF_PI / 180.0;
    float *p = xyz + 15 + 3 * i;
    p[0] = (float)(R * cos(a));
    p[1] = (float)(R * sin(a));
    p[2] = 1.0f;
  }
  strand_curve c;
  satf_error err;
  counts[1] = 86;
  assert_int_equal(strand_curve_refine(2, counts, xyz, NULL, 0.5f, &c, &err),
                   SATF_OK);
  assert_int_equal(c.counts[0], 5);
  assert_int_equal(c.counts[1], 86);
  assert_int_equal(c.total, 91);
  assert_memory_equal(c.xyz, xyz, sizeof(float) * 3 * 91);
  for (size_t k = 0; k < c.total; k++)
    assert_true(c.width[k] == 0.5f);
  strand_curve_free(&c);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_coarse_circle_follows_its_curve),
      cmocka_unit_test(test_straight_and_fine_kept),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
