/* test_maps_gpu.c - the maps built on the GPU (maps_gpu.h) are the CPU's
 * (maps.c and, in the physical mode, maps_fiber.c: the reference): every
 * texel of every drawn cluster's textures, read back after a frame in each
 * mode, within half-float rounding per channel (all 8 halfs of a physical
 * texel), and the frames alike (luminance SSIM >= 0.999), for procedural
 * clusters (several prototypes, instances and layers; the samples of Fig.
 * 6a and 7a) and for an imported curtain, whose records take the
 * orientation-free level and whose physical maps the directions of its
 * wavy strands (satf_shell_geom.hair), straight and curly; again after the
 * eye and the light move in the GPU mode (its instances built again), and
 * after an instance moves and a prototype bends. The physical mode's run on
 * a small fibre database, under a directional key light and a coloured
 * point light. The default mode, SATF_MAPS_AUTO, resolves by the context. */
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
#include "metrics.h"
#include "render_fixture.h"
#include "renderer_internal.h"
#include "satf/import.h"
#include "satf/render.h"

#define W 96
#define H 72

/* the GL context, the fixture's database and a fibre database
 * (fixture_fiber_db) */
typedef struct state {
  fixture_gl *gl;
  satf_db *fiber;
} state;

static int setup(void **st) {
  state *s = calloc(1, sizeof *s);
  if (!s || !(s->gl = fixture_gl_create(W, H))) {
    free(s);
    return -1;
  }
  *st = s;
  return (s->fiber = fixture_fiber_db()) ? 0 : -1;
}

static int teardown(void **st) {
  state *s = *st;
  satf_db_destroy(s->fiber);
  fixture_gl_free(s->gl);
  free(s);
  return 0;
}

/* Every texel of every drawn cluster's map textures (4 floats a quad,
 * r->quads quads a texel: the physical mode's 8 halfs unpacked, the
 * instances' layers of the shared arrays, prototype by prototype); *n
 * values. */
static float *read_maps(const satf_renderer *r, size_t *n) {
  size_t total = 0;
  for (int m = 0; m < r->nprotos; m++) {
    const proto *p = &r->protos[m];
    if (p->ready && !p->sparse)
      total += satf_maps_layer_texels(&p->geom, r->w) * 4 * (size_t)r->quads *
               (size_t)p->layers * (size_t)p->ninsts;
  }
  float *out = malloc((total > 0 ? total : 1) * sizeof *out);
  assert_non_null(out);
  float *at = out;
  for (int m = 0; m < r->nprotos; m++) {
    const proto *p = &r->protos[m];
    if (!p->ready || p->sparse)
      continue;
    size_t layer = satf_maps_layer_texels(&p->geom, r->w) * 4 * r->quads;
    const satf_shell_params *sh = &p->geom.shell;
    for (int i = 0; i < p->ninsts; i++) {
      const inst *in = &r->insts[p->first_inst + i];
      size_t values = layer * (size_t)p->layers;
      /* its layers of the shared array, the texels its maps hold */
      if (r->quads == 2) { /* 4 words of two halfs, low half first */
        uint16_t *h = malloc(values * sizeof *h);
        assert_non_null(h);
        glGetTextureSubImage(in->tex, 0, 0, 0, in->layer0, sh->su * r->w,
                             2 * sh->st, p->layers, GL_RGBA_INTEGER,
                             GL_UNSIGNED_INT, (GLsizei)(values * sizeof *h), h);
        half_unpack(h, at, values);
        free(h);
      } else {
        glGetTextureSubImage(in->tex, 0, 0, 0, in->layer0, sh->su * r->w,
                             2 * sh->st, p->layers, GL_RGBA, GL_FLOAT,
                             (GLsizei)(values * sizeof *at), at);
      }
      at += values;
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
 * differs in far more. A physical texel (quads 2) holds the key light's
 * RGB and alpha, then the fill lights' RGB and the s-map sum, its RGBs
 * divided by that alpha (maps_fiber.h). Prints the largest difference per
 * channel. */
#define FLIPS 2e-4
static void assert_maps_equal(const char *what, const float *cpu,
                              const float *gpu, size_t n, int quads) {
  int per = 4 * quads, alpha = quads == 2 ? 3 : 1;
  double worst[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  size_t bad = 0, first_bad = 0;
  for (size_t x = 0; x < n; x++) {
    int c = (int)(x % (size_t)per);
    size_t a = x - (size_t)c + (size_t)alpha;
    int quotient = quads == 2 ? c % 4 != 3 : c == 0;
    if (quotient && cpu[a] < 1e-3f && gpu[a] < 1e-3f)
      continue;
    double d = fabs((double)gpu[x] - (double)cpu[x]);
    if (!(d <= 2.0 * half_step(cpu[x]) + 1e-4 * fabs((double)cpu[x])) && !bad++)
      first_bad = x;
    if (!(d <= worst[c]))
      worst[c] = d;
  }
  printf("%s: %zu values, %zu beyond half rounding; largest |GPU - CPU| "
         "per channel",
         what, n, bad);
  for (int c = 0; c < per; c++)
    printf(" %.3g", worst[c]);
  printf("\n");
  if ((double)bad > FLIPS * (double)n)
    fail_msg("%s: %zu values differ beyond half rounding; first texel %zu "
             "channel %zu: GPU %.8g, CPU %.8g",
             what, bad, first_bad / (size_t)per, first_bad % (size_t)per,
             (double)gpu[first_bad], (double)cpu[first_bad]);
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
  assert_maps_equal(what, maps[SATF_MAPS_CPU], maps[SATF_MAPS_GPU], n[0],
                    r->quads);
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

/* What SATF_MAPS_AUTO resolves to on this test's context. */
static satf_maps_mode auto_mode(void) {
  const char *name = (const char *)glGetString(GL_RENDERER);
  return satf_gl_renderer_is_software(name) ? SATF_MAPS_CPU : SATF_MAPS_GPU;
}

/* Both modes on `scene` (the physical mode's on a fibre database db);
 * then the eye and the key light move while in the GPU mode (which must
 * build its instances again), compared with the CPU's maps for them.
 * Returns whether any prototype takes the orientation-free level. */
static int check_scene(const satf_db *db, satf_scene *scene, const char *what) {
  assert_non_null(scene);
  satf_renderer *r = fixture_renderer(scene, db, W, H, 2);
  assert_non_null(r);
  satf_error err;
  /* every cluster drawn as a cluster, with maps */
  assert_int_equal(satf_renderer_set_sparse_strands(r, 0, &err), SATF_OK);
  assert_int_equal(satf_renderer_maps(r), auto_mode());
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

/* The default mode: a new renderer's maps are SATF_MAPS_AUTO's choice
 * for the context (the CPU's on llvmpipe), set again after either mode;
 * the names parse back and anything else is refused. */
static void test_auto(void **st) {
  state *f = *st;
  satf_scene *scene = fixture_scene(FIXTURE_TWO_PROTOTYPES);
  assert_non_null(scene);
  satf_renderer *r = fixture_renderer(scene, f->gl->db, W, H, 2);
  assert_non_null(r);
  satf_error err;
  assert_int_equal(SATF_MAPS_DEFAULT, SATF_MAPS_AUTO);
  assert_int_equal(satf_renderer_maps(r), auto_mode());
  satf_maps_mode modes[] = {SATF_MAPS_GPU, SATF_MAPS_CPU};
  for (int i = 0; i < 2; i++) {
    assert_int_equal(satf_renderer_set_maps(r, modes[i], &err), SATF_OK);
    assert_int_equal(satf_renderer_maps(r), modes[i]);
    assert_int_equal(satf_renderer_set_maps(r, SATF_MAPS_AUTO, &err), SATF_OK);
    assert_int_equal(satf_renderer_maps(r), auto_mode());
  }
  assert_int_equal(satf_renderer_set_maps(r, (satf_maps_mode)7, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_renderer_maps(r), auto_mode());
  satf_maps_mode all[] = {SATF_MAPS_CPU, SATF_MAPS_GPU, SATF_MAPS_AUTO}, m;
  for (int i = 0; i < 3; i++) {
    assert_int_equal(satf_maps_mode_parse(satf_maps_mode_name(all[i]), &m), 0);
    assert_int_equal(m, all[i]);
  }
  assert_string_equal(satf_maps_mode_name(SATF_MAPS_AUTO), "auto");
  assert_int_equal(satf_maps_mode_parse("tpu", &m), -1);
  assert_int_equal(satf_maps_mode_parse("", &m), -1);
  assert_int_equal(satf_maps_mode_parse("GPU", &m), -1);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

static void test_procedural(void **st) {
  state *f = *st;
  assert_false(check_scene(f->gl->db, fixture_scene(FIXTURE_TWO_PROTOTYPES),
                           "two prototypes"));
}

/* An animation step in the GPU mode: an instance moves and a prototype
 * bends (its frames rebuilt: the GPU's copy of them must follow). */
static void test_scene_change(void **st) {
  state *f = *st;
  satf_scene *scene = fixture_scene(FIXTURE_TWO_PROTOTYPES);
  satf_scene *next = fixture_scene(FIXTURE_TWO_PROTOTYPES);
  assert_non_null(scene);
  assert_non_null(next);
  satf_renderer *r = fixture_renderer(scene, f->gl->db, W, H, 2);
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

static void test_samples(void **st) {
  state *f = *st;
  const char *names[] = {"cluster_6a.json", "hair_7a.json"};
  for (int i = 0; i < 2; i++) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", SATF_SAMPLES_DIR, names[i]);
    satf_scene *scene = NULL;
    satf_error err;
    if (satf_scene_load(path, &scene, &err) != SATF_OK)
      fail_msg("%s", err.message);
    /* the maps do not depend on the meshes, and the samples' head
     * (out/head.obj) is made by scripts/main.sh, which a fresh build and
     * its tests have not run */
    for (int m = 0; m < scene->n_meshes; m++)
      free(scene->meshes[m].file);
    free(scene->meshes);
    scene->meshes = NULL;
    scene->n_meshes = 0;
    check_scene(f->gl->db, scene, names[i]);
  }
}

/* A cyHair file of a curtain (satf_hair_write): `strands` straight
 * strands of `points` points, 0.1 thick, hanging from a band, a little
 * wavy. */
static void write_curtain(const char *path, int strands, int points) {
  size_t n = (size_t)strands * (size_t)points;
  int *counts = malloc((size_t)strands * sizeof *counts);
  float *xyz = malloc(3 * n * sizeof *xyz), *thick = malloc(n * sizeof *thick);
  assert_true(counts && xyz && thick);
  for (int s = 0; s < strands; s++) {
    counts[s] = points;
    for (int i = 0; i < points; i++) {
      float t = (float)i / (float)(points - 1);
      float x = -6.0f + 12.0f * (float)s / (float)(strands - 1);
      float *p = xyz + 3 * ((size_t)s * (size_t)points + (size_t)i);
      p[0] = x + 0.3f * sinf(3.0f * t + 0.37f * (float)s);
      p[1] = 20.0f - 30.0f * t;
      p[2] = 0.5f * sinf(0.71f * (float)s) + 1.5f * t * t;
      thick[(size_t)s * (size_t)points + (size_t)i] = 0.1f;
    }
  }
  satf_strand_set *set = NULL;
  satf_error err;
  if (satf_strand_set_create(strands, counts, xyz, thick, &set, &err) !=
          SATF_OK ||
      satf_hair_write(path, set, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_strand_set_destroy(set);
  free(counts);
  free(xyz);
  free(thick);
}

/* The scene of an imported curtain (satf-import of write_curtain's hair),
 * its records orientation-free. */
static satf_scene *curtain_scene(void) {
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
  return scene;
}

static void test_imported(void **st) {
  state *f = *st;
  assert_true(check_scene(f->gl->db, curtain_scene(), "imported curtain"));
}

/* `scene` in the physical mode, its key light joined by a reddish point
 * light (a fill light, with its falloff: maps_fiber.h). */
static satf_scene *physical(satf_scene *scene) {
  assert_non_null(scene);
  scene->material.model = SATF_MATERIAL_PHYSICAL;
  satf_scene_light *l =
      realloc(scene->lights, (size_t)(scene->n_lights + 1) * sizeof *l);
  assert_non_null(l);
  scene->lights = l;
  l += scene->n_lights++;
  memset(l, 0, sizeof *l);
  l->type = SATF_SCENE_LIGHT_POINT;
  const float at[3] = {3.0f, 2.0f, 6.0f}, col[3] = {1.0f, 0.6f, 0.4f};
  memcpy(l->position, at, sizeof at);
  memcpy(l->color, col, sizeof col);
  l->intensity = 20.0f;
  return scene;
}

/* The physical mode's maps (maps_fiber_cs.glsl against maps_fiber.c): the
 * procedural prototypes, Fig. 6a's cluster and the imported curtain
 * (orientation-free), each with a fill light. */
static void test_physical(void **st) {
  state *f = *st;
  assert_false(check_scene(f->fiber,
                           physical(fixture_scene(FIXTURE_TWO_PROTOTYPES)),
                           "physical, two prototypes"));
  char path[1024];
  snprintf(path, sizeof path, "%s/cluster_6a.json", SATF_SAMPLES_DIR);
  satf_scene *scene = NULL;
  satf_error err;
  if (satf_scene_load(path, &scene, &err) != SATF_OK)
    fail_msg("%s", err.message);
  check_scene(f->fiber, physical(scene), "physical, cluster_6a.json");
  assert_true(
      check_scene(f->fiber, physical(curtain_scene()), "physical, curtain"));
}

/* r's frame with the CPU's maps (set here) against img: luminance SSIM
 * at least `least`. */
static void assert_frames_alike(satf_renderer *r, const satf_image *img,
                                double least) {
  satf_error err;
  assert_int_equal(satf_renderer_set_maps(r, SATF_MAPS_CPU, &err), SATF_OK);
  satf_image *cpu = fixture_render_image(r);
  assert_non_null(cpu);
  compare_image a = fixture_compare_image(cpu, "cpu");
  compare_image b = fixture_compare_image(img, "auto");
  compare_result res;
  assert_int_equal(compare_measure(&a, &b, &res, &err), SATF_OK);
  printf("auto against the CPU's maps: SSIM %.5f\n", res.ssim);
  assert_true(res.union_px > 100);
  assert_true(res.ssim >= least);
  satf_image_destroy(cpu);
}

/* Auto's choice of the GPU's maps (made as on a hardware GPU) is lazy
 * and falls back: nothing GPU-side is made until a frame builds maps;
 * then, on the fixture's fibre database, the GPU's maps serve; on a fibre
 * database of odd record width, which they cannot read, that frame and
 * the next take the CPU's maps, the same frame as --maps cpu gives, and
 * the reason is kept. */
static void test_auto_fallback(void **st) {
  state *f = *st;
  satf_db *odd = fixture_fiber_db_width(15);
  assert_non_null(odd);
  satf_error err;
  const satf_db *dbs[2] = {f->fiber, odd};
  for (int d = 0; d < 2; d++) {
    satf_scene *scene = physical(fixture_scene(FIXTURE_TWO_PROTOTYPES));
    satf_renderer *r = fixture_renderer(scene, dbs[d], W, H, 2);
    assert_non_null(r);
    renderer_maps_auto_as(r, SATF_MAPS_GPU);
    assert_int_equal(satf_renderer_maps(r), SATF_MAPS_GPU);
    assert_null(r->mgpu);
    assert_string_equal(satf_renderer_maps_note(r), "");
    satf_image *img = fixture_render_image(r);
    assert_non_null(img);
    if (d == 0) { /* made mid-frame, they give the CPU's frame */
      assert_non_null(r->mgpu);
      assert_int_equal(satf_renderer_maps(r), SATF_MAPS_GPU);
      assert_string_equal(satf_renderer_maps_note(r), "");
      assert_frames_alike(r, img, 0.999);
    } else {
      assert_null(r->mgpu);
      assert_int_equal(satf_renderer_maps(r), SATF_MAPS_CPU);
      const char *note = satf_renderer_maps_note(r);
      printf("auto fell back: %s\n", note);
      assert_non_null(strstr(note, "15 samples"));
      assert_frames_alike(r, img, 0.9999); /* the CPU's frame */
      assert_string_equal(satf_renderer_maps_note(r), "");
      /* an explicit --maps gpu still refuses it */
      assert_int_equal(satf_renderer_set_maps(r, SATF_MAPS_GPU, &err),
                       SATF_ERR_INCOMPATIBLE);
      assert_int_equal(satf_renderer_maps(r), SATF_MAPS_CPU);
    }
    satf_image_destroy(img);
    satf_renderer_destroy(r);
    satf_scene_destroy(scene);
  }
  satf_db_destroy(odd);
}

/* Curly clusters (satf_scene_density.curl: M_p over a cone of fibre
 * tangents, maps_fiber.c mp_tilted) in the physical mode: the GPU's maps
 * are the CPU's; and the curl changes the frame: the front-lit
 * highlights of fibres along the trajectory spread over the cone
 * (luminance ratio against the prototypes with no curl). */
static void test_physical_curl(void **st) {
  state *f = *st;
  satf_scene *scene = physical(fixture_scene(FIXTURE_TWO_PROTOTYPES));
  satf_scene *flat = physical(fixture_scene(FIXTURE_TWO_PROTOTYPES));
  assert_true(scene->n_macro_clusters >= 2);
  scene->macro_clusters[0].prototype.density.curl = 45.0f;
  scene->macro_clusters[1].prototype.density.curl = 30.0f;
  satf_image *img[2];
  satf_scene *both[2] = {flat, scene};
  for (int k = 0; k < 2; k++) {
    satf_renderer *r = fixture_renderer(both[k], f->fiber, W, H, 2);
    assert_non_null(r);
    img[k] = fixture_render_image(r);
    assert_non_null(img[k]);
    satf_renderer_destroy(r);
  }
  compare_image a = fixture_compare_image(img[0], "no curl");
  compare_image b = fixture_compare_image(img[1], "curl");
  compare_result res;
  satf_error err;
  assert_int_equal(compare_measure(&a, &b, &res, &err), SATF_OK);
  printf("curl 45 and 30 degrees against none: luminance x %.3f, IoU %.4f\n",
         res.lum_ratio, res.iou);
  assert_true(res.iou > 0.999); /* the coverage is the density's */
  assert_true(fabs(res.lum_ratio - 1.0) > 0.03);
  satf_image_destroy(img[0]);
  satf_image_destroy(img[1]);
  satf_scene_destroy(flat);
  check_scene(f->fiber, scene, "physical, curly prototypes");
  /* curly clusters of imported strands: the cone about each sector's own
   * direction (maps_cone_tangents), the GPU's as the CPU's */
  satf_scene *curtain = physical(curtain_scene());
  for (int m = 0; m < curtain->n_macro_clusters; m++)
    curtain->macro_clusters[m].prototype.density.curl = 40.0f;
  assert_true(check_scene(f->fiber, curtain, "physical, curly curtain"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_auto),       cmocka_unit_test(test_auto_fallback),
      cmocka_unit_test(test_procedural), cmocka_unit_test(test_scene_change),
      cmocka_unit_test(test_samples),    cmocka_unit_test(test_imported),
      cmocka_unit_test(test_physical),   cmocka_unit_test(test_physical_curl),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
