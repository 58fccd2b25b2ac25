/* test_physical.c - the physical shading mode of the cluster path
 * (online/render/maps_fiber.c, glsl/shade_fs.glsl with PHYSICAL): the
 * hair's colour follows its melanin, back-lit hair glows with transmitted
 * light, an absorption-free fibre is neutral, every light adds its own
 * look-ups, a cluster's root row is not darkened, and a Phong database is
 * refused. */
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
#include "satf/common.h"
#include "satf/render.h"
#include "test_util.h"

#define W 120
#define H 120

FIXTURE_FIBER_GROUP(W, H)

/* One straight vertical cluster seen from +z, under `lights` (JSON), with
 * the material's fibre `material` (JSON keys); shadows 1: cluster shadows
 * and self-shadowing, 2: self-shadowing alone, 0: neither. */
static void scene_json(char *buf, size_t size, const char *material,
                       const char *lights, int shadows) {
  snprintf(buf, size,
           "{\"macro_clusters\": [{\"prototype\": {"
           "  \"trajectory\": [[0, -2, 0], [0, 2, 0]], \"a\": 1.0,"
           "  \"shell\": {\"layers\": 4, \"st\": 8, \"su\": 10},"
           "  \"density\": {\"strands\": 500, \"seed\": 2,"
           "               \"strand_width\": 0.05}}}],"
           " \"camera\": {\"position\": [0, 0, 9], \"target\": [0, 0, 0],"
           "              \"fov_y\": 40},"
           " \"lights\": [%s],"
           " \"material\": {\"model\": \"physical\"%s%s},"
           " \"effects\": {\"cluster_shadows\": %s, \"self_shadow\": %s},"
           " \"image\": {\"width\": %d, \"height\": %d}}",
           lights, material[0] ? ", " : "", material,
           shadows == 1 ? "true" : "false", shadows ? "true" : "false", W, H);
}

/* A renderer of `json`'s scene (*s, to destroy after it) on database db:
 * the status of satf_renderer_create, with *r and err->message. */
static satf_status make_renderer(const char *json, const satf_db *db,
                                 satf_scene **s, satf_renderer **r,
                                 satf_error *err) {
  *s = fixture_scene(json);
  assert_non_null(*s);
  *r = NULL;
  return satf_renderer_create(*s, db, W, H, 0, r, err);
}

/* Renders `json`; secondary 0 switches Fig. 4b's effect off. */
static satf_image *render_fx(const char *json, int secondary) {
  satf_scene *s;
  satf_renderer *r;
  satf_error err;
  if (make_renderer(json, fiber_db, &s, &r, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_renderer_effects(r)->secondary_highlight = secondary;
  satf_image *img = NULL;
  satf_frame_timing t;
  if (satf_renderer_render_image(r, 0, &img, &t, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_renderer_destroy(r);
  satf_scene_destroy(s);
  return img;
}

static satf_image *render(const char *json) { return render_fx(json, 1); }

/* Mean R, G, B (premultiplied) over the pixels the hair covers (A > 0.5),
 * and their count. */
static int mean_rgb(const satf_image *img, double rgb[3]) {
  const char *ch[3] = {"R", "G", "B"};
  const float *A = fixture_plane(img, "A");
  int n = 0;
  rgb[0] = rgb[1] = rgb[2] = 0.0;
  for (int c = 0; c < 3; c++) {
    const float *P = fixture_plane(img, ch[c]);
    for (int i = 0; i < W * H; i++)
      if (A[i] > 0.5f) {
        rgb[c] += P[i];
        n += c == 0;
      }
  }
  for (int c = 0; c < 3; c++)
    rgb[c] /= n > 0 ? n : 1;
  return n;
}

static double luminance(const double rgb[3]) {
  return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

static const char *const FRONT =
    "{\"direction\": [-0.3, -0.4, -0.87], \"intensity\": 3}";

/* Blond (melanin 0.2) is brighter than dark brown (0.8); brown hair is
 * red over green over blue, as eumelanin absorbs blue most (Cycles'
 * cross-sections, satf/fiber.h). */
static void test_colour_follows_melanin(void **state) {
  (void)state;
  char json[2048];
  double blond[3], dark[3];
  scene_json(json, sizeof json, "\"melanin\": 0.2", FRONT, 1);
  satf_image *a = render(json);
  scene_json(json, sizeof json, "\"melanin\": 0.8", FRONT, 1);
  satf_image *b = render(json);
  int na = mean_rgb(a, blond), nb = mean_rgb(b, dark);
  printf("blond %.4f %.4f %.4f (%d px), dark %.4f %.4f %.4f (%d px)\n",
         blond[0], blond[1], blond[2], na, dark[0], dark[1], dark[2], nb);
  assert_true(na > 500 && abs(na - nb) < na / 10);
  assert_true(luminance(blond) > 1.5 * luminance(dark));
  assert_true(dark[0] > dark[1] && dark[1] > dark[2]);
  assert_true(blond[0] > blond[1] && blond[1] > blond[2]);
  satf_image_destroy(a);
  satf_image_destroy(b);
}

/* Light from behind the hair towards the camera reaches the eye through
 * the fibres (TT): a back-lit blond cluster glows, coloured by the
 * absorption on the way through. */
static void test_back_lit_glow(void **state) {
  (void)state;
  char json[2048];
  double front[3], back[3];
  scene_json(json, sizeof json, "\"melanin\": 0.2", FRONT, 0);
  satf_image *a = render(json);
  scene_json(json, sizeof json, "\"melanin\": 0.2",
             "{\"direction\": [0.1, -0.2, 0.97], \"intensity\": 3}", 0);
  satf_image *b = render(json);
  mean_rgb(a, front);
  mean_rgb(b, back);
  printf("front-lit %.4f, back-lit %.4f (R/B %.2f)\n", luminance(front),
         luminance(back), back[0] / fmax(back[2], 1e-9));
  assert_true(luminance(back) > 0.15 * luminance(front));
  assert_true(back[0] > 1.3 * back[2]);
  satf_image_destroy(a);
  satf_image_destroy(b);
}

/* A cluster lit from behind is shadowed by its own hair between the light
 * and the layers the eye sees first (shade_fs.glsl: through_count), not
 * only by the layers outside them, which are the same from either side:
 * what its self-shadowing keeps of the light is far less from behind
 * than from the front. */
static void test_back_lit_own_shadow(void **state) {
  (void)state;
  const char *const lights[2] = {
      FRONT, "{\"direction\": [0.3, -0.4, 0.87], \"intensity\": 3}"};
  double kept[2];
  for (int i = 0; i < 2; i++) {
    char json[2048];
    double on[3], off[3];
    scene_json(json, sizeof json, "\"melanin\": 0.2", lights[i], 2);
    satf_image *a = render(json);
    scene_json(json, sizeof json, "\"melanin\": 0.2", lights[i], 0);
    satf_image *b = render(json);
    mean_rgb(a, on);
    mean_rgb(b, off);
    kept[i] = luminance(on) / fmax(luminance(off), 1e-9);
    satf_image_destroy(a);
    satf_image_destroy(b);
  }
  printf("self-shadowing keeps %.3f of the light from the front, %.3f from "
         "behind\n",
         kept[0], kept[1]);
  assert_true(kept[0] > 0.3);
  assert_true(kept[1] < 0.6 * kept[0]);
}

/* A fibre that absorbs nothing under white light is white: every channel
 * of every covered pixel equal within half-float rounding. */
static void test_clear_fibre_is_neutral(void **state) {
  (void)state;
  char json[2048];
  scene_json(json, sizeof json, "\"absorption\": [0, 0, 0]", FRONT, 1);
  satf_image *img = render(json);
  double rgb[3];
  assert_true(mean_rgb(img, rgb) > 500);
  printf("clear fibre %.5f %.5f %.5f\n", rgb[0], rgb[1], rgb[2]);
  assert_true(luminance(rgb) > 0.01);
  assert_near(rgb[0], rgb[1], 2e-3 * rgb[1]);
  assert_near(rgb[2], rgb[1], 2e-3 * rgb[1]);
  satf_image_destroy(img);
}

/* Every light gets its own look-ups: without shadows (which only the key
 * light casts) two lights give the sum of each alone, each in its own role
 * (the other one dark: the fill light's look-ups take the nearest sample
 * only, maps_fiber.c). */
static void test_lights_add(void **state) {
  (void)state;
  const char *l1 = "{\"direction\": [-0.3, -0.4, -0.87], \"intensity\": %g}";
  const char *l2 = "{\"direction\": [0.7, 0.1, -0.7], \"intensity\": %g,"
                   " \"color\": [0.6, 0.8, 1]}";
  char json[2048], fmt[512], lights[512];
  snprintf(fmt, sizeof fmt, "%s, %s", l1, l2);
  snprintf(lights, sizeof lights, fmt, 2.0, 0.0);
  scene_json(json, sizeof json, "", lights, 0);
  satf_image *a = render(json);
  snprintf(lights, sizeof lights, fmt, 0.0, 1.5);
  scene_json(json, sizeof json, "", lights, 0);
  satf_image *b = render(json);
  snprintf(lights, sizeof lights, fmt, 2.0, 1.5);
  scene_json(json, sizeof json, "", lights, 0);
  satf_image *ab = render(json);
  const char *ch[3] = {"R", "G", "B"};
  double worst = 0.0, peak = 0.0, fill = 0.0;
  for (int c = 0; c < 3; c++) {
    const float *pa = fixture_plane(a, ch[c]), *pb = fixture_plane(b, ch[c]);
    const float *pab = fixture_plane(ab, ch[c]);
    for (int i = 0; i < W * H; i++) {
      worst = fmax(worst, fabs(pab[i] - pa[i] - pb[i]));
      peak = fmax(peak, pab[i]);
      fill = fmax(fill, pb[i]);
    }
  }
  printf("two lights: max |AB - A - B| %.5f of a peak %.4f\n", worst, peak);
  assert_true(peak > 0.01);
  assert_true(fill > 0.2 * peak); /* the fill light does light the hair */
  assert_true(worst < 0.01 * peak);
  satf_image_destroy(a);
  satf_image_destroy(b);
  satf_image_destroy(ab);
}

/* A probe cluster of `strands` strands at the origin and, where
 * `occluder`, a dense one at x = 6 (out of the camera's view), lit by a
 * key light from the camera's side with intensity `key` and by a light
 * from +x with intensity `side`, the key first where `key_first`. */
static void probe_json(char *buf, size_t size, int strands, int occluder,
                       double key, double side, int key_first) {
  char k[128], f[128];
  snprintf(k, sizeof k,
           "{\"direction\": [-0.3, -0.4, -0.87], \"intensity\": %g}", key);
  snprintf(f, sizeof f,
           "{\"direction\": [-1, 0, 0], \"intensity\": %g,"
           " \"color\": [0.7, 0.8, 1]}",
           side);
  snprintf(buf, size,
           "{\"macro_clusters\": [{\"prototype\": {"
           "  \"trajectory\": [[0, -2, 0], [0, 2, 0]], \"a\": 1.0,"
           "  \"shell\": {\"layers\": 4, \"st\": 8, \"su\": 10},"
           "  \"density\": {\"strands\": %d, \"seed\": 2,"
           "               \"strand_width\": 0.05}}}%s],"
           " \"camera\": {\"position\": [0, 0, 9], \"target\": [0, 0, 0],"
           "              \"fov_y\": 40},"
           " \"lights\": [%s, %s],"
           " \"material\": {\"model\": \"physical\"},"
           " \"image\": {\"width\": %d, \"height\": %d}}",
           strands,
           occluder ? ", {\"prototype\": {"
                      "  \"trajectory\": [[6, -2.5, 0], [6, 2.5, 0]],"
                      "  \"a\": 1.6,"
                      "  \"shell\": {\"layers\": 4, \"st\": 8, \"su\": 10},"
                      "  \"density\": {\"strands\": 3000, \"seed\": 3,"
                      "               \"strand_width\": 0.08}}}"
                    : "",
           key_first ? k : f, key_first ? f : k, W, H);
}

static double probe_luminance(int strands, int occluder, double key,
                              double side, int key_first) {
  char json[4096];
  double rgb[3];
  probe_json(json, sizeof json, strands, occluder, key, side, key_first);
  satf_image *img = render(json);
  assert_true(mean_rgb(img, rgb) > 100);
  satf_image_destroy(img);
  return luminance(rgb);
}

/* Every light casts the hair's shadows, as in Cycles, not only the key:
 * the fill light's own deep opacity map. A dense cluster between the
 * fill light and a probe takes most of the fill's light from it, and the
 * two lights in either order light the probe alike. Both drawings: the
 * probe as shells (500 strands) and as its strands (12, drawn as strands:
 * strand_fs.glsl). */
static void test_fill_light_shadowed(void **state) {
  (void)state;
  const int probes[2] = {500, 6};
  for (int p = 0; p < 2; p++) {
    int n = probes[p];
    double open = probe_luminance(n, 0, 2.0, 1.5, 1);
    double shut = probe_luminance(n, 1, 2.0, 1.5, 1);
    double key = probe_luminance(n, 1, 2.0, 0.0, 1);
    double swapped_open = probe_luminance(n, 0, 2.0, 1.5, 0);
    double swapped = probe_luminance(n, 1, 2.0, 1.5, 0);
    printf("probe of %d strands: key and fill %.4f, fill behind the "
           "cluster %.4f, key alone %.4f; the lights swapped %.4f, "
           "behind the cluster %.4f\n",
           n, open, shut, key, swapped_open, swapped);
    assert_true(open > 1.1 * key); /* the fill lights the open probe */
    /* most of the fill's light is gone behind the cluster */
    assert_true(open - shut > 0.6 * (open - key));
    /* and about as much as when the same light is the key (0.33 and
     * 0.46 of the open probe's: the key's records are blended, the
     * fill's the nearest sample's, which on this coarse database differ
     * by up to 26%, on the default one by 3-6%; with the fill unshadowed
     * the first is 1) */
    assert_true(fabs(swapped / swapped_open - shut / open) < 0.2);
  }
}

/* Fig. 4b in the physical mode: the secondary highlight is the TRT lobe
 * (Marschner 2003), coloured by two passes through the fibre; without it
 * the hair is darker and less red. */
static void test_no_secondary_drops_trt(void **state) {
  (void)state;
  char json[2048];
  scene_json(json, sizeof json, "\"melanin\": 0.3",
             "{\"direction\": [0, -0.6, -0.8], \"intensity\": 3}", 0);
  satf_image *a = render_fx(json, 1), *b = render_fx(json, 0);
  double with[3], without[3];
  mean_rgb(a, with);
  mean_rgb(b, without);
  printf("with TRT %.4f (R/B %.2f), without %.4f (R/B %.2f)\n", luminance(with),
         with[0] / with[2], luminance(without), without[0] / without[2]);
  assert_true(luminance(without) < 0.97 * luminance(with));
  assert_true(without[0] / without[2] < with[0] / with[2]);
  satf_image_destroy(a);
  satf_image_destroy(b);
}

/* Look-ups proportional to change in the physical mode: a second frame
 * with nothing moved looks nothing up and gives the same image; a light's
 * colour or the TRT switch changing looks everything up again, as a fresh
 * renderer would. */
static void test_still_frames(void **state) {
  (void)state;
  char json[2048];
  scene_json(json, sizeof json, "", FRONT, 1);
  satf_scene *s;
  satf_renderer *r;
  satf_error err;
  assert_int_equal(make_renderer(json, fiber_db, &s, &r, &err), SATF_OK);
  satf_image *a = NULL, *b = NULL, *c = NULL;
  satf_frame_timing t1, t2, t3, t4;
  assert_int_equal(satf_renderer_render_image(r, 0, &a, &t1, &err), SATF_OK);
  assert_int_equal(satf_renderer_render_image(r, 0, &b, &t2, &err), SATF_OK);
  assert_true(t1.lookups > 0);
  assert_int_equal(t2.lookups, 0);
  assert_true(fixture_same_bits(a, b, "R") && fixture_same_bits(a, b, "B"));
  satf_renderer_effects(r)->secondary_highlight = 0;
  assert_int_equal(satf_renderer_render_image(r, 0, &c, &t3, &err), SATF_OK);
  assert_int_equal(t3.lookups, t1.lookups);
  assert_false(fixture_same_bits(a, c, "R"));
  satf_renderer_effects(r)->secondary_highlight = 1;
  satf_scene_light *l = satf_renderer_light(r, 0);
  assert_non_null(l);
  l->color[2] = 0.5f;
  satf_image_destroy(c);
  c = NULL;
  assert_int_equal(satf_renderer_render_image(r, 0, &c, &t4, &err), SATF_OK);
  assert_int_equal(t4.lookups, t1.lookups);
  printf("still frames: %ld look-ups, then %ld, %ld, %ld\n", (long)t1.lookups,
         (long)t2.lookups, (long)t3.lookups, (long)t4.lookups);
  satf_image_destroy(a);
  satf_image_destroy(b);
  satf_image_destroy(c);
  satf_renderer_destroy(r);
  satf_scene_destroy(s);
}

/* The physical maps' layout (maps_fiber.h), built as halfs in one pass
 * from the outer layer in: a texel is a key quad and a fill quad, the
 * fill's channel 3 the sum of the key quads' alpha over the layers outside
 * k (eq. 12), 0 for the outer one; HSV i's top row and HSV i - 1's bottom
 * row, one boundary, are the same texels in every layer. Three threads: the one
 * cluster is built in three parts (cluster_cpu.c), of 3, 3 and 4 columns of
 * HSVs, the same maps as one thread's. */
static void test_layout_sums(void **state) {
  (void)state;
  char json[2048], lights[512];
  snprintf(lights, sizeof lights,
           "%s, {\"direction\": [0.7, 0.1, -0.7], \"intensity\": 1}", FRONT);
  scene_json(json, sizeof json, "", lights, 1);
  satf_scene *s = fixture_scene(json);
  assert_non_null(s);
  satf_renderer *r, *one;
  satf_error err;
  assert_int_equal(satf_renderer_create(s, fiber_db, W, H, 3, &r, &err),
                   SATF_OK);
  assert_int_equal(satf_renderer_create(s, fiber_db, W, H, 1, &one, &err),
                   SATF_OK);
  /* the CPU's copy of the maps is read below */
  assert_int_equal(satf_renderer_set_maps(r, SATF_MAPS_CPU, &err), SATF_OK);
  assert_int_equal(satf_renderer_set_maps(one, SATF_MAPS_CPU, &err), SATF_OK);
  satf_image *img = NULL, *img1 = NULL;
  satf_frame_timing t;
  assert_int_equal(satf_renderer_render_image(r, 0, &img, &t, &err), SATF_OK);
  assert_int_equal(satf_renderer_render_image(one, 0, &img1, &t, &err),
                   SATF_OK);
  const inst *in = &r->insts[0];
  const satf_shell_params *sh = &in->geom.shell;
  assert_int_equal(r->quads, 2);
  size_t n = satf_maps_layer_texels(&in->geom, r->w), slice = 8 * n;
  size_t all = slice * (size_t)sh->layers;
  size_t row = (size_t)sh->su * (size_t)r->w * 8;
  float *v = malloc(all * sizeof *v);
  assert_non_null(v);
  half_unpack(in->texels, v, all);
  double deepest = 0.0;
  for (int k = 0; k < sh->layers; k++) {
    const float *texel = v + (size_t)k * slice;
    for (size_t x = 0; x < n; x++) {
      double sum = 0.0; /* of halfs, which the float sums were rounded to */
      for (int m = k + 1; m < sh->layers; m++)
        sum += v[(size_t)m * slice + 8 * x + 3];
      if (fabs(texel[8 * x + 7] - sum) > ldexp(sum, -9) + ldexp(1.0, -20))
        fail_msg("layer %d texel %zu: s-map sum %.6g, outer alphas %.6g", k, x,
                 (double)texel[8 * x + 7], sum);
      deepest = fmax(deepest, sum);
    }
  }
  for (int k = 0; k < sh->layers; k++)
    for (int i = 1; i < sh->st; i++) {
      const uint16_t *a = in->texels + (size_t)k * slice;
      if (memcmp(a + (size_t)(2 * i - 1) * row, a + (size_t)(2 * i) * row,
                 row * sizeof *a) != 0)
        fail_msg("layer %d: rows %d and %d differ", k, 2 * i - 1, 2 * i);
    }
  printf("s-map sums up to %.3f over %d layers\n", deepest, sh->layers);
  assert_true(deepest > 0.5);
  assert_memory_equal(in->texels, one->insts[0].texels, all * sizeof(uint16_t));
  free(v);
  satf_image_destroy(img);
  satf_image_destroy(img1);
  satf_renderer_destroy(r);
  satf_renderer_destroy(one);
  satf_scene_destroy(s);
}

/* The maps of three lights, a directional key, a directional and a point
 * fill (maps_fiber.c: the first fill light stores its radiance, further
 * ones add theirs; directional lights' directions are found once per
 * column of layers, a point light's per sector): the key quads are those
 * of the key light alone, bit for bit, and each fill quad's colour is the
 * sum of the two fills' (within the halfs' rounding), the point light's
 * share not zero. */
static const inst *maps_of(const char *lights, satf_scene **s,
                           satf_renderer **r) {
  char json[2048];
  scene_json(json, sizeof json, "", lights, 1);
  *s = fixture_scene(json);
  assert_non_null(*s);
  satf_error err;
  assert_int_equal(satf_renderer_create(*s, fiber_db, W, H, 1, r, &err),
                   SATF_OK);
  /* the CPU's copy of the maps is read */
  assert_int_equal(satf_renderer_set_maps(*r, SATF_MAPS_CPU, &err), SATF_OK);
  satf_image *img = NULL;
  satf_frame_timing t;
  assert_int_equal(satf_renderer_render_image(*r, 0, &img, &t, &err), SATF_OK);
  satf_image_destroy(img);
  return &(*r)->insts[0];
}

static void test_fill_lights_sum(void **state) {
  (void)state;
  const char *dir = "{\"direction\": [0.7, 0.1, -0.7], \"intensity\": 1}";
  const char *point = "{\"type\": \"point\", \"position\": [-3, 1, 4],"
                      " \"intensity\": 20, \"color\": [1, 0.7, 0.5]}";
  char l_dir[512], l_point[512], l_all[1024];
  snprintf(l_dir, sizeof l_dir, "%s, %s", FRONT, dir);
  snprintf(l_point, sizeof l_point, "%s, %s", FRONT, point);
  snprintf(l_all, sizeof l_all, "%s, %s, %s", FRONT, dir, point);
  satf_scene *sa, *sb, *sc;
  satf_renderer *ra, *rb, *rc;
  const inst *a = maps_of(l_dir, &sa, &ra), *b = maps_of(l_point, &sb, &rb);
  const inst *c = maps_of(l_all, &sc, &rc);
  const satf_shell_params *sh = &a->geom.shell;
  size_t n = satf_maps_layer_texels(&a->geom, ra->w) * (size_t)sh->layers;
  size_t all = 8 * n;
  float *va = malloc(3 * all * sizeof *va), *vb = va + all, *vc = vb + all;
  assert_non_null(va);
  half_unpack(a->texels, va, all);
  half_unpack(b->texels, vb, all);
  half_unpack(c->texels, vc, all);
  double worst = 0.0, point_share = 0.0, fill_peak = 0.0;
  for (size_t t = 0; t < n; t++) {
    size_t key = 8 * t, fill = key + 4;
    assert_memory_equal(a->texels + key, c->texels + key, 4 * sizeof(uint16_t));
    assert_memory_equal(b->texels + key, c->texels + key, 4 * sizeof(uint16_t));
    for (size_t x = 0; x < 3; x++) { /* 3: the s-map sum, of the key's alpha */
      double fa = va[fill + x], fb = vb[fill + x], fc = vc[fill + x];
      double err = fabs(fc - fa - fb) /
                   (ldexp(fabs(fa) + fabs(fb), -10) + ldexp(1.5, -24));
      worst = fmax(worst, err);
      point_share = fmax(point_share, fb);
      fill_peak = fmax(fill_peak, fc);
    }
  }
  printf("three lights: fill quads within %.2f of the halfs' rounding of "
         "the fills' sum; point fill up to %.4f of %.4f\n",
         worst, point_share, fill_peak);
  assert_true(worst <= 1.0);
  assert_true(point_share > 0.05 * fill_peak);
  free(va);
  satf_renderer_destroy(ra);
  satf_renderer_destroy(rb);
  satf_renderer_destroy(rc);
  satf_scene_destroy(sa);
  satf_scene_destroy(sb);
  satf_scene_destroy(sc);
}

/* The key light's level (green radiance per unit coverage) of each
 * column of HSVs of the outer layer of `in`'s maps into level[su]: 0 for
 * a column without coverage. */
static void column_levels(const satf_renderer *r, const inst *in,
                          double *level) {
  const satf_shell_params *sh = &in->geom.shell;
  size_t n = satf_maps_layer_texels(&in->geom, r->w), slice = 8 * n;
  float *v = malloc(slice * sizeof *v);
  assert_non_null(v);
  half_unpack(in->texels + (size_t)(sh->layers - 1) * slice, v, slice);
  for (int j = 0; j < sh->su; j++) {
    double ga = 0.0, a = 0.0;
    for (int row = 0; row < 2 * sh->st; row++)
      for (int x = 0; x < r->w; x++) {
        const float *t = v + 8 * (((size_t)row * sh->su + j) * r->w + x);
        ga += (double)t[1] * t[3];
        a += t[3];
      }
    level[j] = a > 1e-3 * 2 * sh->st * r->w ? ga / a : 0.0;
  }
  free(v);
}

/* The spread (highest over lowest) of the outer layer's column levels of
 * the one cluster, its sectors all of one feature vector, looked up with
 * orientation-free records (its density taken as its strands', as an
 * imported cluster's) or without. */
static double level_spread(int from_strands) {
  char json[2048];
  scene_json(json, sizeof json, "", FRONT, 0);
  /* from far off (the same view): every sector sees the eye and the light
   * at one difference of azimuths, which the perspective of the eye at 9
   * would turn by up to 6 degrees */
  const char *near = "[0, 0, 9], \"target\": [0, 0, 0],"
                     "              \"fov_y\": 40";
  const char *cam = strstr(json, near);
  assert_non_null(cam);
  char far[2048];
  snprintf(far, sizeof far,
           "%.*s[0, 0, 900], \"target\": [0, 0, 0], "
           "\"fov_y\": 0.4%s",
           (int)(cam - json), json, cam + strlen(near));
  memcpy(json, far, sizeof json);
  satf_scene *s = fixture_scene(json);
  assert_non_null(s);
  satf_renderer *r;
  satf_error err;
  assert_int_equal(satf_renderer_create(s, fiber_db, W, H, 1, &r, &err),
                   SATF_OK);
  assert_int_equal(satf_renderer_set_maps(r, SATF_MAPS_CPU, &err), SATF_OK);
  inst *in = &r->insts[0];
  size_t q = satf_shell_sector_count(&in->geom.shell);
  for (size_t i = 0; i < q; i++) /* the first sector's, and no cached */
    memcpy(in->geom.features + 3 * i, in->geom.features, 3 * sizeof(float));
  in->geom.neighbors = NULL; /* neighbours: looked up from the features */
  r->protos[in->proto].from_strands = from_strands;
  satf_image *img = NULL;
  satf_frame_timing t;
  assert_int_equal(satf_renderer_render_image(r, 0, &img, &t, &err), SATF_OK);
  double *level = malloc((size_t)in->geom.shell.su * sizeof *level);
  assert_non_null(level);
  column_levels(r, in, level);
  double lo = INFINITY, hi = 0.0;
  int seen = 0;
  for (int j = 0; j < in->geom.shell.su; j++)
    if (level[j] > 0.0) {
      lo = fmin(lo, level[j]);
      hi = fmax(hi, level[j]);
      seen++;
    }
  assert_true(seen >= in->geom.shell.su / 2);
  free(level);
  satf_image_destroy(img);
  satf_renderer_destroy(r);
  satf_scene_destroy(s);
  return hi / lo;
}

/* Orientation-free records in the physical maps (maps_fiber.c,
 * satf_map_options.orientation_free): as a sector turns round a straight
 * cluster its view and light azimuths turn together, so one feature
 * vector gives every column of HSVs one level, where the records' own
 * levels (a cluster of procedural density) shade it as a cylinder. */
static void test_orientation_free_level(void **state) {
  (void)state;
  double own = level_spread(0), free_ = level_spread(1);
  printf("column levels over the circumference: highest / lowest %.3f, "
         "orientation-free %.3f\n",
         own, free_);
  assert_true(own > 1.2);
  assert_true(free_ < 1.01);
}

/* The physical maps' first HSV row of a cluster whose strands start after
 * its first slice: SATF eq. 7 mixes the boundary records' radiance per
 * unit alpha weighted by their alpha, so the row thins out towards t = 0
 * without darkening (as test_render's kk frame). */
static void test_root_row_not_darkened(void **state) {
  (void)state;
  char *json = fixture_rooted_tracks_json("{\"model\": \"physical\"}");
  assert_non_null(json);
  satf_image *img = render(json);
  free(json);
  double ratio = fixture_root_rows_ratio(img);
  printf("root rows: luminance per unit alpha %.3f of the body's\n", ratio);
  /* 0.87 measured; 0.22 mixed as stored */
  assert_true(ratio > 0.75);
  satf_image_destroy(img);
}

/* A physical scene with a Phong database: refused with a message that
 * says what is needed. */
static void test_phong_database_refused(void **state) {
  (void)state;
  char json[2048];
  scene_json(json, sizeof json, "", FRONT, 1);
  satf_scene *s;
  satf_renderer *r;
  satf_error err;
  assert_int_equal(make_renderer(json, gl->db, &s, &r, &err),
                   SATF_ERR_INCOMPATIBLE);
  assert_null(r);
  assert_non_null(strstr(err.message, "fibre database"));
  satf_scene_destroy(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_colour_follows_melanin),
      cmocka_unit_test(test_back_lit_glow),
      cmocka_unit_test(test_back_lit_own_shadow),
      cmocka_unit_test(test_clear_fibre_is_neutral),
      cmocka_unit_test(test_lights_add),
      cmocka_unit_test(test_fill_light_shadowed),
      cmocka_unit_test(test_no_secondary_drops_trt),
      cmocka_unit_test(test_still_frames),
      cmocka_unit_test(test_root_row_not_darkened),
      cmocka_unit_test(test_phong_database_refused),
      cmocka_unit_test(test_layout_sums),
      cmocka_unit_test(test_fill_lights_sum),
      cmocka_unit_test(test_orientation_free_level),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
