/* test_fiber_strands.c - the strand reference path with the physical
 * material (strands.c, glsl/strand_fs.glsl with fiber.glsl): one wide
 * vertical strand seen from the front, whose pixels are computed in C from
 * the fibre model (satf_fiber_dual_shade with no hair in the way) at the
 * offset h each pixel centre has across the ribbon, times the light's
 * irradiance (colour x intensity), with and without the deep opacity map.
 * That checks the fibre frame, the sign and scale of h, the light's units
 * and the tables' upload. A back light makes the strand glow through TT,
 * reddish for brown hair; a second strand wholly between the key light and
 * the first leaves it about e^-1 of its light (one hair in the way, plus
 * forward scattering). Whole frames on Mesa's llvmpipe through a headless
 * EGL context. */
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
#include "satf/fiber.h"
#include "satf/render.h"
#include "test_util.h"

#define W 128
#define H 96
#define DIST 20.0  /* camera on +z, looking at the origin */
#define FOV_Y 30.0 /* degrees */
#define POINTS 7
#define WIDTH 2.0f /* the strand's width: ~9 pixels */

typedef fixture_gl fixture;

/* The fixture's parameters with fibre records: the physical mode needs a
 * fibre database even though the strands do not read it. */
static int setup(void **state) {
  fixture *f = calloc(1, sizeof *f);
  satf_error err;
  if (!f)
    return -1;
  if (satf_gl_context_create_headless(W, H, &f->ctx, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    free(f);
    return -1;
  }
  satf_build_params p = fixture_db_params();
  p.kind = SATF_RECORD_FIBER;
  if (satf_build(&p, 0, NULL, NULL, &f->db, &err) != SATF_OK) {
    fprintf(stderr, "fibre database: %s\n", err.message);
    satf_gl_context_destroy(f->ctx);
    free(f);
    return -1;
  }
  *state = f;
  return 0;
}

static int teardown(void **state) {
  fixture_gl_free(*state);
  return 0;
}

static double px_per_unit(void) {
  return 0.5 * H / (DIST * tan(0.5 * FOV_Y * 3.14159265358979 / 180.0));
}

/* The scene: camera on +z, one directional light, the physical material
 * (melanin 0.5, redness 0.2, roughness 0.3, radial roughness 0.4, tilt 2,
 * ior 1.55), a cluster the strand mode does not draw. */
static satf_scene *make_scene(const float light_dir[3], float intensity) {
  char json[1400];
  snprintf(json, sizeof json,
           "{\"macro_clusters\": [{\"prototype\": {"
           "  \"trajectory\": [[0, -3, -1], [0, 3, -1]], \"a\": 0.3,"
           "  \"shell\": {\"layers\": 3, \"st\": 8, \"su\": 8}}}],"
           " \"camera\": {\"position\": [0, 0, 20], \"target\": [0, 0, 0],"
           "              \"fov_y\": 30},"
           " \"lights\": [{\"direction\": [%g, %g, %g],"
           "   \"color\": [1, 0.9, 0.8], \"intensity\": %g}],"
           " \"material\": {\"model\": \"physical\", \"melanin\": 0.5,"
           "   \"redness\": 0.2, \"roughness\": 0.3, \"radial_roughness\": 0.4,"
           "   \"cuticle_tilt\": 2, \"ior\": 1.55},"
           " \"background\": [0, 0, 0],"
           " \"image\": {\"width\": 128, \"height\": 96}}",
           (double)light_dir[0], (double)light_dir[1], (double)light_dir[2],
           (double)intensity);
  return fixture_scene(json);
}

/* Vertical strands at x[i], depth z[i], `width` wide. */
static satf_image *render_width(const fixture *f, const float light_dir[3],
                                float intensity, const float *x, const float *z,
                                int n, int shadows, float strand_width) {
  satf_scene *scene = make_scene(light_dir, intensity);
  assert_non_null(scene);
  satf_renderer *r = NULL;
  satf_error err;
  if (satf_renderer_create(scene, f->db, W, H, 0, &r, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_renderer_effects(r)->cluster_shadows = shadows;
  int counts[4];
  float xyz[4 * POINTS * 3], width[4 * POINTS];
  for (int i = 0, at = 0; i < n; i++) {
    counts[i] = POINTS;
    for (int j = 0; j < POINTS; j++, at++) {
      xyz[3 * at] = x[i];
      xyz[3 * at + 1] = -3.0f + 6.0f * (float)j / (POINTS - 1);
      xyz[3 * at + 2] = z[i];
      width[at] = strand_width;
    }
  }
  if (satf_renderer_set_strands(r, n, counts, xyz, width, 0.0f, &err) !=
      SATF_OK)
    fail_msg("%s", err.message);
  satf_image *img = NULL;
  satf_frame_timing t;
  if (satf_renderer_render_image(r, 0, &img, &t, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
  return img;
}

static satf_image *render(const fixture *f, const float light_dir[3],
                          float intensity, const float *x, const float *z,
                          int n, int shadows) {
  return render_width(f, light_dir, intensity, x, z, n, shadows, WIDTH);
}

static float px(const satf_image *img, const char *ch, int col, int row) {
  return fixture_plane(img, ch)[(size_t)row * W + (size_t)col];
}

static void test_fiber(satf_fiber *f, float *tables, int n) {
  satf_fiber_material m = satf_fiber_material_default();
  m.melanin = 0.5f;
  m.redness = 0.2f;
  m.roughness = 0.3f;
  m.radial_roughness = 0.4f;
  m.cuticle_tilt = 2.0f * 3.14159265f / 180.0f;
  satf_fiber_init(f, &m);
  satf_fiber_dual_tables(f, n, tables);
}

/* The pixels across the strand's middle against the model in C. */
static void pixels_match_the_model(void **state) {
  const fixture *fx = *state;
  const float light[3] = {-0.6f, -0.2f, -0.7746f}; /* travelling to -x -z */
  const float x0[1] = {0.0f}, z0[1] = {0.0f};
  /* with and without the deep opacity map: a lone strand is the first
   * hair towards the light everywhere, so the map must not dim it */
  for (int shadows = 0; shadows <= 1; shadows++) {
    satf_image *img = render(fx, light, 2.0f, x0, z0, 1, shadows);
    satf_fiber f;
    float tables[32 * SATF_FIBER_DUAL_FIELDS * 3];
    test_fiber(&f, tables, 32);
    const float rgb[3] = {2.0f, 1.8f, 1.6f}; /* colour x intensity */
    int row = H / 2, checked = 0;
    double half_px = 0.5 * WIDTH * px_per_unit();
    for (int col = 0; col < W; col++) {
      double x = (col + 0.5 - 0.5 * W) / px_per_unit();
      /* only pixels the strand covers whole, one pixel from its edges */
      if (fabs(x) * px_per_unit() > half_px - 1.0)
        continue;
      assert_near(px(img, "A", col, row), 1.0, 1e-3);
      /* the fibre frame: x up the strand, z towards the eye, y = z x x, so
       * h runs along -x in the world (strand_fs.glsl) */
      /* the eye's direction from the strand's centre line, as the shader
       * takes it (v_world is the centre line: the ribbon is widened in
       * screen space), so the frame is the same across the ribbon */
      double ex = 0.0, ez = DIST;
      double el = sqrt(ex * ex + ez * ez);
      double zx = ex / el, zz = ez / el; /* the frame's z: the eye's side */
      double yx = -zz, yz = zx;          /* y = z x t, t = +Y */
      double lx = -light[0], ly = -light[1], lz = -light[2];
      double ll = sqrt(lx * lx + ly * ly + lz * lz);
      float wo[3] = {0.0f, 0.0f, 1.0f};
      float wi[3] = {(float)(ly / ll), (float)((lx * yx + lz * yz) / ll),
                     (float)((lx * zx + lz * zz) / ll)};
      /* h: the across-ribbon pixel offset over half the width in pixels,
       * positive on the frame's +y side (-x here) */
      float h = (float)(-x / (0.5 * WIDTH));
      float want[3];
      /* with the map, a lone strand has no hair behind it to send back
       * local back-scattering (d_b 0); without, a hair volume's d_b */
      satf_fiber_dual_shade_behind(&f, tables, 32, wo, wi, h, 0.0f,
                                   shadows ? 0.0f : INFINITY, want);
      for (int c = 0; c < 3; c++) {
        float got = px(img, c == 0 ? "R" : c == 1 ? "G" : "B", col, row);
        double expect = rgb[c] * want[c];
        if (fabs(got - expect) > 0.02 * expect + 1e-4)
          fprintf(stderr, "col %d h %.3f c %d: %g, model %g\n", col, h, c, got,
                  expect);
        assert_near(got, expect, 0.02 * expect + 1e-4);
      }
      checked++;
    }
    assert_true(checked >= 5);
    satf_image_destroy(img);
  }
}

/* A strand thinner than a pixel: its light is the fibre's average over
 * the offsets h (strand_light_cs.glsl, per point), so a row's pixels sum
 * to the model's mean over h times the strand's width in pixels (the
 * coverages sum to the width). */
static void thin_strand_averages_the_fibre(void **state) {
  const fixture *fx = *state;
  const float light[3] = {-0.6f, -0.2f, -0.7746f};
  const float x0[1] = {0.0f}, z0[1] = {0.0f};
  const float width = 0.1f; /* 0.9 pixels */
  satf_image *img = render_width(fx, light, 2.0f, x0, z0, 1, 0, width);
  satf_fiber f;
  float tables[32 * SATF_FIBER_DUAL_FIELDS * 3];
  test_fiber(&f, tables, 32);
  const float rgb[3] = {2.0f, 1.8f, 1.6f};
  /* the frame as pixels_match_the_model's: the eye on +z, t = +Y */
  double lx = -light[0], ly = -light[1], lz = -light[2];
  double ll = sqrt(lx * lx + ly * ly + lz * lz);
  float wo[3] = {0.0f, 0.0f, 1.0f};
  float wi[3] = {(float)(ly / ll), (float)(-lx / ll), (float)(lz / ll)};
  double mean[3] = {0, 0, 0};
  enum { NH = 512 };
  for (int k = 0; k < NH; k++) {
    float want[3];
    satf_fiber_dual_shade(&f, tables, 32, wo, wi,
                          -1.0f + (k + 0.5f) * 2.0f / NH, 0.0f, want);
    for (int c = 0; c < 3; c++)
      mean[c] += want[c] / NH;
  }
  double wpx = width * px_per_unit(), alpha = 0.0, sum[3] = {0, 0, 0};
  for (int col = 0; col < W; col++) {
    alpha += px(img, "A", col, H / 2);
    sum[0] += px(img, "R", col, H / 2);
    sum[1] += px(img, "G", col, H / 2);
    sum[2] += px(img, "B", col, H / 2);
  }
  assert_near(alpha, wpx, 0.01 * wpx);
  for (int c = 0; c < 3; c++) {
    double expect = rgb[c] * mean[c] * wpx;
    fprintf(stderr, "thin strand c %d: row sum %g, model's mean over h %g\n", c,
            sum[c], expect);
    assert_near(sum[c], expect, 0.03 * expect);
  }
  satf_image_destroy(img);
}

/* Back-lit brown hair glows through TT: the strand lit from behind is
 * bright, and redder than front-lit. */
static void back_light_glows(void **state) {
  const fixture *fx = *state;
  const float back[3] = {0.0f, -0.2f, 0.98f}; /* towards the camera */
  const float front[3] = {0.0f, -0.2f, -0.98f};
  const float x0[1] = {0.0f}, z0[1] = {0.0f};
  satf_image *b = render(fx, back, 1.0f, x0, z0, 1, 0);
  satf_image *f = render(fx, front, 1.0f, x0, z0, 1, 0);
  double sb[3] = {0}, sf[3] = {0};
  for (int col = W / 2 - 3; col <= W / 2 + 2; col++)
    for (int c = 0; c < 3; c++) {
      const char *ch = c == 0 ? "R" : c == 1 ? "G" : "B";
      sb[c] += px(b, ch, col, H / 2);
      sf[c] += px(f, ch, col, H / 2);
    }
  assert_true(sb[0] > 0.01);
  /* TT through brown hair: red over blue well above R's white */
  assert_true(sb[0] / sb[2] > 1.5 * (sf[0] / sf[2]));
  satf_image_destroy(b);
  satf_image_destroy(f);
}

/* A strand between the key light and the first: the first is darker than
 * unshadowed but brighter than its direct light alone through the
 * crossing's Poisson probability (forward scattering), as the model says
 * for one hair in the way (satf_fiber_dual_shade, n = 1). */
static void shadowed_strand_keeps_forward_scattering(void **state) {
  const fixture *fx = *state;
  /* the light from +x+z; the blocker at (4, y, 4) lies on the first's
   * ray to it and off the camera's view of the first */
  const float tilted[3] = {-0.7071f, 0.0f, -0.7071f};
  const float x1[1] = {0.0f}, z1[1] = {0.0f};
  const float x2[2] = {0.0f, 4.0f}, z2[2] = {0.0f, 4.0f};
  satf_image *alone = render(fx, tilted, 1.0f, x1, z1, 1, 1);
  satf_image *shadowed = render(fx, tilted, 1.0f, x2, z2, 2, 1);
  satf_fiber f;
  float tables[32 * SATF_FIBER_DUAL_FIELDS * 3];
  test_fiber(&f, tables, 32);
  /* the frame of pixels_match_the_model: wi = (l.y, -l.x, l.z) */
  const float wo[3] = {0.0f, 0.0f, 1.0f};
  const float wi[3] = {0.0f, -0.7071068f, 0.7071068f};
  double a = 0, s = 0, m0 = 0, m1 = 0, m2 = 0;
  for (int col = W / 2 - 3; col <= W / 2 + 2; col++) {
    a += px(alone, "R", col, H / 2);
    s += px(shadowed, "R", col, H / 2);
    double x = (col + 0.5 - 0.5 * W) / px_per_unit();
    float h = (float)(-x / (0.5 * WIDTH)), o[3];
    /* nothing behind the first strand, which the light reaches first */
    satf_fiber_dual_shade_behind(&f, tables, 32, wo, wi, h, 0.0f, 0.0f, o);
    m0 += o[0];
    satf_fiber_dual_shade_behind(&f, tables, 32, wo, wi, h, 1.0f, 0.0f, o);
    m1 += o[0];
    satf_fiber_dual_shade_behind(&f, tables, 32, wo, wi, h, 2.0f, 0.0f, o);
    m2 += o[0];
  }
  /* one hair wholly in the way (n = 1): the model's 0.51 of the lone
   * strand (direct e^-1 plus the forward-scattered part); counting the
   * lit strand too (n = 2, slabs thinner than a hair, dom.c) gave 0.33,
   * a map that counted nothing 0.59 */
  fprintf(stderr, "shadowed / alone %g, model n = 1 %g, n = 2 %g\n", s / a,
          m1 / m0, m2 / m0);
  assert_near(s / a, m1 / m0, 0.05);
  assert_true(s / a > m2 / m0 + 0.1);
  satf_image_destroy(alone);
  satf_image_destroy(shadowed);
}

/* Back-lit, a strand behind another (towards the light): the deep
 * opacity map counts the one hair in the way, not the lit strand itself.
 * Its slabs are at least one strand deep (dom.c); thinner ones, a third
 * of this scene's cluster radius (0.1, a twentieth of the strand), put the
 * map's four inside the first hair, so the lit strand counted the whole
 * column, itself too (n = 2: its pixels e^-1 of these). The pixels against
 * satf_fiber_dual_shade with n = 1 at each pixel's h. */
static void back_lit_strand_counts_only_the_hair_in_front(void **state) {
  const fixture *fx = *state;
  const float light[3] = {0.0f, -0.2f, 0.98f}; /* towards the camera */
  /* the blocker 2.5 strand widths behind, on the lit strand's ray to the
   * light and hidden behind it from the camera */
  const float x2[2] = {0.0f, 0.0f}, z2[2] = {0.0f, -5.0f};
  satf_image *img = render(fx, light, 2.0f, x2, z2, 2, 1);
  satf_fiber f;
  float tables[32 * SATF_FIBER_DUAL_FIELDS * 3];
  test_fiber(&f, tables, 32);
  const float rgb[3] = {2.0f, 1.8f, 1.6f};
  int row = H / 2, checked = 0;
  double half_px = 0.5 * WIDTH * px_per_unit(), got_sum = 0, one = 0, two = 0;
  for (int col = 0; col < W; col++) {
    double x = (col + 0.5 - 0.5 * W) / px_per_unit();
    if (fabs(x) * px_per_unit() > half_px - 1.0)
      continue;
    /* the frame of pixels_match_the_model: z towards the eye, y = -x */
    double lx = -light[0], ly = -light[1], lz = -light[2];
    double ll = sqrt(lx * lx + ly * ly + lz * lz);
    float wo[3] = {0.0f, 0.0f, 1.0f};
    float wi[3] = {(float)(ly / ll), (float)(-lx / ll), (float)(lz / ll)};
    float h = (float)(-x / (0.5 * WIDTH));
    float want1[3], want2[3];
    satf_fiber_dual_shade(&f, tables, 32, wo, wi, h, 1.0f, want1);
    satf_fiber_dual_shade(&f, tables, 32, wo, wi, h, 2.0f, want2);
    for (int c = 0; c < 3; c++) {
      float got = px(img, c == 0 ? "R" : c == 1 ? "G" : "B", col, row);
      got_sum += got;
      one += rgb[c] * want1[c];
      two += rgb[c] * want2[c];
    }
    checked++;
  }
  assert_true(checked >= 5);
  fprintf(stderr, "back-lit behind one strand: %g, model n = 1 %g, n = 2 %g\n",
          got_sum, one, two);
  assert_true(one > 1.5 * two);
  assert_near(got_sum, one, 0.05 * one);
  satf_image_destroy(img);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(pixels_match_the_model),
      cmocka_unit_test(thin_strand_averages_the_fibre),
      cmocka_unit_test(back_light_glows),
      cmocka_unit_test(shadowed_strand_keeps_forward_scattering),
      cmocka_unit_test(back_lit_strand_counts_only_the_hair_in_front),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
