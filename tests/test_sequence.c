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

#include "online/gl_context.h"
#include "online/renderer.h"
#include "online/sequence.h"
#include "render_fixture.h"
#include "satf/anim.h"
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
  satf_sequence_opts full = {1, 5, pat_a, NULL, NULL, 0, 0, 1};
  satf_sequence_stats st;
  assert_int_equal(satf_sequence_render(r, anim, &full, &st, &err), SATF_OK);
  assert_int_equal(st.rendered, 5);
  /* the "killed" batch: frames 1-2 complete, frame 3 cut short */
  satf_sequence_opts part = {1, 2, pat_b, NULL, NULL, 0, 0, 1};
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
  satf_sequence_opts resume = {1, 5, pat_b, NULL, sheet, 1, 0, 1};
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
  satf_renderer_destroy(r);
  satf_scene_destroy(anim);
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
      cmocka_unit_test(frame_patterns_are_checked),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
