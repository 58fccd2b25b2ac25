/* test_half_maps.c - the renderer keeps its maps as half floats (half.h):
 * the conversion rounds to nearest even with exact known
 * results, the F16C path and the portable one agree bit for bit, and the
 * renderer's texels are exactly the float maps (satf_maps_build_layer and
 * satf_maps_shadow_sums) rounded to halfs, so within 2^-11 of them
 * relatively: on the first frame, after the camera turns (every HSV looked
 * up again), after one instance moves, and when part of an instance is
 * looked up again (the rest's halfs are unpacked, kept and packed
 * again). */
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

#include "half.h"
#include "maps.h"
#include "render_fixture.h"
#include "renderer_internal.h"
#include "satf/render.h"

static float from_bits(uint32_t u) {
  float f;
  memcpy(&f, &u, sizeof f);
  return f;
}

/* Known binary16 encodings, rounding ties to even. */
static void test_known_values(void **state) {
  (void)state;
  const struct {
    float x;
    uint16_t h;
  } cases[] = {
      {0.0f, 0x0000},
      {-0.0f, 0x8000},
      {1.0f, 0x3C00},
      {-2.0f, 0xC000},
      {0.5f, 0x3800},
      {1.0f / 3.0f, 0x3555},
      {65504.0f, 0x7BFF},                 /* the largest half */
      {65519.0f, 0x7BFF},                 /* below the tie: rounds down */
      {65520.0f, 0x7C00},                 /* the tie: to even, infinity */
      {1e6f, 0x7C00},                     /* overflow: infinity */
      {-1e6f, 0xFC00},                    /* and its sign */
      {ldexpf(1.0f, -14), 0x0400},        /* the smallest normal */
      {ldexpf(1.0f, -24), 0x0001},        /* the smallest subnormal */
      {ldexpf(1.0f, -25), 0x0000},        /* half of it: tie to even, 0 */
      {ldexpf(3.0f, -26), 0x0001},        /* above the tie: up */
      {1.0f + ldexpf(1.0f, -11), 0x3C00}, /* tie between 0x3C00, 0x3C01 */
      {1.0f + ldexpf(3.0f, -11), 0x3C02}, /* tie between 0x3C01, 0x3C02 */
      {1.0f + ldexpf(1.0f, -10), 0x3C01}, /* exact */
      {(float)INFINITY, 0x7C00},
  };
  size_t n = sizeof cases / sizeof cases[0];
  for (size_t i = 0; i < n; i++) {
    uint16_t a, b;
    half_pack_portable(&cases[i].x, &a, 1);
    half_pack(&cases[i].x, &b, 1);
    if (a != cases[i].h || b != cases[i].h)
      fail_msg("%.9g: portable 0x%04X, dispatched 0x%04X, expected 0x%04X",
               (double)cases[i].x, a, b, cases[i].h);
    float back;
    half_unpack(&cases[i].h, &back, 1);
    /* every exactly representable case comes back as itself */
    if (cases[i].h == 0x3C00 || cases[i].h == 0x0400 || cases[i].h == 0x7BFF)
      assert_true(back == 1.0f || back == ldexpf(1.0f, -14) ||
                  back == 65504.0f);
  }
  float nan = (float)NAN;
  uint16_t h;
  half_pack(&nan, &h, 1);
  assert_true((h & 0x7C00) == 0x7C00 && (h & 0x03FF) != 0);
}

/* Both paths over many floats (every 4093rd bit pattern, a prime step, in
 * runs of 37 so the 8-wide F16C loop and its tail both run; every other
 * run through the streamed packer, half_stream_packer), and every half
 * back to float. */
static void test_paths_agree(void **state) {
  (void)state;
  enum { RUN = 37 };
  float x[RUN];
  uint16_t a[RUN], b[RUN];
  long checked = 0;
  for (uint64_t u = 0; u < 0x100000000ull; u += 4093ull * RUN) {
    for (int i = 0; i < RUN; i++)
      x[i] = from_bits((uint32_t)(u + 4093ull * (uint64_t)i));
    half_pack_portable(x, a, RUN);
    if (u % 2 == 0) {
      half_pack(x, b, RUN);
    } else { /* the streamed packer, to an aligned and a misaligned dst */
      _Alignas(16) uint16_t c[RUN + 1];
      half_pack_fn stream = half_stream_packer();
      stream(x, c, RUN);
      half_stream_end();
      memcpy(b, c, sizeof b);
      stream(x, c + 1, RUN);
      half_stream_end();
      assert_memory_equal(b, c + 1, sizeof b);
    }
    for (int i = 0; i < RUN; i++) {
      int nan_a = (a[i] & 0x7C00) == 0x7C00 && (a[i] & 0x03FF);
      int nan_b = (b[i] & 0x7C00) == 0x7C00 && (b[i] & 0x03FF);
      if (nan_a || nan_b) { /* NaN payloads may differ */
        assert_true(nan_a && nan_b && isnan(x[i]));
        continue;
      }
      if (a[i] != b[i])
        fail_msg("bits 0x%08X: portable 0x%04X, dispatched 0x%04X (%s)",
                 (unsigned)(u + 4093ull * (uint64_t)i), a[i], b[i],
                 u % 2 == 0 ? "half_pack" : "streamed");
      checked++;
    }
  }
  assert_true(checked > 1000000);
  uint16_t all[256];
  float fa[256], fb[256];
  for (unsigned hi = 0; hi < 256; hi++) {
    for (unsigned lo = 0; lo < 256; lo++)
      all[lo] = (uint16_t)(hi << 8 | lo);
    half_unpack_portable(all, fa, 256);
    half_unpack(all, fb, 256);
    for (int i = 0; i < 256; i++)
      assert_true(isnan(fa[i]) ? isnan(fb[i]) : fa[i] == fb[i]);
  }
}

#define W 96
#define H 72

FIXTURE_GL_GROUP(W, H)

/* Every instance's texels equal its float maps, built from scratch for
 * its current azimuths, rounded to halfs; returns the largest relative
 * difference (over values above 1e-3) between the two. With kept texels
 * (`kept`), the s-map sums (channel 2) add alphas that were rounded to
 * halfs when kept: within 2^-10 relatively (two roundings) plus two
 * subnormal steps (2^-24 each, for sums near 0), the other
 * channels still exact. */
static double assert_maps_are_rounded(const satf_renderer *r, int kept) {
  double worst = 0.0;
  for (int i = 0; i < r->ninsts; i++) {
    const inst *in = &r->insts[i];
    const satf_shell_geom *g = &in->geom;
    size_t layer = satf_maps_layer_texels(g, r->w) * 4;
    size_t n = layer * (size_t)g->shell.layers;
    float *f = malloc(n * sizeof *f), *back = malloc(n * sizeof *back);
    uint16_t *h = malloc(n * sizeof *h);
    assert_non_null(f);
    assert_non_null(back);
    assert_non_null(h);
    /* the options the renderer looks this instance up with (kk_layer) */
    satf_map_options opt = r->map_opt;
    opt.orientation_free &= r->protos[in->proto].from_strands;
    for (int k = 0; k < g->shell.layers; k++)
      satf_maps_build_layer(r->maps, g, in->angles, &opt, k,
                            f + (size_t)k * layer);
    satf_maps_shadow_sums(g, r->w, f);
    half_pack(f, h, n);
    half_unpack(in->texels, back, n);
    for (size_t x = 0; x < n; x++) {
      if (kept && x % 4 == 2) {
        if (fabs((double)back[x] - f[x]) >
            ldexp(fabs((double)f[x]), -10) + ldexp(1.0, -23))
          fail_msg("instance %d value %zu: s-map sum %.8g, float %.8g", i, x,
                   (double)back[x], (double)f[x]);
      } else if (h[x] != in->texels[x]) {
        fail_msg("instance %d value %zu: half 0x%04X, rounded float 0x%04X", i,
                 x, in->texels[x], h[x]);
      }
      if (fabsf(f[x]) > 1e-3f) {
        double d = fabs((double)back[x] - f[x]) / fabs((double)f[x]);
        worst = d > worst ? d : worst;
      }
    }
    free(f);
    free(back);
    free(h);
  }
  return worst;
}

static void test_renderer_maps_are_rounded_floats(void **state) {
  fixture_gl *f = *state;
  satf_scene *scene = fixture_scene(FIXTURE_TWO_PROTOTYPES);
  assert_non_null(scene);
  satf_renderer *r = fixture_renderer_cpu_maps(scene, f->db, W, H, 2);
  assert_non_null(r);
  assert_true(r->incremental);
  long all = fixture_render_lookups(r);
  assert_true(all > 0);
  double worst = assert_maps_are_rounded(r, 0);
  /* rounding to nearest: at most half a unit in the last of 11 bits */
  assert_true(worst > 0.0 && worst <= ldexp(1.0, -11));
  /* the camera turns: every HSV again */
  satf_renderer_camera(r)->position[0] += 0.7f;
  assert_true(fixture_render_lookups(r) > 0);
  assert_maps_are_rounded(r, 0);
  /* one instance moves: the others keep their halfs */
  satf_scene *next = fixture_scene(FIXTURE_TWO_PROTOTYPES);
  assert_non_null(next);
  next->macro_clusters[0].instances[1].m[3] += 0.25f;
  satf_error err;
  assert_int_equal(satf_renderer_set_scene(r, next, NULL, &err), SATF_OK);
  satf_renderer_camera(r)->position[0] += 0.7f;
  long some = fixture_render_lookups(r);
  assert_true(some > 0 && some < all);
  assert_maps_are_rounded(r, 0);
  /* part of an instance looked up again (its first rows of sectors
   * forgotten): the rest keep their texels, unpacked and packed again */
  inst *in = &r->insts[0]; /* the scratch holds insts[1]'s last maps */
  size_t ns = satf_shell_sector_count(&in->geom.shell);
  for (size_t q = 0; q < ns; q++)
    in->looked_up[q] = NAN; /* the first ns / 2 sectors' two azimuths */
  in->replaced = 1;
  long part = fixture_render_lookups(r);
  assert_true(part > 0 && part < all / 3);
  assert_maps_are_rounded(r, 1);
  satf_renderer_destroy(r);
  satf_scene_destroy(next);
  satf_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_known_values),
      cmocka_unit_test(test_paths_agree),
      cmocka_unit_test_setup_teardown(test_renderer_maps_are_rounded_floats,
                                      setup, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
