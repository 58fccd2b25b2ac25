/* test_sequence.c - animation playback through the renderer: snapshots
 * switched into satf_renderer_set_scene, and batch frames with --resume
 * semantics (online/sequence.c). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>
#include <math.h>
#include <png.h>

#include "render_fixture.h"
#include "satf/gl.h"
#include "satf/render.h"
#include "satf/scene.h"
#include "test_util.h"

#define W 160
#define H 120

static satf_db *g_db;
static satf_gl_context *g_ctx;

/* Two clusters side by side; %s is spliced into the first one's instance
 * (its keys, or nothing). */
static const char *SCENE =
    "{\n%s"
    " \"image\": {\"width\": 160, \"height\": 120},\n"
    " \"camera\": {\"position\": [0, 0, 30], \"target\": [0, 0, 0],"
    "  \"up\": [0, 1, 0], \"fov_y\": 40},\n"
    " \"lights\": [{\"type\": \"directional\", \"direction\": [-0.3, -0.2, "
    "-1]}],\n"
    " \"background\": [0.2, 0.2, 0.25],\n"
    " \"effects\": {\"cluster_shadows\": false},\n"
    " \"macro_clusters\": [\n"
    "  {\"prototype\": {\"trajectory\": [[0, 5, 0], [0, -5, 0]], \"a\": 1.2,"
    "    \"b\": 1.0, \"twist\": 0,"
    "    \"shell\": {\"layers\": 3, \"st\": 8, \"su\": 12, \"core\": 0.3},"
    "    \"density\": {\"type\": \"procedural\", \"strands\": 600, \"seed\": 3,"
    "     \"layout\": \"uniform\", \"strand_width\": 0.05}},\n"
    "   \"instances\": [{\"translate\": [-6, 0, 0]%s}]},\n"
    "  {\"prototype\": {\"trajectory\": [[0, 5, 0], [0, -5, 0]], \"a\": 1.0,"
    "    \"b\": 1.0, \"twist\": 0,"
    "    \"shell\": {\"layers\": 3, \"st\": 8, \"su\": 12, \"core\": 0.3},"
    "    \"density\": {\"type\": \"procedural\", \"strands\": 600, \"seed\": 4,"
    "     \"layout\": \"uniform\", \"strand_width\": 0.05}},\n"
    "   \"instances\": [{\"translate\": [6, 0, 0]}]}\n"
    " ]\n}\n";

static satf_scene *scene_with(const char *animation, const char *keys) {
  char json[8192];
  snprintf(json, sizeof json, SCENE, animation, keys);
  return fixture_scene(json);
}

static const char *ANIM =
    " \"animation\": {\"fps\": 24, \"frames\": [1, 9]},\n";

static int setup(void **state) {
  (void)state;
  g_db = fixture_db();
  satf_error err;
  if (!g_db || satf_gl_context_create_headless(W, H, &g_ctx, &err) != SATF_OK)
    return -1;
  return 0;
}

static int teardown(void **state) {
  (void)state;
  satf_gl_context_destroy(g_ctx);
  satf_db_destroy(g_db);
  return 0;
}

static satf_image *render_frame(satf_renderer *r, const satf_scene *anim,
                                double frame, satf_scene **keep) {
  satf_scene *snap = NULL;
  satf_error err;
  assert_int_equal(satf_scene_at_frame(anim, frame, &snap, &err), SATF_OK);
  assert_int_equal(satf_renderer_set_scene(r, snap, NULL, &err), SATF_OK);
  satf_image *img = NULL;
  assert_int_equal(satf_renderer_render_image(r, 0, &img, NULL, &err), SATF_OK);
  satf_scene_destroy(*keep);
  *keep = snap;
  return img;
}

static void identical_keys_render_the_still_frame(void **state) {
  (void)state;
  satf_scene *still = scene_with("", "");
  satf_scene *anim =
      scene_with(ANIM, ", \"keys\": [{\"frame\": 1, \"translate\": [-6, 0, 0]},"
                       " {\"frame\": 9, \"translate\": [-6, 0, 0]}]");
  assert_non_null(still);
  assert_non_null(anim);
  satf_renderer *rs = NULL, *ra = NULL;
  satf_error err;
  assert_int_equal(satf_renderer_create(still, g_db, W, H, 0, &rs, &err),
                   SATF_OK);
  assert_int_equal(satf_renderer_create(anim, g_db, W, H, 0, &ra, &err),
                   SATF_OK);
  satf_image *ref = NULL;
  assert_int_equal(satf_renderer_render_image(rs, 0, &ref, NULL, &err),
                   SATF_OK);
  satf_scene *keep = NULL;
  for (double f = 1; f <= 9; f += 2.5) {
    satf_image *img = render_frame(ra, anim, f, &keep);
    const char *ch[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; c++)
      assert_true(fixture_same_bits(ref, img, ch[c]));
    satf_image_destroy(img);
  }
  satf_image_destroy(ref);
  satf_renderer_destroy(ra);
  satf_scene_destroy(keep);
  satf_renderer_destroy(rs);
  satf_scene_destroy(still);
  satf_scene_destroy(anim);
}

static void a_moving_cluster_changes_only_its_pixels(void **state) {
  (void)state;
  /* the left cluster slides 3 units right; the right one stays */
  satf_scene *anim =
      scene_with(ANIM, ", \"keys\": [{\"frame\": 1, \"translate\": [-6, 0, 0]},"
                       " {\"frame\": 9, \"translate\": [-3, 0, 0]}]");
  assert_non_null(anim);
  satf_renderer *r = NULL;
  satf_error err;
  assert_int_equal(satf_renderer_create(anim, g_db, W, H, 0, &r, &err),
                   SATF_OK);
  satf_scene *keep = NULL;
  satf_image *a = render_frame(r, anim, 1, &keep);
  satf_image *b = render_frame(r, anim, 9, &keep);
  const float *aa = fixture_plane(a, "A"), *ba = fixture_plane(b, "A");
  const float *ar = fixture_plane(a, "R"), *br = fixture_plane(b, "R");
  int changed = 0, right_half_changed = 0, background_changed = 0;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      size_t i = (size_t)y * W + (size_t)x;
      int diff = ar[i] != br[i] || aa[i] != ba[i];
      changed += diff;
      /* the static cluster stands right of the middle, the moving one
       * never crosses it */
      if (x > W / 2 + 4)
        right_half_changed += diff;
      if (aa[i] == 0.0f && ba[i] == 0.0f)
        background_changed += diff;
    }
  assert_true(changed > 100);
  assert_int_equal(right_half_changed, 0);
  assert_int_equal(background_changed, 0);
  satf_image_destroy(a);
  satf_image_destroy(b);
  satf_renderer_destroy(r);
  satf_scene_destroy(keep);
  satf_scene_destroy(anim);
}

static unsigned char *slurp(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  if (!f)
    return NULL;
  fseek(f, 0, SEEK_END);
  long size = ftell(f);
  fseek(f, 0, SEEK_SET);
  unsigned char *buf = malloc((size_t)size + 1);
  *n = fread(buf, 1, (size_t)size, f);
  fclose(f);
  return buf;
}

/* Each thumbnail of the sheet carries its frame number in its top-left
 * corner: a black box with white 3x5 digits, checked by their top rows. */
static void check_sheet_labels(const char *path, int frames) {
  png_image png;
  memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  assert_true(png_image_begin_read_from_file(&png, path));
  png.format = PNG_FORMAT_GRAY;
  unsigned char *px = malloc(PNG_IMAGE_SIZE(png));
  assert_non_null(px);
  assert_true(png_image_finish_read(&png, NULL, px, 0, NULL));
  int tw = (int)png.width / frames, w = (int)png.width;
  assert_true(png.height >= 7);
  for (int i = 0; i < frames; i++) {
    const unsigned char *cell = px + i * tw;
    int digit = i + 1; /* top rows: 1 010, 2 111, 3 111, 4 101, 5 111 */
    assert_int_equal(cell[0], 0); /* the box */
    assert_int_equal(cell[1 * w + 1], digit == 1 ? 0 : 255);
    assert_int_equal(cell[1 * w + 2], digit == 4 ? 0 : 255);
    assert_int_equal(cell[1 * w + 3], digit == 1 ? 0 : 255);
  }
  free(px);
}

/* The frames' EXRs are premultiplied over transparent black; the sheet
 * composites them over the scene's background (0.2, 0.2, 0.25) whether a
 * thumbnail came from the renderer or, resumed, from the file: the
 * bottom-right pixel of every cell (no hair there) is the background. */
static void check_sheet_background(const char *path, int frames) {
  png_image png;
  memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  assert_true(png_image_begin_read_from_file(&png, path));
  png.format = PNG_FORMAT_RGB;
  unsigned char *px = malloc(PNG_IMAGE_SIZE(png));
  assert_non_null(px);
  assert_true(png_image_finish_read(&png, NULL, px, 0, NULL));
  int tw = (int)png.width / frames, w = (int)png.width;
  const double bg[3] = {0.2, 0.2, 0.25};
  for (int i = 0; i < frames; i++) {
    const unsigned char *p =
        px + 3 * ((size_t)(png.height - 1) * w + (size_t)(i + 1) * tw - 1);
    for (int c = 0; c < 3; c++) {
      double want = (1.055 * pow(bg[c], 1.0 / 2.4) - 0.055) * 255.0;
      if (fabs(p[c] - want) > 1.0)
        fail_msg("cell %d channel %d: %d, background %.1f", i, c, p[c], want);
    }
  }
  free(px);
}

static void resume_finishes_a_killed_batch(void **state) {
  (void)state;
  satf_scene *anim =
      scene_with(ANIM, ", \"keys\": [{\"frame\": 1, \"translate\": [-6, 0, 0]},"
                       " {\"frame\": 9, \"translate\": [-3, 0, 0]}]");
  satf_renderer *r = NULL;
  satf_error err;
  assert_int_equal(satf_renderer_create(anim, g_db, W, H, 0, &r, &err),
                   SATF_OK);
  char dir_a[512], dir_b[512], pat_a[600], pat_b[600], sheet[600];
  test_path(dir_a, sizeof dir_a, "seq_full");
  test_path(dir_b, sizeof dir_b, "seq_resumed");
  mkdir(dir_a, 0755);
  mkdir(dir_b, 0755);
  snprintf(pat_a, sizeof pat_a, "%s/f_%%03d.exr", dir_a);
  snprintf(pat_b, sizeof pat_b, "%s/f_%%03d.exr", dir_b);
  snprintf(sheet, sizeof sheet, "%s/sheet.png", dir_b);
  for (int k = 1; k <= 5; k++) { /* a clean start, whatever ran before */
    char old[700];
    snprintf(old, sizeof old, "%s/f_%03d.exr", dir_a, k);
    remove(old);
    snprintf(old, sizeof old, "%s/f_%03d.exr", dir_b, k);
    remove(old);
  }
  satf_sequence_opts full = {1, 5, pat_a, NULL, NULL, 0, 0, 1, 0, NULL};
  satf_sequence_stats st;
  assert_int_equal(satf_sequence_render(r, anim, &full, &st, &err), SATF_OK);
  assert_int_equal(st.rendered, 5);
  /* the "killed" batch: frames 1-2 complete, frame 3 cut short */
  satf_sequence_opts part = {1, 2, pat_b, NULL, NULL, 0, 0, 1, 0, NULL};
  assert_int_equal(satf_sequence_render(r, anim, &part, &st, &err), SATF_OK);
  char f3a[700], f3b[700];
  snprintf(f3a, sizeof f3a, "%s/f_003.exr", dir_a);
  snprintf(f3b, sizeof f3b, "%s/f_003.exr", dir_b);
  size_t n;
  unsigned char *bytes = slurp(f3a, &n);
  assert_non_null(bytes);
  FILE *f = fopen(f3b, "wb");
  fwrite(bytes, 1, n / 2, f);
  fclose(f);
  free(bytes);
  satf_sequence_opts resume = {1, 5, pat_b, NULL, sheet, 1, 0, 1, 0, NULL};
  assert_int_equal(satf_sequence_render(r, anim, &resume, &st, &err), SATF_OK);
  assert_int_equal(st.skipped, 2);
  assert_int_equal(st.rendered, 3);
  for (int k = 1; k <= 5; k++) {
    char fa[700], fb[700];
    snprintf(fa, sizeof fa, "%s/f_%03d.exr", dir_a, k);
    snprintf(fb, sizeof fb, "%s/f_%03d.exr", dir_b, k);
    size_t na, nb;
    unsigned char *ba = slurp(fa, &na), *bb = slurp(fb, &nb);
    assert_non_null(ba);
    assert_non_null(bb);
    assert_int_equal(na, nb);
    assert_memory_equal(ba, bb, na);
    free(ba);
    free(bb);
  }
  struct stat sb;
  assert_int_equal(stat(sheet, &sb), 0);
  assert_true(sb.st_size > 100);
  check_sheet_labels(sheet, 5);
  check_sheet_background(sheet, 5);
  satf_renderer_destroy(r);
  satf_scene_destroy(anim);
}

/* An axis-aligned box as an OBJ file (faces wound outwards). */
static void write_box(const char *path, const float lo[3], const float hi[3]) {
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  for (int c = 0; c < 8; c++)
    fprintf(f, "v %g %g %g\n", (double)(c & 1 ? hi[0] : lo[0]),
            (double)(c & 2 ? hi[1] : lo[1]), (double)(c & 4 ? hi[2] : lo[2]));
  static const int quads[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5},
                                  {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
  for (int q = 0; q < 6; q++)
    fprintf(f, "f %d %d %d\nf %d %d %d\n", quads[q][0], quads[q][1],
            quads[q][2], quads[q][0], quads[q][2], quads[q][3]);
  fclose(f);
}

static satf_image *render_with_box(const char *box, int cluster_shadows) {
  char json[8192], meshes[1024] = "";
  if (box)
    snprintf(meshes, sizeof meshes,
             " \"meshes\": [{\"file\": \"%s\", \"color\": [0.9, 0.1, "
             "0.1]}],\n",
             box);
  snprintf(json, sizeof json, SCENE, meshes, "");
  satf_scene *scene = fixture_scene(json);
  assert_non_null(scene);
  scene->effects.cluster_shadows = cluster_shadows;
  satf_renderer *r = NULL;
  satf_error err;
  assert_int_equal(satf_renderer_create(scene, g_db, W, H, 0, &r, &err),
                   SATF_OK);
  satf_image *img = NULL;
  assert_int_equal(satf_renderer_render_image(r, 0, &img, NULL, &err), SATF_OK);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
  return img;
}

static double mean_over(const satf_image *img, const char *ch, int x0, int x1,
                        int y0, int y1) {
  const float *p = fixture_plane(img, ch);
  double sum = 0;
  for (int y = y0; y < y1; y++)
    for (int x = x0; x < x1; x++)
      sum += p[(size_t)y * W + (size_t)x];
  return sum / ((x1 - x0) * (y1 - y0));
}

static void meshes_occlude_and_shadow_hair(void **state) {
  (void)state;
  char box[512];
  test_path(box, sizeof box, "seq_box.obj");
  /* a red box in front of the left cluster's lower half (camera at z 30) */
  const float lo[3] = {-6, -6, 3}, hi[3] = {-3, -1, 5};
  write_box(box, lo, hi);
  satf_image *plain = render_with_box(NULL, 0);
  satf_image *boxed = render_with_box(box, 0);
  /* the box: opaque red, hiding the hair */
  const float *a = fixture_plane(boxed, "A"), *r = fixture_plane(boxed, "R"),
              *g = fixture_plane(boxed, "G");
  int red = 0;
  for (size_t i = 0; i < (size_t)W * H; i++)
    red += a[i] == 1.0f && r[i] > 3.0f * g[i] && r[i] > 0.05f;
  assert_true(red > 50);
  /* the right cluster, far from the box, is untouched with shadows off */
  assert_true(mean_over(plain, "R", W / 2 + 10, W, 0, H) ==
              mean_over(boxed, "R", W / 2 + 10, W, 0, H));
  /* with the box between the key light and the hair, the left cluster
   * darkens (the light comes from +z, the box is in front of it) */
  char caster[512];
  test_path(caster, sizeof caster, "seq_caster.obj");
  /* up the key light's path from the left cluster's upper half, out of
   * view: only its shadow shows */
  const float clo[3] = {-3.5f, 4.5f, 13.5f}, chi[3] = {-0.5f, 7.5f, 16.5f};
  write_box(caster, clo, chi);
  satf_image *lit = render_with_box(NULL, 1);
  satf_image *shaded = render_with_box(caster, 1);
  /* over the left cluster's pixels */
  const float *pa = fixture_plane(plain, "A");
  const float *lg = fixture_plane(lit, "G"), *sg = fixture_plane(shaded, "G");
  double before = 0, after = 0;
  int n = 0;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W / 2; x++) {
      size_t i = (size_t)y * W + (size_t)x;
      if (pa[i] > 0.5f) {
        before += lg[i];
        after += sg[i];
        n++;
      }
    }
  assert_true(n > 50);
  assert_true(after < 0.99 * before);
  satf_image_destroy(plain);
  satf_image_destroy(boxed);
  satf_image_destroy(lit);
  satf_image_destroy(shaded);
}

static void frame_patterns_are_checked(void **state) {
  (void)state;
  satf_error err;
  assert_int_equal(satf_sequence_check_pattern("out/f_%04d.exr", &err),
                   SATF_OK);
  assert_int_equal(satf_sequence_check_pattern("f%d.exr", &err), SATF_OK);
  assert_int_equal(satf_sequence_check_pattern("out/f.exr", &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_sequence_check_pattern("f_%s.exr", &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_sequence_check_pattern("f_%d_%d.exr", &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "f_%d_%d.exr"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(identical_keys_render_the_still_frame),
      cmocka_unit_test(a_moving_cluster_changes_only_its_pixels),
      cmocka_unit_test(resume_finishes_a_killed_batch),
      cmocka_unit_test(meshes_occlude_and_shadow_hair),
      cmocka_unit_test(frame_patterns_are_checked),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
