/* test_maps_gpu.c - the paper's maps built on the GPU (maps_gpu.h) are the
 * CPU's (maps.c, the reference): every texel of every drawn cluster's
 * textures, read back after a frame in each mode, within half-float
 * rounding per channel, and the frames alike (luminance SSIM >= 0.999),
 * for procedural clusters (several prototypes, instances and layers; the
 * samples of Fig. 6a and 7a) and for an imported curtain, whose records
 * take the orientation-free level; again after the eye and the light move
 * in the GPU mode (its instances built again), and after an instance
 * moves and a prototype bends. */
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

#include "metrics.h"
#include "render_fixture.h"
#include "renderer_internal.h"
#include "satf/import.h"
#include "satf/render.h"

#define W 96
#define H 72

FIXTURE_GL_GROUP(W, H)

/* Every texel of every drawn cluster's map textures (RGBA floats, the
 * prototypes' texture arrays in order); *n values. */
static float *read_maps(const satf_renderer *r, size_t *n) {
  size_t total = 0;
  for (int m = 0; m < r->nprotos; m++) {
    const proto *p = &r->protos[m];
    if (p->ready && !p->sparse)
      total += satf_maps_layer_texels(&p->geom, r->w) * 4 * (size_t)p->layers *
               (size_t)p->ninsts;
  }
  float *out = malloc((total > 0 ? total : 1) * sizeof *out);
  assert_non_null(out);
  float *at = out;
  for (int m = 0; m < r->nprotos; m++) {
    const proto *p = &r->protos[m];
    if (!p->ready || p->sparse)
      continue;
    size_t layer = satf_maps_layer_texels(&p->geom, r->w) * 4;
    for (int c = 0; c < p->nchunks; c++) {
      int insts = p->ninsts - c * p->chunk_insts;
      insts = insts < p->chunk_insts ? insts : p->chunk_insts;
      glBindTexture(GL_TEXTURE_2D_ARRAY, p->map_tex[c]);
      glGetTexImage(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA, GL_FLOAT, at);
      at += layer * (size_t)p->layers * (size_t)insts;
    }
  }
  glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
  assert_int_equal(glGetError(), GL_NO_ERROR);
  assert_true(at == out + total);
  *n = total;
  return out;
}

/* A half's rounding at |v|: 2^-11 relatively (two roundings of floats that
 * differ in their last bits: twice that), at least the subnormal step. */
static double half_step(double v) {
  return fmax(ldexp(fabs(v), -10), ldexp(1.0, -24));
}

/* The GPU's maps against the CPU's: each value within two of its half
 * steps plus the sums' drift, 1e-4 relatively (the GPU adds eq. 12's
 * alphas as the texture keeps them, halfs, as the CPU does for the texels
 * it keeps; the level's row sums run in another order), the reflectance
 * (channel 0, re / alpha) where alpha is above 1e-3 (below it a tiny
 * alpha's rounding moves the quotient). Except at most FLIPS of the values: the
 * last bit of the GPU's atan against the CPU's atan2f decides a row whose view
 * azimuth lies on the boundary of two of maps.c's resampling bins
 * (hair_7a: at 405.50006 bins; 160 of its 6.9 M values differ, by up to
 * 0.003 with the s-map sums under them) and an HSV whose eq. 6 distance
 * is the threshold (the imported curtain: 0.049998, one HSV uniform on
 * the GPU and not on the CPU, alpha 0.78 against 0.60 in a texel). A
 * map without the level's scaling or without eq. 6's uniform HSVs
 * differs in far more. Prints the largest difference per channel. */
#define FLIPS 2e-4
static void assert_maps_equal(const char *what, const float *cpu,
                              const float *gpu, size_t n) {
  double worst[4] = {0, 0, 0, 0};
  size_t bad = 0, first_bad = 0;
  for (size_t x = 0; x < n; x++) {
    int c = (int)(x % 4);
    if (c == 0 && cpu[x + 1] < 1e-3f && gpu[x + 1] < 1e-3f)
      continue;
    double d = fabs((double)gpu[x] - (double)cpu[x]);
    if (!(d <= 2.0 * half_step(cpu[x]) + 1e-4 * fabs((double)cpu[x])) && !bad++)
      first_bad = x;
    if (!(d <= worst[c]))
      worst[c] = d;
  }
  printf("%s: %zu values, %zu beyond half rounding; largest |GPU - CPU| "
         "per channel %.3g %.3g %.3g %.3g\n",
         what, n, bad, worst[0], worst[1], worst[2], worst[3]);
  if ((double)bad > FLIPS * (double)n)
    fail_msg("%s: %zu values differ beyond half rounding; first texel %zu "
             "channel %zu: GPU %.8g, CPU %.8g",
             what, bad, first_bad / 4, first_bad % 4, (double)gpu[first_bad],
             (double)cpu[first_bad]);
}

/* A frame in `mode` and its maps. */
static satf_image *frame(satf_renderer *r, satf_maps_mode mode, float **maps,
                         size_t *n) {
  satf_error err;
  if (satf_renderer_set_maps(r, mode, &err) != SATF_OK)
    fail_msg("%s", err.message);
  assert_int_equal(satf_renderer_maps(r), mode);
  satf_image *img = fixture_render_image(r);
  assert_non_null(img);
  *maps = read_maps(r, n);
  return img;
}

/* The frames and maps of r in both modes, `first` first, against each
 * other. */
static void assert_modes_agree(satf_renderer *r, const char *what,
                               satf_maps_mode first) {
  float *maps[2];
  size_t n[2];
  satf_image *img[2];
  img[first] = frame(r, first, &maps[first], &n[first]);

  satf_maps_mode other = first == SATF_MAPS_CPU ? SATF_MAPS_GPU : SATF_MAPS_CPU;
  img[other] = frame(r, other, &maps[other], &n[other]);
  assert_true(n[0] == n[1] && n[0] > 0);
  assert_maps_equal(what, maps[SATF_MAPS_CPU], maps[SATF_MAPS_GPU], n[0]);
  compare_image a = fixture_compare_image(img[SATF_MAPS_CPU], "cpu");
  compare_image b = fixture_compare_image(img[SATF_MAPS_GPU], "gpu");
  compare_result res;
  satf_error err;
  assert_int_equal(compare_measure(&a, &b, &res, &err), SATF_OK);
  printf("%s: frames' SSIM %.5f over %lld pixels\n", what, res.ssim,
         res.union_px);
  assert_true(res.union_px > 100);
  assert_true(res.ssim >= 0.999);
  for (int m = 0; m < 2; m++) {
    free(maps[m]);
    satf_image_destroy(img[m]);
  }
}

/* Both modes on `scene`; then the eye and the key light move while in the
 * GPU mode (which must build its instances again), compared with the
 * CPU's maps for them. Returns whether any prototype takes the
 * orientation-free level. */
static int check_scene(const satf_db *db, satf_scene *scene, const char *what) {
  assert_non_null(scene);
  satf_renderer *r = fixture_renderer(scene, db, W, H, 2);
  assert_non_null(r);
  satf_error err;
  /* every cluster drawn as a cluster, with maps */
  assert_int_equal(satf_renderer_set_sparse_strands(r, 0, &err), SATF_OK);
  assert_int_equal(satf_renderer_maps(r), SATF_MAPS_DEFAULT);
  assert_modes_agree(r, what, SATF_MAPS_CPU);
  satf_scene_camera *cam = satf_renderer_camera(r);
  /* 50 degrees around the target's vertical, the light 30 degrees */
  float d[3], c = cosf(0.87f), s = sinf(0.87f);
  for (int a = 0; a < 3; a++)
    d[a] = cam->position[a] - cam->target[a];
  cam->position[0] = cam->target[0] + c * d[0] + s * d[2];
  cam->position[2] = cam->target[2] - s * d[0] + c * d[2];
  satf_scene_light *l = satf_renderer_light(r, 0);
  c = cosf(0.52f), s = sinf(0.52f);
  float lx = l->direction[0], lz = l->direction[2];
  l->direction[0] = c * lx + s * lz;
  l->direction[2] = -s * lx + c * lz;
  char moved[160];
  snprintf(moved, sizeof moved, "%s, eye and light moved", what);
  assert_modes_agree(r, moved, SATF_MAPS_GPU);
  int free_level = 0;
  for (int m = 0; m < r->nprotos; m++)
    free_level |= r->protos[m].ready && r->protos[m].from_strands &&
                  r->map_opt.orientation_free;
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
  return free_level;
}

static void test_procedural(void **state) {
  fixture_gl *f = *state;
  assert_false(check_scene(f->db, fixture_scene(FIXTURE_TWO_PROTOTYPES),
                           "two prototypes"));
}

/* An animation step in the GPU mode: an instance moves and a prototype
 * bends (its frames rebuilt: the GPU's copy of them must follow). */
static void test_scene_change(void **state) {
  fixture_gl *f = *state;
  satf_scene *scene = fixture_scene(FIXTURE_TWO_PROTOTYPES);
  satf_scene *next = fixture_scene(FIXTURE_TWO_PROTOTYPES);
  assert_non_null(scene);
  assert_non_null(next);
  satf_renderer *r = fixture_renderer(scene, f->db, W, H, 2);
  assert_non_null(r);
  satf_error err;
  assert_int_equal(satf_renderer_set_maps(r, SATF_MAPS_GPU, &err), SATF_OK);
  satf_image *img = fixture_render_image(r);
  assert_non_null(img);
  satf_image_destroy(img);
  next->macro_clusters[0].instances[1].m[3] += 0.25f;
  next->macro_clusters[1].prototype.trajectory[0] += 0.4f;
  int rebuilt = 0;
  assert_int_equal(satf_renderer_set_scene(r, next, &rebuilt, &err), SATF_OK);
  assert_int_equal(rebuilt, 1);
  assert_modes_agree(r, "two prototypes, one moved, one bent", SATF_MAPS_GPU);
  satf_renderer_destroy(r);
  satf_scene_destroy(next);
  satf_scene_destroy(scene);
}

static void test_samples(void **state) {
  fixture_gl *f = *state;
  const char *names[] = {"cluster_6a.json", "hair_7a.json"};
  for (int i = 0; i < 2; i++) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", SATF_SAMPLES_DIR, names[i]);
    satf_scene *scene = NULL;
    satf_error err;
    if (satf_scene_load(path, &scene, &err) != SATF_OK)
      fail_msg("%s", err.message);
    check_scene(f->db, scene, names[i]);
  }
}

/* A little-endian cyHair file of a curtain: `strands` straight strands of
 * `points` points hanging from a band, a little wavy. */
static void write_curtain(const char *path, int strands, int points) {
  FILE *fp = fopen(path, "wb");
  assert_non_null(fp);
  unsigned char head[128] = {'H', 'A', 'I', 'R'};
  uint32_t u[4] = {(uint32_t)strands, (uint32_t)(strands * points), 2u,
                   (uint32_t)(points - 1)};
  float thickness = 0.1f;
  memcpy(head + 4, u, sizeof u);
  memcpy(head + 20, &thickness, sizeof thickness);
  assert_int_equal(fwrite(head, 1, sizeof head, fp), sizeof head);
  for (int s = 0; s < strands; s++)
    for (int i = 0; i < points; i++) {
      float t = (float)i / (float)(points - 1);
      float x = -6.0f + 12.0f * (float)s / (float)(strands - 1);
      float p[3] = {x + 0.3f * sinf(3.0f * t + 0.37f * (float)s),
                    20.0f - 30.0f * t,
                    0.5f * sinf(0.71f * (float)s) + 1.5f * t * t};
      assert_int_equal(fwrite(p, sizeof(float), 3, fp), 3);
    }
  assert_int_equal(fclose(fp), 0);
}

static void test_imported(void **state) {
  fixture_gl *f = *state;
  char hair[1024], json[1024];
  snprintf(hair, sizeof hair, "%s/maps_gpu_curtain.hair", SATF_TEST_OUT_DIR);
  snprintf(json, sizeof json, "%s/maps_gpu_curtain.json", SATF_TEST_OUT_DIR);
  write_curtain(hair, 240, 12);
  satf_import_options o = satf_import_options_default();
  o.inputs[0] = hair;
  o.n_inputs = 1;
  o.output = json;
  o.quiet = 1;
  o.threads = 2;
  o.no_strands = 1;
  satf_import_result res;
  satf_error err;
  if (satf_import_run(&o, &res, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_scene *scene = NULL;
  if (satf_scene_load(json, &scene, &err) != SATF_OK)
    fail_msg("%s", err.message);
  assert_true(check_scene(f->db, scene, "imported curtain"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_procedural),
      cmocka_unit_test(test_scene_change),
      cmocka_unit_test(test_samples),
      cmocka_unit_test(test_imported),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
