/* test_render.c - whole frames of the online renderer (satf/render.h) on
 * Mesa's llvmpipe through a headless EGL context, with a small database built
 * in the test: determinism, the AOV layers and their EXR file, the effect
 * switches of the paper's Fig. 4, order-independent compositing (eq. 14),
 * eq. 7's mix of a root row, the background, every light the scene
 * accepts, and rejected input. */
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

#include <png.h>

#include "render_fixture.h"
#include "satf/common.h"
#include "satf/gl.h"
#include "satf/render.h"
#include "test_util.h"

#define W 160
#define H 120

/* One cluster, bent and twisted, lit from the upper right. */
static const char *scene_one =
    "{\"macro_clusters\": [{\"prototype\": {"
    "  \"trajectory\": [[0, -3, 0], [0.4, 0, 0.3], [0, 3, 0]],"
    "  \"a\": 1.0, \"b\": 0.7, \"twist\": [0, 1.2, 2.4],"
    "  \"shell\": {\"layers\": 4, \"st\": 12, \"su\": 10, \"core\": 0.4},"
    "  \"density\": {\"strands\": 800, \"seed\": 5, \"strand_width\": 0.05}}}],"
    " \"camera\": {\"position\": [0, 0, 12], \"target\": [0, 0, 0],"
    "              \"fov_y\": 40},"
    " \"lights\": [{\"direction\": [-0.3, -0.4, -0.85]}],"
    " \"background\": [0.2, 0.3, 0.4],"
    " \"image\": {\"width\": 160, \"height\": 120}}";

/* Three macro-clusters crossing on screen (the second with two
 * instances), listed in either order. */
static const char *macro[3] = {
    "{\"name\": \"vertical\", \"prototype\": {"
    "  \"trajectory\": [[0, -3, 0], [0, 3, 0]], \"a\": 0.9,"
    "  \"shell\": {\"layers\": 3, \"st\": 8, \"su\": 10},"
    "  \"density\": {\"strands\": 600, \"seed\": 1}}}",
    "{\"name\": \"diagonal\", \"prototype\": {"
    "  \"trajectory\": [[-3, -2, 1], [3, 2, 1]], \"a\": 0.7, \"b\": 0.5,"
    "  \"shell\": {\"layers\": 3, \"st\": 8, \"su\": 10},"
    "  \"density\": {\"strands\": 500, \"seed\": 2, \"layout\": \"clumped\"}},"
    " \"instances\": [{}, {\"translate\": [0, 0, -2], "
    "                    \"rotate\": {\"axis\": [0, 0, 1], \"angle\": 70}}]}",
    "{\"name\": \"horizontal\", \"prototype\": {"
    "  \"trajectory\": [[-3, 0.5, -1], [0, 0.2, -0.5], [3, 0.5, -1]],"
    "  \"a\": 0.8, \"twist\": [0, 2, 4],"
    "  \"shell\": {\"layers\": 4, \"st\": 10, \"su\": 8},"
    "  \"density\": {\"strands\": 700, \"seed\": 3, \"layout\": \"holes\"}}}"};

static const char *scene_tail =
    "], \"camera\": {\"position\": [1, 2, 12], \"target\": [0, 0, 0]},"
    " \"lights\": [{\"direction\": [-0.5, -0.3, -0.8]},"
    "             {\"type\": \"point\", \"position\": [4, 4, 6],"
    "              \"intensity\": 6, \"color\": [0.8, 0.9, 1]}],"
    " \"background\": [0.05, 0.05, 0.1]}";

typedef struct fixture {
  satf_gl_context *ctx;
  satf_db *db;
  satf_scene *one;
  satf_renderer *r; /* scene_one at W x H */
} fixture;

static const char *const all_channels[] = {
    "R",         "G",        "B",       "A",       "diffuse.R", "diffuse.G",
    "diffuse.B", "specI.R",  "specI.G", "specI.B", "specII.R",  "specII.G",
    "specII.B",  "shadow.Y", "alpha.Y", "Z"};
#define NCHANNELS 16

static int setup(void **state) {
  fixture *f = calloc(1, sizeof *f);
  satf_error err;
  if (!f)
    return -1;
  if (satf_gl_context_create_headless(W, H, &f->ctx, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  if (!(f->db = fixture_db()) || !(f->one = fixture_scene(scene_one)))
    return -1;
  if (satf_renderer_create(f->one, f->db, W, H, 0, &f->r, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  *state = f;
  return 0;
}

static int teardown(void **state) {
  fixture *f = *state;
  satf_renderer_destroy(f->r);
  satf_scene_destroy(f->one);
  satf_db_destroy(f->db);
  satf_gl_context_destroy(f->ctx);
  free(f);
  return 0;
}

static satf_image *render(satf_renderer *r, int aovs) {
  satf_image *img = NULL;
  satf_error err;
  satf_frame_timing t;
  if (satf_renderer_render_image(r, aovs, &img, &t, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return NULL;
  }
  return img;
}

/* scene JSON through a fresh renderer at W x H: its frame (with aovs), and
 * the scene and renderer for the caller to destroy */
static satf_image *render_json(const fixture *f, const char *json, int aovs,
                               satf_scene **scene, satf_renderer **r) {
  *scene = fixture_scene(json);
  assert_non_null(*scene);
  *r = fixture_renderer(*scene, f->db, W, H, 0);
  assert_non_null(*r);
  satf_image *img = render(*r, aovs);
  assert_non_null(img);
  return img;
}

static double luminance(const satf_image *img, size_t i) {
  return 0.2126 * fixture_plane(img, "R")[i] +
         0.7152 * fixture_plane(img, "G")[i] +
         0.0722 * fixture_plane(img, "B")[i];
}

/* Pixels the hair covers noticeably. */
static size_t hair_pixels(const satf_image *img, float min_alpha) {
  const float *a = fixture_plane(img, "A");
  size_t n = 0, px = (size_t)satf_image_width(img) * satf_image_height(img);
  for (size_t i = 0; i < px; i++)
    n += a[i] > min_alpha;
  return n;
}

static void test_deterministic(void **state) {
  fixture *f = *state;
  satf_image *a = render(f->r, 1), *b = render(f->r, 1);
  assert_non_null(a);
  assert_non_null(b);
  for (int c = 0; c < NCHANNELS; c++)
    if (!fixture_same_bits(a, b, all_channels[c]))
      fail_msg("channel %s differs between two renders", all_channels[c]);
  /* a second renderer of the same scene draws the same frame */
  satf_renderer *r2 = NULL;
  satf_error err;
  assert_int_equal(satf_renderer_create(f->one, f->db, W, H, 1, &r2, &err),
                   SATF_OK);
  satf_image *c = render(r2, 0);
  assert_non_null(c);
  for (int k = 0; k < 4; k++)
    assert_true(fixture_same_bits(a, c, all_channels[k]));
  satf_image_destroy(c);
  satf_renderer_destroy(r2);
  satf_image_destroy(a);
  satf_image_destroy(b);
}

/* Transparent black where no hair is (the background is the image's
 * background colour, for the preview); hair pixels have coverage; the
 * frame is not empty. */
static void test_background_and_coverage(void **state) {
  fixture *f = *state;
  satf_image *img = render(f->r, 1);
  assert_non_null(img);
  assert_int_equal(satf_image_width(img), W);
  assert_int_equal(satf_image_height(img), H);
  const size_t corners[4] = {0, W - 1, (size_t)W * (H - 1), (size_t)W * H - 1};
  const float *bg = f->one->background;
  float img_bg[3];
  satf_image_background(img, img_bg);
  for (int k = 0; k < 4; k++) {
    size_t i = corners[k];
    for (int c = 0; c < 3; c++) {
      assert_true(fixture_plane(img, all_channels[c])[i] == 0.0f);
      assert_true(img_bg[c] == bg[c]);
    }
    assert_true(fixture_plane(img, "A")[i] == 0.0f);
    for (int c = 4; c < NCHANNELS - 1; c++) /* AOVs are over black */
      assert_true(fixture_plane(img, all_channels[c])[i] == 0.0f);
    /* and the depth is Blender's and Nuke's "nothing": 1e10 */
    assert_true(fixture_plane(img, "Z")[i] == 1e10f);
  }
  size_t centre = (size_t)W * (H / 2) + W / 2;
  assert_true(fixture_plane(img, "A")[centre] > 0.1f);
  satf_render_stats stats; /* no pixel of this scene overflows */
  satf_renderer_stats(f->r, &stats);
  assert_int_equal(stats.overflow_pixels, 0);
  size_t covered = hair_pixels(img, 0.01f);
  printf("hair covers %zu of %d pixels\n", covered, W * H);
  assert_true(covered > 500 && covered < (size_t)W * H / 2);
  /* coverage and colour stay in range */
  for (size_t i = 0; i < (size_t)W * H; i++) {
    float a = fixture_plane(img, "A")[i];
    assert_true(a >= 0.0f && a <= 1.0f);
    for (int c = 0; c < 3; c++)
      assert_true(isfinite(fixture_plane(img, all_channels[c])[i]) &&
                  fixture_plane(img, all_channels[c])[i] >= 0.0f);
  }
  satf_image_destroy(img);
}

/* The AOVs decompose the frame: every layer is composited with the same
 * fragments and alphas, and eq. 14 is linear in colour, so the
 * premultiplied beauty = diffuse + specI + specII (+ bg (1 - A) once
 * flattened), the alpha AOV is A, and the shadow AOV
 * (transmittance x coverage) lies in [0, A]. Fragments are stored as
 * halves per pass, hence the tolerance. */
static void test_aovs_decompose_beauty(void **state) {
  fixture *f = *state;
  satf_image *img = render(f->r, 1);
  assert_non_null(img);
  satf_image_flatten(img); /* what --background-in-exr writes */
  const float *bg = f->one->background;
  const char *layers[3][3] = {{"diffuse.R", "specI.R", "specII.R"},
                              {"diffuse.G", "specI.G", "specII.G"},
                              {"diffuse.B", "specI.B", "specII.B"}};
  const float *A = fixture_plane(img, "A");
  double worst = 0.0, spec2 = 0.0;
  for (size_t i = 0; i < (size_t)W * H; i++) {
    for (int c = 0; c < 3; c++) {
      double sum = bg[c] * (1.0 - A[i]);
      for (int l = 0; l < 3; l++)
        sum += fixture_plane(img, layers[c][l])[i];
      double beauty = fixture_plane(img, all_channels[c])[i];
      double d = fabs(beauty - sum);
      worst = d > worst ? d : worst;
      if (d > 2e-3 * fabs(beauty) + 2e-4)
        fail_msg("pixel %zu channel %d: beauty %.6f, bg (1 - A) + AOVs %.6f", i,
                 c, beauty, sum);
      spec2 = fmax(spec2, fixture_plane(img, layers[c][2])[i]);
    }
    float alpha = fixture_plane(img, "alpha.Y")[i];
    float shadow = fixture_plane(img, "shadow.Y")[i];
    /* the alpha AOV is a fragment's colour sum, A its 1 - prod(1 - a):
     * equal, but each is rounded to a half separately, so they may land
     * one half step (2^-11 relative) apart */
    float half_step = 1e-5f + A[i] / 1024.0f;
    assert_true(fabsf(alpha - A[i]) <= half_step);
    assert_true(shadow >= 0.0f && shadow <= alpha + half_step);
  }
  printf("largest |beauty - (bg (1 - A) + AOVs)| = %.2e\n", worst);
  assert_true(spec2 > 0.0);
  satf_image_destroy(img);
}

/* SATF eq. 10-11 shift the highlights along the normal of a strand facing
 * the viewer (shade_fs.glsl, as the strand reference path), not along the
 * cluster's ellipse normal: the strands of a straight flat cluster, all
 * parallel, seen and lit from far away, have one highlight across the
 * whole cluster, so primary highlight over diffuse is the same in every
 * covered pixel (both AOVs are the same layers' reflectance and alphas
 * times one lighting). Along the ellipse normal it ran from 0.84 to 1.01 of
 * its mean across the cluster (the normal turns sideways at its
 * silhouette, and the back shells took the inward one): the imported
 * ponytail's crown showed a highlight arc per cluster. */
static void test_highlight_across_flat_cluster(void **state) {
  fixture *f = *state;
  static const char *json =
      "{\"macro_clusters\": [{\"prototype\": {"
      "  \"trajectory\": [[0, -3, 0], [0, 3, 0]], \"a\": 1.5, \"b\": 0.4,"
      "  \"shell\": {\"layers\": 4, \"st\": 8, \"su\": 12, \"core\": 0.3},"
      "  \"density\": {\"strands\": 900, \"seed\": 9, "
      "               \"strand_width\": 0.05}}}],"
      " \"camera\": {\"position\": [0, 0, 300], \"target\": [0, 0, 0],"
      "              \"fov_y\": 1.6},"
      " \"lights\": [{\"direction\": [-0.4, 0.19, -0.9]}],"
      " \"effects\": {\"cluster_shadows\": false},"
      " \"background\": [0, 0, 0], \"image\": {\"width\": 160, "
      "\"height\": 120}}";
  satf_scene *scene;
  satf_renderer *r;
  satf_image *img = render_json(f, json, 1, &scene, &r);
  const float *A = fixture_plane(img, "A");
  const float *dif = fixture_plane(img, "diffuse.G");
  const float *spec = fixture_plane(img, "specI.G");
  double lo = 1e30, hi = 0.0, sum = 0.0;
  int n = 0;
  for (int y = H / 4; y < 3 * H / 4; y++)
    for (int x = 0; x < W; x++) {
      size_t i = (size_t)y * W + (size_t)x;
      if (!(A[i] > 0.3f && dif[i] > 1e-3f))
        continue;
      double q = spec[i] / dif[i];
      lo = fmin(lo, q), hi = fmax(hi, q), sum += q, n++;
    }
  printf("primary highlight / diffuse over %d pixels: %.4f to %.4f, mean "
         "%.4f\n",
         n, lo, hi, sum / n);
  assert_true(n > 500);
  assert_true(lo > 0.01 * (sum / n)); /* the highlight is there */
  assert_true(hi - lo < 0.02 * (sum / n));
  satf_image_destroy(img);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

/* A cluster of "tracks" whose strands all start after its first slice
 * (satf-import's clusters begin a little above their roots): the first
 * boundary holds no strand, so the first HSV row thins out towards t = 0
 * (SATF eq. 7 mixes its two boundary records), but the strands it holds
 * are lit like the rest. Mixed as stored (reflectance per unit alpha),
 * the row went from black to full brightness. */
static void test_root_row_not_darkened(void **state) {
  fixture *f = *state;
  char *json = fixture_rooted_tracks_json("");
  assert_non_null(json);
  satf_scene *scene;
  satf_renderer *r;
  satf_image *img = render_json(f, json, 0, &scene, &r);
  free(json);
  double ratio = fixture_root_rows_ratio(img);
  printf("root rows: luminance per unit alpha %.3f of the body's\n", ratio);
  /* 1.00 measured; 0.34 mixed as stored */
  assert_true(ratio > 0.85);
  satf_image_destroy(img);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

/* satf-render --aov: the frame and every AOV in one EXR, read back through
 * OpenEXR with the documented channel names, values rounded to half. */
static void test_exr_with_aovs(void **state) {
  fixture *f = *state;
  satf_image *img = render(f->r, 1);
  assert_non_null(img);
  assert_int_equal(satf_image_channel_count(img), NCHANNELS);
  for (int c = 0; c < NCHANNELS; c++)
    assert_string_equal(satf_image_channel_name(img, c), all_channels[c]);
  char path[1024];
  test_path(path, sizeof path, "test_render_aov.exr");
  satf_error err;
  assert_int_equal(satf_image_write_exr(img, path, &err), SATF_OK);
  float *planes[NCHANNELS] = {NULL};
  int w = 0, h = 0;
  satf_status st = satf_exr_read(path, all_channels, NCHANNELS, 1 << 24, NULL,
                                 NULL, &w, &h, planes, &err);
  if (st != SATF_OK)
    fail_msg("%s", err.message);
  assert_int_equal(w, W);
  assert_int_equal(h, H);
  for (int c = 0; c < NCHANNELS; c++) {
    const float *want = fixture_plane(img, all_channels[c]);
    for (size_t i = 0; i < (size_t)W * H; i++)
      if (fabsf(planes[c][i] - want[i]) > 5e-4f * fabsf(want[i]) + 1e-7f)
        fail_msg("%s pixel %zu: file %.6f, image %.6f", all_channels[c], i,
                 (double)planes[c][i], (double)want[i]);
    free(planes[c]);
  }
  remove(path);
  satf_image_destroy(img);
}

/* The channel names in the header of the EXR at path, through OpenEXRCore
 * (what Blender, Nuke and OpenImageIO list); returns their count. */
static int exr_channel_names(const char *path, char names[][64], int max) {
  exr_context_t ctx = NULL;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  if (exr_start_read(&ctx, path, &init) != EXR_ERR_SUCCESS)
    return -1;
  const exr_attr_chlist_t *list = NULL;
  int n = -1;
  if (exr_get_channels(ctx, 0, &list) == EXR_ERR_SUCCESS) {
    n = list->num_channels < max ? list->num_channels : max;
    for (int c = 0; c < n; c++)
      snprintf(names[c], 64, "%s", list->entries[c].name.str);
  }
  exr_finish(&ctx);
  return n;
}

/* One of the EXR's names: a single-letter layer-less beauty channel
 * or LAYER.TOKEN with a token every compositor knows. */
static int standard_channel(const char *name) {
  const char *dot = strrchr(name, '.');
  const char *token = dot ? dot + 1 : name;
  return strlen(token) == 1 && strchr("RGBAYZ", token[0]) &&
         (!dot || dot > name);
}

/* The file's worldToCamera and worldToNDC: the image's camera, transposed
 * (Imath multiplies row vectors). */
static void exr_expect_camera(const char *path, const satf_image *img) {
  float view[16], ndc[16];
  assert_true(satf_image_camera(img, view, ndc));
  exr_context_t ctx = NULL;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  assert_int_equal(exr_start_read(&ctx, path, &init), EXR_ERR_SUCCESS);
  static const char *const names[2] = {"worldToCamera", "worldToNDC"};
  const float *want[2] = {view, ndc};
  for (int k = 0; k < 2; k++) {
    const exr_attribute_t *a = NULL;
    assert_int_equal(exr_get_attribute_by_name(ctx, 0, names[k], &a),
                     EXR_ERR_SUCCESS);
    assert_int_equal(a->type, EXR_ATTR_M44F);
    for (int i = 0; i < 4; i++)
      for (int j = 0; j < 4; j++)
        assert_true(a->m44f->m[4 * i + j] == want[k][4 * j + i]);
  }
  exr_finish(&ctx);
}

/* EXR conventions: every channel is named with a
 * standard token, the beauty is R, G, B, A, colour is premultiplied over
 * transparent black (alpha 0: RGB 0), and the PNG preview is that colour
 * over the background: PNG = RGB + (1 - A) bg, i.e. for an opaque
 * background-free preview RGB = PNG colour x A. */
static void test_exr_premultiplied_and_named(void **state) {
  fixture *f = *state;
  satf_image *img = render(f->r, 1);
  assert_non_null(img);
  char exr[1024], png[1024];
  test_path(exr, sizeof exr, "test_render_conv.exr");
  test_path(png, sizeof png, "test_render_conv.png");
  satf_error err;
  assert_int_equal(satf_image_write_exr(img, exr, &err), SATF_OK);
  assert_int_equal(satf_image_write_png_rgb(img, png, &err), SATF_OK);
  char names[NCHANNELS + 4][64];
  assert_int_equal(exr_channel_names(exr, names, NCHANNELS + 4), NCHANNELS);
  /* one named view layer (Blender's image node lists an unnamed one as no
   * layer at all): satf.Combined.R for R, satf.diffuse.R for diffuse.R */
  for (int c = 0; c < NCHANNELS; c++) {
    char want[80];
    const char *pass = strchr(all_channels[c], '.')        ? ""
                       : strcmp(all_channels[c], "Z") == 0 ? "Depth."
                                                           : "Combined.";
    snprintf(want, sizeof want, "satf.%s%s", pass, all_channels[c]);
    int found = 0;
    for (int k = 0; k < NCHANNELS; k++)
      found |= strcmp(names[k], want) == 0;
    if (!found || !standard_channel(names[c]) ||
        strncmp(names[c], "satf.", 5) != 0)
      fail_msg("channel '%s' missing or '%s' not satf.PASS.TOKEN", want,
               names[c]);
  }
  exr_expect_camera(exr, img);
  float *p[4] = {NULL};
  int w = 0, h = 0;
  assert_int_equal(
      satf_exr_read(exr, all_channels, 4, 1 << 24, NULL, NULL, &w, &h, p, &err),
      SATF_OK);
  png_image pi;
  memset(&pi, 0, sizeof pi);
  pi.version = PNG_IMAGE_VERSION;
  assert_true(png_image_begin_read_from_file(&pi, png));
  pi.format = PNG_FORMAT_RGB;
  unsigned char *px = malloc(PNG_IMAGE_SIZE(pi));
  assert_non_null(px);
  assert_true(png_image_finish_read(&pi, NULL, px, 0, NULL));
  const float *bg = f->one->background;
  size_t clear = 0, half = 0;
  for (size_t i = 0; i < (size_t)W * H; i++) {
    float a = p[3][i];
    for (int c = 0; c < 3; c++) {
      if (a == 0.0f && p[c][i] != 0.0f)
        fail_msg("pixel %zu: A = 0 but %s = %g", i, all_channels[c],
                 (double)p[c][i]);
      double v = px[3 * i + (size_t)c] / 255.0; /* sRGB decode */
      v = v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
      double want = p[c][i] + (1.0 - a) * bg[c];
      /* 8-bit sRGB steps are at most 1.4% of the value, plus the toe */
      if (want <= 1.0 && fabs(v - want) > 0.015 * want + 0.002)
        fail_msg("pixel %zu %s: PNG %.4f, EXR over background %.4f", i,
                 all_channels[c], v, want);
    }
    clear += a == 0.0f;
    half += a > 0.3f && a < 0.7f;
  }
  printf("%zu pixels with A = 0, %zu half covered\n", clear, half);
  assert_true(clear > 1000 && half > 20);
  free(px);
  for (int c = 0; c < 4; c++)
    free(p[c]);
  remove(exr);
  remove(png);
  satf_image_destroy(img);
}

/* Fig. 4(b): without the secondary highlight only specII (and the beauty
 * colour, by exactly specII) changes. */
static void test_secondary_highlight_off(void **state) {
  fixture *f = *state;
  satf_scene_effects *e = satf_renderer_effects(f->r);
  satf_image *on = render(f->r, 1);
  e->secondary_highlight = 0;
  satf_image *off = render(f->r, 1);
  e->secondary_highlight = 1;
  assert_non_null(on);
  assert_non_null(off);
  const char *same[] = {"A",         "diffuse.R", "diffuse.G",
                        "diffuse.B", "specI.R",   "specI.G",
                        "specI.B",   "shadow.Y",  "alpha.Y"};
  for (size_t k = 0; k < sizeof same / sizeof same[0]; k++)
    if (!fixture_same_bits(on, off, same[k]))
      fail_msg("%s changed with the secondary highlight off", same[k]);
  const char *spec2[3] = {"specII.R", "specII.G", "specII.B"};
  double most = 0.0;
  for (int c = 0; c < 3; c++) {
    const float *s_on = fixture_plane(on, spec2[c]);
    const float *s_off = fixture_plane(off, spec2[c]);
    const float *b_on = fixture_plane(on, all_channels[c]);
    const float *b_off = fixture_plane(off, all_channels[c]);
    for (size_t i = 0; i < (size_t)W * H; i++) {
      assert_true(s_off[i] == 0.0f);
      most = fmax(most, s_on[i]);
      double d = (double)b_on[i] - b_off[i];
      assert_true(fabs(d - s_on[i]) <= 2e-3 * fabs(b_on[i]) + 2e-4);
    }
  }
  printf("largest specII: %.4f\n", most);
  assert_true(most > 0.01);
  assert_true(fixture_max_diff(on, off, "R") > 0.01);
  satf_image_destroy(on);
  satf_image_destroy(off);
}

/* Fig. 4(c): without the s-maps of eq. 12 inner layers are lit fully, so
 * hair gets brighter; the shadow AOV then carries only the deep opacity
 * map, and without that too it is the coverage itself. */
static void test_self_shadow_off(void **state) {
  fixture *f = *state;
  satf_scene_effects *e = satf_renderer_effects(f->r);
  satf_image *on = render(f->r, 1);
  e->self_shadow = 0;
  satf_image *off = render(f->r, 1);
  e->cluster_shadows = 0;
  satf_image *none = render(f->r, 1);
  e->self_shadow = 1;
  e->cluster_shadows = 1;
  assert_non_null(on);
  assert_non_null(off);
  assert_non_null(none);
  assert_true(fixture_same_bits(on, off, "A"));
  double lum_on = 0, lum_off = 0, sh_on = 0, sh_off = 0;
  size_t n = 0;
  const float *A = fixture_plane(on, "A");
  for (size_t i = 0; i < (size_t)W * H; i++)
    if (A[i] > 0.05f) {
      lum_on += luminance(on, i);
      lum_off += luminance(off, i);
      sh_on += fixture_plane(on, "shadow.Y")[i];
      sh_off += fixture_plane(off, "shadow.Y")[i];
      n++;
      assert_true(fixture_plane(off, "shadow.Y")[i] >=
                  fixture_plane(on, "shadow.Y")[i] - 1e-5f);
    }
  assert_true(n > 0);
  printf("mean luminance over %zu hair pixels: %.4f with s-maps, %.4f "
         "without; mean shadow AOV %.4f, %.4f\n",
         n, lum_on / n, lum_off / n, sh_on / n, sh_off / n);
  assert_true(lum_off > 1.03 * lum_on);
  assert_true(sh_off > sh_on);
  for (size_t i = 0; i < (size_t)W * H; i++)
    assert_true(fabsf(fixture_plane(none, "shadow.Y")[i] -
                      fixture_plane(none, "alpha.Y")[i]) <= 1e-5f);
  satf_image_destroy(on);
  satf_image_destroy(off);
  satf_image_destroy(none);
}

/* Fig. 4(a): plain Kajiya-Kay without the database looks clearly
 * different from SATF. */
static void test_satf_off(void **state) {
  fixture *f = *state;
  satf_scene_effects *e = satf_renderer_effects(f->r);
  satf_image *on = render(f->r, 0);
  e->satf = 0;
  satf_image *off = render(f->r, 0);
  e->satf = 1;
  assert_non_null(on);
  assert_non_null(off);
  double sum = 0.0;
  size_t n = 0;
  const float *A = fixture_plane(on, "A");
  for (size_t i = 0; i < (size_t)W * H; i++)
    if (A[i] > 0.05f) {
      sum += fabs(luminance(on, i) - luminance(off, i));
      n++;
    }
  double max_rgb = fmax(
      fixture_max_diff(on, off, "R"),
      fmax(fixture_max_diff(on, off, "G"), fixture_max_diff(on, off, "B")));
  printf("SATF vs plain Kajiya-Kay: mean |dL| %.4f over %zu hair pixels, max "
         "%.4f\n",
         n ? sum / n : 0.0, n, max_rgb);
  assert_true(n > 0);
  assert_true(sum / n > 0.01);
  assert_true(max_rgb > 0.05);
  satf_image_destroy(on);
  satf_image_destroy(off);
}

static satf_scene *macro_scene(const int order[3]) {
  size_t len = 64 + strlen(scene_tail);
  for (int k = 0; k < 3; k++)
    len += strlen(macro[k]) + 2;
  char *json = malloc(len);
  if (!json)
    return NULL;
  strcpy(json, "{\"macro_clusters\": [");
  for (int k = 0; k < 3; k++) {
    if (k)
      strcat(json, ", ");
    strcat(json, macro[order[k]]);
  }
  strcat(json, scene_tail);
  satf_scene *s = fixture_scene(json);
  free(json);
  return s;
}

/* Eq. 14 through sorted per-pixel fragment lists: the order in which the
 * clusters are drawn does not change the picture. */
static void test_order_independence(void **state) {
  fixture *f = *state;
  const int fwd[3] = {0, 1, 2}, rev[3] = {2, 1, 0};
  satf_scene *a = macro_scene(fwd), *b = macro_scene(rev);
  assert_non_null(a);
  assert_non_null(b);
  satf_renderer *ra = NULL, *rb = NULL;
  satf_error err;
  assert_int_equal(satf_renderer_create(a, f->db, W, H, 0, &ra, &err), SATF_OK);
  assert_int_equal(satf_renderer_create(b, f->db, W, H, 0, &rb, &err), SATF_OK);
  satf_render_stats sa, sb;
  satf_renderer_stats(ra, &sa);
  satf_renderer_stats(rb, &sb);
  /* 1 + 2 + 1 clusters of 3, 3 and 4 layers */
  assert_int_equal(sa.macro_clusters, 3);
  assert_int_equal(sa.clusters, 4);
  assert_int_equal(sa.layers, 3 + 2 * 3 + 4);
  assert_int_equal(sa.hsvs, 3 * 8 * 10 + 2 * 3 * 8 * 10 + 4 * 10 * 8);
  assert_int_equal(sa.strands, 600 + 2 * 500 + 700);
  assert_int_equal(sa.prototypes_shared, 1);
  assert_memory_equal(&sa, &sb, sizeof sa);
  satf_image *ia = render(ra, 0), *ib = render(rb, 0);
  assert_non_null(ia);
  assert_non_null(ib);
  double worst = 0.0;
  for (int c = 0; c < 4; c++)
    worst = fmax(worst, fixture_max_diff(ia, ib, all_channels[c]));
  size_t covered = hair_pixels(ia, 0.01f);
  printf("order: max difference %.2e (%zu hair pixels)\n", worst, covered);
  assert_true(covered > 1000);
  assert_true(worst <= 1.0 / 255.0);
  satf_image_destroy(ia);
  satf_image_destroy(ib);
  satf_renderer_destroy(ra);
  satf_renderer_destroy(rb);
  satf_scene_destroy(a);
  satf_scene_destroy(b);
}

/* Resizing re-allocates the screen buffers; going back to the first size
 * draws the first frame again. */
static void test_resize(void **state) {
  fixture *f = *state;
  satf_error err;
  satf_image *a = render(f->r, 0);
  assert_int_equal(satf_renderer_resize(f->r, W / 2, H / 2, &err), SATF_OK);
  satf_image *small = render(f->r, 0);
  assert_non_null(small);
  assert_int_equal(satf_image_width(small), W / 2);
  assert_int_equal(satf_image_height(small), H / 2);
  assert_true(hair_pixels(small, 0.01f) > 100);
  assert_int_equal(satf_renderer_resize(f->r, 0, H, &err), SATF_ERR_ARGUMENT);
  assert_int_equal(satf_renderer_resize(f->r, W, H, &err), SATF_OK);
  satf_image *b = render(f->r, 0);
  assert_non_null(a);
  assert_non_null(b);
  for (int c = 0; c < 4; c++)
    assert_true(fixture_same_bits(a, b, all_channels[c]));
  satf_image_destroy(a);
  satf_image_destroy(small);
  satf_image_destroy(b);
}

/* Bad input is refused with a message, never drawn: records wider than
 * the renderer's maps support, and an empty frame. */
/* Every light the scene format accepts is drawn: with the scene's largest
 * number of lights, the last one still changes the picture. */
static void test_every_light_drawn(void **state) {
  fixture *f = *state;
  char lights[4096] = "", json[8192];
  size_t len = 0;
  for (int k = 0; k < SATF_SCENE_MAX_LIGHTS; k++) {
    int last = k == SATF_SCENE_MAX_LIGHTS - 1;
    len += (size_t)snprintf(
        lights + len, sizeof lights - len,
        "%s{\"direction\": %s, \"intensity\": %d}", k ? ", " : "",
        last ? "[0.6, 0.2, -0.77]" : "[-0.3, -0.4, -0.85]", k == 0 || last);
    assert_true(len < sizeof lights);
  }
  const char *from = strstr(scene_one, "\"lights\"");
  const char *to = strstr(scene_one, "\"background\"");
  assert_non_null(from);
  assert_non_null(to);
  snprintf(json, sizeof json, "%.*s\"lights\": [%s], %s",
           (int)(from - scene_one), scene_one, lights, to);
  satf_scene *scene = fixture_scene(json);
  assert_non_null(scene);
  satf_renderer *r = NULL;
  satf_error err;
  assert_int_equal(satf_renderer_create(scene, f->db, W, H, 0, &r, &err),
                   SATF_OK);
  assert_int_equal(satf_renderer_light_count(r), SATF_SCENE_MAX_LIGHTS);
  satf_image *with = render(r, 0);
  satf_renderer_light(r, SATF_SCENE_MAX_LIGHTS - 1)->intensity = 0.0f;
  satf_image *without = render(r, 0);
  assert_non_null(with);
  assert_non_null(without);
  double d = fixture_max_diff(with, without, "R");
  printf("the last of %d lights changes R by up to %.4f\n",
         SATF_SCENE_MAX_LIGHTS, d);
  assert_true(d > 0.01);
  satf_image_destroy(with);
  satf_image_destroy(without);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

static void test_rejects_bad_input(void **state) {
  fixture *f = *state;
  satf_build_params p = fixture_db_params();
  p.samples = 2;
  p.n_view = 2;
  p.n_light = 2;
  p.grid = 4;
  p.trace.width = 1024;
  satf_db *wide = NULL;
  satf_error err;
  assert_int_equal(satf_db_create(&p, &wide, &err), SATF_OK);
  assert_int_equal(satf_db_finalize(wide, &err), SATF_OK);
  satf_renderer *r = (satf_renderer *)&err; /* must be reset to NULL */
  satf_status st = satf_renderer_create(f->one, wide, W, H, 0, &r, &err);
  assert_int_not_equal(st, SATF_OK);
  assert_int_equal(st, SATF_ERR_INCOMPATIBLE);
  assert_null(r);
  assert_non_null(strstr(err.message, "1024"));
  printf("width 1024: %s\n", err.message);
  satf_db_destroy(wide);

  r = (satf_renderer *)&err;
  st = satf_renderer_create(f->one, f->db, 0, H, 0, &r, &err);
  assert_int_equal(st, SATF_ERR_ARGUMENT);
  assert_null(r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_deterministic),
      cmocka_unit_test(test_background_and_coverage),
      cmocka_unit_test(test_aovs_decompose_beauty),
      cmocka_unit_test(test_highlight_across_flat_cluster),
      cmocka_unit_test(test_root_row_not_darkened),
      cmocka_unit_test(test_exr_with_aovs),
      cmocka_unit_test(test_exr_premultiplied_and_named),
      cmocka_unit_test(test_secondary_highlight_off),
      cmocka_unit_test(test_self_shadow_off),
      cmocka_unit_test(test_satf_off),
      cmocka_unit_test(test_order_independence),
      cmocka_unit_test(test_resize),
      cmocka_unit_test(test_every_light_drawn),
      cmocka_unit_test(test_rejects_bad_input),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
