/* test_strand_render.c - the strand reference path
 * (satf_renderer_set_strands): straight vertical strands seen from the
 * front, whose pixels are computed from the camera. Alpha lies along the
 * projected strands and nowhere else; the alpha summed across a strand is
 * its width in pixels, so a thicker strand covers more; a strand half a
 * pixel wide centred on a pixel gives that pixel alpha 0.5; a strand with
 * another between it and the key light is darker than without (the deep
 * opacity map is built from the strands); AOVs come out too. Whole frames
 * on Mesa's llvmpipe through a headless EGL context. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
/* cmocka needs the headers above first */
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_fixture.h"
#include "satf/common.h"
#include "satf/render.h"
#include "test_util.h"

#define W 128
#define H 96
#define DIST 20.0  /* camera on +z, looking at the origin */
#define FOV_Y 30.0 /* degrees */
#define POINTS 7   /* points per test strand */

/* The strands are what is drawn; the scene gives the camera, the light
 * (travelling towards -x, so from +x), the material and a small cluster
 * behind them, which strand mode does not draw. */
static const char *scene_json =
    "{\"macro_clusters\": [{\"prototype\": {"
    "  \"trajectory\": [[0, -3, -1], [0, 3, -1]], \"a\": 0.3,"
    "  \"shell\": {\"layers\": 3, \"st\": 8, \"su\": 8}}}],"
    " \"camera\": {\"position\": [0, 0, 20], \"target\": [0, 0, 0],"
    "              \"fov_y\": 30},"
    " \"lights\": [{\"direction\": [-1, 0, 0]}],"
    " \"background\": [0, 0, 0],"
    " \"image\": {\"width\": 128, \"height\": 96}}";

typedef fixture_gl fixture;

FIXTURE_GL_GROUP(W, H)

/* Pixels per scene unit in the plane z = 0. */
static double px_per_unit(void) {
  return 0.5 * H / (DIST * tan(0.5 * FOV_Y * 3.14159265358979 / 180.0));
}

/* The scene x whose projection is column `col` + `frac` (0.5: the
 * pixel's centre). */
static float x_of_column(double col) {
  return (float)((col - 0.5 * W) / px_per_unit());
}

typedef struct strand_spec {
  float x, z, width; /* a vertical strand from y = -3 to 3 */
  /* or, with horizontal set, one segment from (-5, y0, z) to (5, y0, -z) */
  int horizontal;
  float y0;
} strand_spec;

/* Renders the strands (with AOVs when aovs) through the pixel filter;
 * the caller destroys it. */
static satf_image *render_filtered(const fixture *f, const strand_spec *spec,
                                   int n, int aovs, int shadows,
                                   satf_pixel_filter filter) {
  satf_scene *scene = fixture_scene(scene_json);
  assert_non_null(scene);
  satf_renderer *r = NULL;
  satf_error err;
  if (satf_renderer_create(scene, f->db, W, H, 0, &r, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_renderer_effects(r)->cluster_shadows = shadows;
  satf_renderer_set_pixel_filter(r, filter);
  assert_int_equal(satf_renderer_pixel_filter(r), filter);
  int counts[8], at = 0;
  float xyz[8 * POINTS * 3], width[8 * POINTS];
  for (int i = 0; i < n; i++) {
    counts[i] = spec[i].horizontal ? 2 : POINTS;
    for (int j = 0; j < counts[i]; j++, at++) {
      float *p = xyz + 3 * at, f = (float)j / (float)(counts[i] - 1);
      p[0] = spec[i].horizontal ? -5.0f + 10.0f * f : spec[i].x;
      p[1] = spec[i].horizontal ? spec[i].y0 : -3.0f + 6.0f * f;
      p[2] = spec[i].horizontal ? spec[i].z * (1.0f - 2.0f * f) : spec[i].z;
      width[at] = spec[i].width;
    }
  }
  if (satf_renderer_set_strands(r, n, counts, xyz, width, 0.0f, &err) !=
      SATF_OK)
    fail_msg("%s", err.message);
  assert_int_equal(satf_renderer_strand_count(r), n);
  satf_image *img = NULL;
  satf_frame_timing t;
  if (satf_renderer_render_image(r, aovs, &img, &t, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
  return img;
}

static satf_image *render_strands(const fixture *f, const strand_spec *spec,
                                  int n, int aovs, int shadows) {
  return render_filtered(f, spec, n, aovs, shadows, SATF_PIXEL_FILTER_BOX);
}

static float at(const satf_image *img, const char *ch, int col, int row) {
  return fixture_plane(img, ch)[(size_t)row * W + (size_t)col];
}

/* Alpha summed along row `row` over columns [c0, c1). */
static double row_sum(const satf_image *img, int row, int c0, int c1) {
  double s = 0.0;
  for (int c = c0; c < c1; c++)
    s += at(img, "A", c, row);
  return s;
}

/* Two strands 3 and 1.5 pixels wide, centred on columns 40 and 90 (their
 * projected centre lines, x = -2.6 and 2.8 units about): alpha 1 at their
 * centres, 0 a few pixels off and above their ends, and the alpha summed
 * across each is its width in pixels. */
static void test_coverage_follows_strands(void **state) {
  double ppu = px_per_unit();
  strand_spec s[2] = {{x_of_column(40.5), 0.0f, (float)(3.0 / ppu), 0, 0.0f},
                      {x_of_column(90.5), 0.0f, (float)(1.5 / ppu), 0, 0.0f}};
  satf_image *img = render_strands(*state, s, 2, 0, 1);
  /* the strands span y in [-3, 3]: rows 48 -+ 3 ppu (26.9 px) */
  int rows[3] = {30, 48, 66};
  for (int k = 0; k < 3; k++) {
    int row = rows[k];
    double wide = row_sum(img, row, 30, 51), thin = row_sum(img, row, 80, 101);
    printf("row %d: alpha across the 3 px strand %.3f, across the 1.5 px "
           "strand %.3f; centres %.3f %.3f\n",
           row, wide, thin, at(img, "A", 40, row), at(img, "A", 90, row));
    assert_true(at(img, "A", 40, row) > 0.95f);
    assert_true(at(img, "A", 90, row) > 0.95f);
    /* a 3 px strand centred on a pixel centre covers pixels 39-41; the
     * 1.5 px one covers pixel 90 and a quarter of 89 and 91 */
    assert_near(at(img, "A", 39, row), 1.0, 0.05);
    assert_near(at(img, "A", 41, row), 1.0, 0.05);
    assert_near(at(img, "A", 38, row), 0.0, 0.05);
    assert_near(at(img, "A", 89, row), 0.25, 0.1);
    assert_near(at(img, "A", 91, row), 0.25, 0.1);
    assert_near(wide, 3.0, 0.3);
    assert_near(thin, 1.5, 0.2);
    assert_true(wide > 1.6 * thin); /* thicker covers more */
    /* nothing a few pixels off either strand */
    for (int c = 0; c < W; c++)
      if (abs(c - 40) > 3 && abs(c - 90) > 3)
        assert_true(at(img, "A", c, row) == 0.0f);
  }
  /* nothing above or below the strands' ends (rows 21 and 75) */
  for (int c = 0; c < W; c++) {
    assert_true(at(img, "A", c, 5) == 0.0f);
    assert_true(at(img, "A", c, 90) == 0.0f);
  }
  /* lit: colour where there is alpha */
  assert_true(at(img, "R", 40, 48) + at(img, "G", 40, 48) > 0.01f);
  satf_image_destroy(img);
}

/* A strand half a pixel wide, centred on column 64's centre, is drawn a
 * pixel wide with alpha its coverage, 0.5, not as an aliased line; one a
 * quarter pixel wide, 0.25. */
static void test_subpixel_alpha_is_coverage(void **state) {
  double ppu = px_per_unit();
  strand_spec s[2] = {{x_of_column(64.5), 0.0f, (float)(0.5 / ppu), 0, 0.0f},
                      {x_of_column(100.5), 0.0f, (float)(0.25 / ppu), 0, 0.0f}};
  satf_image *img = render_strands(*state, s, 2, 0, 1);
  for (int row = 30; row <= 66; row += 6) {
    printf("row %d: half-pixel strand alpha %.3f (neighbours %.3f %.3f), "
           "quarter %.3f; sums %.3f %.3f\n",
           row, at(img, "A", 64, row), at(img, "A", 63, row),
           at(img, "A", 65, row), at(img, "A", 100, row),
           row_sum(img, row, 60, 69), row_sum(img, row, 96, 105));
    assert_near(at(img, "A", 64, row), 0.5, 0.15);
    assert_near(at(img, "A", 100, row), 0.25, 0.1);
    assert_near(row_sum(img, row, 60, 69), 0.5, 0.1);
    assert_near(row_sum(img, row, 96, 105), 0.25, 0.06);
  }
  satf_image_destroy(img);
}

/* A strand a pixel wide centred on column 64's centre: through the box,
 * pixel 64 alone with alpha 1; through Cycles' Blackman-Harris film filter
 * (3 pixels of support, strand_cover.glsl) the same coverage, 1 summed
 * across, spread as Cycles spreads it: the window's integral over
 * [-0.5, 0.5] at the centre, 0.7628, and over [0.5, 1.5] on each
 * neighbour, 0.1186 (worked out from the window's closed-form integral
 * apart from the shader), nothing two pixels off (past the support's 1.5
 * plus the strand's half width). */
static void test_blackman_harris_fringe(void **state) {
  double ppu = px_per_unit();
  strand_spec s[1] = {{x_of_column(64.5), 0.0f, (float)(1.0 / ppu), 0, 0.0f}};
  satf_image *box = render_strands(*state, s, 1, 0, 0);
  satf_image *bh =
      render_filtered(*state, s, 1, 0, 0, SATF_PIXEL_FILTER_BLACKMAN_HARRIS);
  for (int row = 36; row <= 60; row += 8) {
    printf("row %d: box %.3f %.3f %.3f, Blackman-Harris %.4f %.4f %.4f %.4f "
           "(sum %.3f)\n",
           row, at(box, "A", 63, row), at(box, "A", 64, row),
           at(box, "A", 65, row), at(bh, "A", 62, row), at(bh, "A", 63, row),
           at(bh, "A", 64, row), at(bh, "A", 65, row),
           row_sum(bh, row, 58, 71));
    assert_near(at(box, "A", 64, row), 1.0, 0.03);
    assert_true(at(box, "A", 63, row) < 0.01f);
    assert_near(at(bh, "A", 64, row), 0.7628, 0.01);
    assert_near(at(bh, "A", 63, row), 0.1186, 0.01);
    assert_near(at(bh, "A", 65, row), 0.1186, 0.01);
    assert_true(at(bh, "A", 62, row) < 0.002f);
    assert_true(at(bh, "A", 66, row) < 0.002f);
    assert_near(row_sum(bh, row, 58, 71), 1.0, 0.05);
  }
  satf_image_destroy(box);
  satf_image_destroy(bh);
}

/* The default filter, AUTO, is Blackman-Harris for hair of at most
 * SATF_RENDER_FILTER_AUTO_STRANDS strands and the box above: the strand a
 * pixel wide of test_blackman_harris_fringe alone, then with a thousand
 * more strands out of view; each image equals the one of the filter it
 * stands for, pixel for pixel, and the two differ at the strand. */
static void test_auto_filter_by_strand_count(void **state) {
  double ppu = px_per_unit();
  enum { HIDDEN = SATF_RENDER_FILTER_AUTO_STRANDS };
  satf_image *img[2][2]; /* [many][auto, the filter it stands for] */
  for (int many = 0; many <= 1; many++)
    for (int k = 0; k <= 1; k++) {
      satf_scene *scene = fixture_scene(scene_json);
      assert_non_null(scene);
      satf_renderer *r = NULL;
      satf_error err;
      if (satf_renderer_create(scene, ((const fixture *)*state)->db, W, H, 0,
                               &r, &err) != SATF_OK)
        fail_msg("%s", err.message);
      assert_int_equal(satf_renderer_pixel_filter(r), SATF_PIXEL_FILTER_AUTO);
      if (k)
        satf_renderer_set_pixel_filter(
            r,
            many ? SATF_PIXEL_FILTER_BOX : SATF_PIXEL_FILTER_BLACKMAN_HARRIS);
      int n = 1 + (many ? HIDDEN : 0);
      int *counts = malloc((size_t)n * sizeof *counts);
      float *xyz = malloc((size_t)n * 6 * sizeof *xyz);
      float *width = malloc((size_t)n * 2 * sizeof *width);
      assert_non_null(counts);
      assert_non_null(xyz);
      assert_non_null(width);
      for (int i = 0; i < n; i++) { /* strand 0 in view, the rest far off */
        float x = i == 0 ? (float)x_of_column(64.5) : 1e3f + (float)i;
        float p[6] = {x, -3.0f, 0.0f, x, 3.0f, 0.0f};
        counts[i] = 2;
        memcpy(xyz + 6 * i, p, sizeof p);
        width[2 * i] = width[2 * i + 1] = (float)(1.0 / ppu);
      }
      if (satf_renderer_set_strands(r, n, counts, xyz, width, 0.0f, &err) !=
          SATF_OK)
        fail_msg("%s", err.message);
      satf_frame_timing t;
      if (satf_renderer_render_image(r, 0, &img[many][k], &t, &err) != SATF_OK)
        fail_msg("%s", err.message);
      free(counts);
      free(xyz);
      free(width);
      satf_renderer_destroy(r);
      satf_scene_destroy(scene);
    }
  for (int many = 0; many <= 1; many++) {
    double worst = 0.0;
    for (int row = 0; row < H; row++)
      for (int col = 0; col < W; col++) {
        double d = fabs(at(img[many][0], "A", col, row) -
                        at(img[many][1], "A", col, row));
        worst = d > worst ? d : worst;
      }
    printf("%d strands: auto against %s, largest alpha difference %.2e; "
           "alpha at column 63 %.4f\n",
           many ? 1 + HIDDEN : 1, many ? "the box" : "Blackman-Harris", worst,
           at(img[many][0], "A", 63, 48));
    assert_true(worst < 1e-6);
  }
  assert_near(at(img[0][0], "A", 63, 48), 0.1186, 0.01);
  assert_true(at(img[1][0], "A", 63, 48) < 0.01f);
  for (int many = 0; many <= 1; many++)
    for (int k = 0; k <= 1; k++)
      satf_image_destroy(img[many][k]);
}

/* Mean premultiplied colour per unit alpha over the strand at column col. */
static double strand_luma(const satf_image *img, int col) {
  double rgb = 0.0, a = 0.0;
  for (int row = 30; row <= 66; row++)
    for (int c = col - 2; c <= col + 2; c++) {
      rgb += at(img, "R", c, row) + at(img, "G", c, row) + at(img, "B", c, row);
      a += at(img, "A", c, row);
    }
  return a > 0.0 ? rgb / a : 0.0;
}

/* The light travels towards -x: a strand at x = 2 lies between it and a
 * strand at x = 0 (not in front of it from the camera). The shadowed
 * strand is darker than the same strand alone, and than with the deep
 * opacity map off; the occluder itself is not shadowed. */
static void test_strands_shadow_strands(void **state) {
  double ppu = px_per_unit();
  float w = (float)(3.0 / ppu); /* 0.33 units: over a DOM texel */
  strand_spec both[2] = {{x_of_column(64.5), 0.0f, w, 0, 0.0f},
                         {x_of_column(64.5) + 2.0f, 0.0f, 2.0f * w, 0, 0.0f}};
  satf_image *shadowed = render_strands(*state, both, 2, 0, 1);
  satf_image *alone = render_strands(*state, both, 1, 0, 1);
  satf_image *no_dom = render_strands(*state, both, 2, 0, 0);
  int occ = (int)floor(0.5 * W + (x_of_column(64.5) + 2.0) * ppu);
  double l_sh = strand_luma(shadowed, 64), l_alone = strand_luma(alone, 64);
  double l_off = strand_luma(no_dom, 64), l_occ = strand_luma(shadowed, occ);
  double l_occ_off = strand_luma(no_dom, occ);
  printf("strand luminance: shadowed %.4f, alone %.4f, opacity map off "
         "%.4f; occluder %.4f (off %.4f)\n",
         l_sh, l_alone, l_off, l_occ, l_occ_off);
  assert_true(l_alone > 0.01);
  assert_true(l_sh < 0.6 * l_alone);
  assert_true(l_sh < 0.6 * l_off);
  assert_near(l_occ, l_occ_off, 0.1 * l_occ_off);
  satf_image_destroy(shadowed);
  satf_image_destroy(alone);
  satf_image_destroy(no_dom);
}

/* Luminance of a pixel's colour per unit alpha. */
static double pixel_luma(const satf_image *img, int col, int row) {
  double a = at(img, "A", col, row);
  return (0.2126 * at(img, "R", col, row) + 0.7152 * at(img, "G", col, row) +
          0.0722 * at(img, "B", col, row)) /
         (a > 0.0 ? a : 1.0);
}

/* Wide strands hide each other pixel by pixel, not segment by segment: a
 * horizontal strand, one segment tilted in depth (z from 2 at x = -5 to -2
 * at x = 5, its centre at z = 0), crosses a vertical one at x = -2.5,
 * z = 0.5, where it is in front (z = 1). Ordered by segment centres alone
 * the vertical strand's segments (centres at z = 0.5) would be drawn over
 * it. The light
 * comes from +x: the horizontal strand, along it, is dark (Kajiya-Kay
 * diffuse goes as the sine between tangent and light), the vertical one
 * bright, so the crossing shows which is on top. */
static void test_wide_strands_occlude_per_pixel(void **state) {
  double ppu = px_per_unit();
  float w = (float)(4.0 / ppu);
  strand_spec s[2] = {{0.0f, 2.0f, w, 1, (float)(0.5 / ppu)},
                      {-2.5f, 0.5f, w, 0, 0.0f}};
  satf_image *img = render_strands(*state, s, 2, 0, 0);
  /* the vertical strand's column: x = -2.5 at distance 19.5 */
  int col = (int)floor(0.5 * W - 2.5 * ppu * DIST / 19.5);
  double cross = pixel_luma(img, col, 47);
  double horiz = pixel_luma(img, col - 8, 47);
  double vert = pixel_luma(img, col, 30);
  printf("column %d: crossing %.4f, horizontal strand %.4f, vertical %.4f\n",
         col, cross, horiz, vert);
  assert_true(at(img, "A", col, 47) > 0.95f);
  assert_true(vert > 2.0 * horiz);
  assert_near(cross, horiz, 0.25 * horiz);
  satf_image_destroy(img);
}

/* AOVs in strand mode: alpha.Y is the coverage, the light AOVs add up to
 * the beauty pass. */
static void test_strand_aovs(void **state) {
  strand_spec s[1] = {
      {x_of_column(64.5), 0.0f, (float)(3.0 / px_per_unit()), 0, 0.0f}};
  satf_image *img = render_strands(*state, s, 1, 1, 1);
  for (int row = 30; row <= 66; row += 12) {
    assert_near(at(img, "alpha.Y", 64, row), at(img, "A", 64, row), 0.01);
    double sum = at(img, "diffuse.G", 64, row) + at(img, "specI.G", 64, row) +
                 at(img, "specII.G", 64, row);
    assert_near(sum, at(img, "G", 64, row), 0.01 + 0.01 * sum);
    assert_true(at(img, "shadow.Y", 64, row) > 0.0f);
  }
  satf_image_destroy(img);
}

/* Degenerate strands draw without NaN: repeated points, a hairpin whose
 * tip has no direction, a strand seen end-on, one of zero width. */
static void test_degenerate_strands(void **state) {
  const fixture *f = *state;
  satf_scene *scene = fixture_scene(scene_json);
  satf_renderer *r = NULL;
  satf_error err;
  assert_int_equal(satf_renderer_create(scene, f->db, W, H, 0, &r, &err),
                   SATF_OK);
  int counts[4] = {4, 3, 2, 2};
  float xyz[] = {-2, -3, 0,  -2, 0, 0, -2, 0,  0, -2, 3, 0, /* repeated */
                 0,  -3, 0,  0,  3, 0, 0,  -3, 0,           /* hairpin */
                 2,  0,  -1, 2,  0, 1,                      /* end-on */
                 3,  -3, 0,  3,  3, 0};                     /* zero width */
  float width[11] = {0.2f, 0.2f, 0.2f, 0.2f, 0.2f, 0.2f,
                     0.2f, 0.2f, 0.2f, 0.0f, 0.0f};
  assert_int_equal(
      satf_renderer_set_strands(r, 4, counts, xyz, width, 0.0f, &err), SATF_OK);
  satf_image *img = NULL;
  satf_frame_timing t;
  if (satf_renderer_render_image(r, 1, &img, &t, &err) != SATF_OK)
    fail_msg("%s", err.message);
  double sum = 0.0;
  for (int c = 0; c < satf_image_channel_count(img); c++) {
    const float *p = satf_image_const_plane(img, c);
    for (size_t i = 0; i < (size_t)W * H; i++) {
      assert_true(isfinite(p[i]));
      sum += p[i];
    }
  }
  assert_true(sum > 0.0);
  /* the zero-width strand (x = 3) covers nothing */
  int col = (int)floor(0.5 * W + 3.0 * px_per_unit());
  for (int row = 30; row <= 66; row++)
    assert_true(at(img, "A", col, row) == 0.0f);
  satf_image_destroy(img);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

/* Bad strands are refused with a reason; zero strands is the cluster
 * path again. */
static void test_bad_strands(void **state) {
  const fixture *f = *state;
  satf_scene *scene = fixture_scene(scene_json);
  satf_renderer *r = NULL;
  satf_error err;
  assert_int_equal(satf_renderer_create(scene, f->db, W, H, 0, &r, &err),
                   SATF_OK);
  int one[1] = {1}, two[1] = {2};
  float xyz[6] = {0, 0, 0, 0, 1, 0}, bad[6] = {0, 0, 0, 0, NAN, 0};
  assert_int_equal(satf_renderer_set_strands(r, 1, one, xyz, NULL, 0.1f, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "strand 0 has 1 points"));
  assert_int_equal(satf_renderer_set_strands(r, 1, two, bad, NULL, 0.1f, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "not finite"));
  assert_int_equal(satf_renderer_set_strands(r, 1, two, xyz, NULL, 0.0f, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_renderer_set_strands(r, 1, two, xyz, NULL, 0.1f, &err),
                   SATF_OK);
  assert_int_equal(satf_renderer_strand_count(r), 1);
  assert_int_equal(satf_renderer_set_strands(r, 0, NULL, NULL, NULL, 0, &err),
                   SATF_OK);
  assert_int_equal(satf_renderer_strand_count(r), 0);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_coverage_follows_strands),
      cmocka_unit_test(test_subpixel_alpha_is_coverage),
      cmocka_unit_test(test_blackman_harris_fringe),
      cmocka_unit_test(test_auto_filter_by_strand_count),
      cmocka_unit_test(test_strands_shadow_strands),
      cmocka_unit_test(test_wide_strands_occlude_per_pixel),
      cmocka_unit_test(test_strand_aovs),
      cmocka_unit_test(test_degenerate_strands),
      cmocka_unit_test(test_bad_strands),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
