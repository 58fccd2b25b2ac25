/* test_sparse_strands.c - clusters of few strands drawn as those strands
 * (satf_renderer_set_sparse_strands, online/render/sparse.c): a one-strand
 * "tracks" cluster renders as the strand reference path draws the same
 * strand, and not as SATF's shells do; it is sorted with the clusters'
 * fragments by depth (hidden behind a dense cluster, on top in front of
 * it) in both compositing modes; it moves with its instance; and the
 * setting's bounds are checked. Whole frames on llvmpipe through EGL. */
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
#include "renderer_internal.h"
#include "satf/common.h"
#include "satf/render.h"
#include "test_util.h"

#define W 128
#define H 96
#define DIST 20.0  /* camera on +z, looking at the origin */
#define FOV_Y 30.0 /* degrees */
#define RADIUS 0.1 /* the sparse cluster's a = b */
#define WIDTH 2.0  /* its strand_width: a diameter of 2 radii, 0.2 units */

/* One sparse cluster, a vertical strand along its trajectory at x = X,
 * z = Z (slices 5, the track on the axis), and with `dense` a wide dense
 * procedural cluster at z = DZ behind or in front of it. */
static char *scene_text(float x, float z, int dense, float dz) {
  static char buf[4096];
  char other[1024] = "";
  if (dense)
    snprintf(other, sizeof other,
             ", {\"prototype\": {\"trajectory\": [[0, -3, %g], [0, 3, %g]], "
             "\"a\": 1.5, \"b\": 0.5, \"shell\": {\"layers\": 4, \"st\": 8, "
             "\"su\": 16}, \"density\": {\"strands\": 6000}}}",
             (double)dz, (double)dz);
  snprintf(buf, sizeof buf,
           "{\"macro_clusters\": [{\"prototype\": {"
           "  \"trajectory\": [[%g, -3, %g], [%g, 3, %g]], \"a\": %g,"
           "  \"shell\": {\"layers\": 3, \"st\": 4, \"su\": 8},"
           "  \"density\": {\"type\": \"tracks\", \"slices\": 5,"
           "    \"strand_width\": %g,"
           "    \"tracks\": [[0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]]}}}%s],"
           " \"camera\": {\"position\": [0, 0, 20], \"target\": [0, 0, 0],"
           "              \"fov_y\": 30},"
           " \"lights\": [{\"direction\": [-1, 0, -1]}],"
           " \"background\": [0, 0, 0],"
           " \"image\": {\"width\": 128, \"height\": 96}}",
           (double)x, (double)z, (double)x, (double)z, RADIUS, WIDTH, other);
  return buf;
}

FIXTURE_GL_GROUP(W, H)

static double px_per_unit(void) {
  return 0.5 * H / (DIST * tan(0.5 * FOV_Y * 3.14159265358979 / 180.0));
}

typedef struct how {
  int sparse;    /* satf_renderer_set_sparse_strands, -1: the default */
  int reference; /* draw the strand itself (satf_renderer_set_strands) */
  int ordered;
  /* satf_pixel_filter, pinned: the default AUTO takes another filter for
   * a scene of one strand than for one with a cluster of a hundred */
  int filter;
} how;

/* The image of json drawn so; fragments: the frame's stored fragments,
 * strands: the renderer's stats.strands (either may be NULL). */
static satf_image *render_counted(const fixture_gl *f, const char *json, how h,
                                  long *fragments, long *strands) {
  satf_scene *scene = fixture_scene(json);
  assert_non_null(scene);
  satf_renderer *r = NULL;
  satf_error err;
  if (satf_renderer_create(scene, f->db, W, H, 0, &r, &err) != SATF_OK)
    fail_msg("%s", err.message);
  assert_int_equal(satf_renderer_sparse_strands(r),
                   SATF_SPARSE_STRANDS_DEFAULT);
  if (h.sparse >= 0 &&
      satf_renderer_set_sparse_strands(r, h.sparse, &err) != SATF_OK)
    fail_msg("%s", err.message);
  if (h.ordered)
    satf_renderer_set_composite(r, SATF_COMPOSITE_ORDERED);
  satf_renderer_set_pixel_filter(r, (satf_pixel_filter)h.filter);
  if (h.reference) { /* the cluster's strand: its trajectory, 0.2 wide */
    const float *p = scene->macro_clusters[0].prototype.trajectory;
    int count = 5;
    float xyz[15], w[5];
    for (int j = 0; j < 5; j++) {
      for (int c = 0; c < 3; c++)
        xyz[3 * j + c] = p[c] + (p[3 + c] - p[c]) * (float)j / 4.0f;
      w[j] = (float)(WIDTH * RADIUS);
    }
    if (satf_renderer_set_strands(r, 1, &count, xyz, w, 0.0f, &err) != SATF_OK)
      fail_msg("%s", err.message);
  }
  satf_image *img = NULL;
  satf_frame_timing timing;
  if (satf_renderer_render_image(r, 0, &img, &timing, &err) != SATF_OK)
    fail_msg("%s", err.message);
  if (fragments)
    *fragments = timing.fragments;
  if (strands) {
    satf_render_stats st;
    satf_renderer_stats(r, &st);
    *strands = st.strands;
  }
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
  return img;
}

/* L's passes timed apart (satf_renderer_set_pass_timing): a sparse strand
 * in front of a dense cluster puts time in each of the exact composite's
 * three passes, which lie within L; with the timing off (the default) the
 * frame reports none. */
static void test_pass_timing(void **state) {
  const fixture_gl *f = *state;
  satf_scene *scene = fixture_scene(scene_text(0.0f, 2.0f, 1, -2.0f));
  assert_non_null(scene);
  satf_renderer *r = NULL;
  satf_error err;
  if (satf_renderer_create(scene, f->db, W, H, 0, &r, &err) != SATF_OK)
    fail_msg("%s", err.message);
  assert_int_equal(satf_renderer_pass_timing(r), 0);
  for (int on = 0; on <= 1; on++) {
    satf_renderer_set_pass_timing(r, on);
    assert_int_equal(satf_renderer_pass_timing(r), on);
    satf_frame_timing t;
    if (satf_renderer_render(r, SATF_AOV_BEAUTY, &t, &err) != SATF_OK)
      fail_msg("%s", err.message);
    double sum = t.shells_ms + t.strands_ms + t.resolve_ms;
    if (!on) {
      assert_true(sum == 0.0);
      continue;
    }
    assert_true(t.shells_ms > 0.0);
    assert_true(t.strands_ms > 0.0);
    assert_true(t.resolve_ms > 0.0);
    assert_true(sum <= t.lighting_ms + 1e-3);
  }
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

static satf_image *render(const fixture_gl *f, const char *json, how h) {
  return render_counted(f, json, h, NULL, NULL);
}

static float px(const satf_image *img, const char *ch, int col, int row) {
  return fixture_plane(img, ch)[(size_t)row * W + (size_t)col];
}

/* A scene whose every cluster is drawn as its strands composites them as
 * the strand path does, without the fragment arrays (sparse_composite: no
 * fragment stored), and looks as it does through the arrays, which it
 * takes when a cluster drawn as shells is in the scene (here behind the
 * camera, so it covers nothing): the same strand, every pixel within
 * 2e-3, in the exact mode and the ordered one, through either filter. */
static void test_strands_alone_without_arrays(void **state) {
  for (int mode = 0; mode < 4; mode++) {
    int ordered = mode & 1;
    how h = {-1, 0, ordered,
             mode >> 1 ? SATF_PIXEL_FILTER_BLACKMAN_HARRIS
                       : SATF_PIXEL_FILTER_BOX};
    long alone = -1, arrays = -1;
    satf_image *a = render_counted(*state, scene_text(0.0f, 0.0f, 0, 0.0f), h,
                                   &alone, NULL);
    satf_image *b = render_counted(*state, scene_text(0.0f, 0.0f, 1, 100.0f), h,
                                   &arrays, NULL);
    double worst = 0.0, covered = 0.0;
    const char *ch[4] = {"R", "G", "B", "A"};
    for (int k = 0; k < 4; k++)
      for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
          double d = fabs(px(a, ch[k], x, y) - px(b, ch[k], x, y));
          worst = d > worst ? d : worst;
          covered += k == 3 ? px(a, "A", x, y) : 0.0;
        }
    printf("%s, %s: fragments stored %ld alone, %ld with a shell cluster; "
           "largest difference %.2e over %.1f pixels of coverage\n",
           ordered ? "ordered" : "exact", mode >> 1 ? "Blackman-Harris" : "box",
           alone, arrays, worst, covered);
    assert_true(covered > 50.0);
    assert_true(worst < 2e-3);
    if (!ordered) {
      assert_int_equal(alone, 0);
      assert_true(arrays > 100);
    }
    satf_image_destroy(a);
    satf_image_destroy(b);
  }
}

/* The default pixel filter, AUTO, reads the hair's strands from the
 * renderer's stats (stats.strands) in the cluster path: the scene's one sparse
 * cluster of one strand is drawn through Blackman-Harris, pixel for pixel,
 * which differs from the box; with the procedural cluster of 6,000 strands
 * behind the camera the same strand is drawn through the box. */
static void test_auto_filter_of_sparse_clusters(void **state) {
  for (int dense = 0; dense <= 1; dense++) {
    const char *json = scene_text(0.0f, 0.0f, dense, 100.0f);
    satf_image *img[3];
    long strands[3];
    for (int f = 0; f < 3; f++)
      img[f] =
          render_counted(*state, json, (how){-1, 0, 0, f}, NULL, &strands[f]);
    /* a tracks cluster counts its one member strand, the procedural one
     * its density's 6,000 */
    assert_int_equal(strands[SATF_PIXEL_FILTER_AUTO], dense ? 6001 : 1);
    double to_bh = 0.0, to_box = 0.0;
    for (int y = 0; y < H; y++)
      for (int x = 0; x < W; x++) {
        float a = px(img[SATF_PIXEL_FILTER_AUTO], "A", x, y);
        to_bh = fmax(to_bh, fabs(a - px(img[SATF_PIXEL_FILTER_BLACKMAN_HARRIS],
                                        "A", x, y)));
        to_box =
            fmax(to_box, fabs(a - px(img[SATF_PIXEL_FILTER_BOX], "A", x, y)));
      }
    printf("%s: auto against Blackman-Harris %.2e, against the box %.2e\n",
           dense ? "6,001 strands" : "1 strand", to_bh, to_box);
    assert_true(dense ? to_box < 1e-6 : to_bh < 1e-6);
    assert_true(dense ? to_bh > 0.05 : to_box > 0.05);
    for (int f = 0; f < 3; f++)
      satf_image_destroy(img[f]);
  }
}

/* Alpha summed over a row, and its centre column. */
static double row_alpha(const satf_image *img, int row, double *centre) {
  double s = 0.0, m = 0.0;
  for (int c = 0; c < W; c++) {
    s += px(img, "A", c, row);
    m += c * px(img, "A", c, row);
  }
  if (centre)
    *centre = s > 0.0 ? m / s : -1.0;
  return s;
}

/* The sparse cluster is its strand: the strand reference path's image
 * within rounding; its alpha across a row is the strand's width in
 * pixels. Drawn as a cluster (sparse strands 0) it is not (a one-strand
 * cluster as thin as its strand is close: 1.91 px of alpha for 1.79). */
static void test_sparse_cluster_is_its_strand(void **state) {
  const char *json = scene_text(0.0f, 0.0f, 0, 0.0f);
  satf_image *sparse =
      render(*state, json, (how){-1, 0, 0, SATF_PIXEL_FILTER_BOX});
  satf_image *ref =
      render(*state, json, (how){-1, 1, 0, SATF_PIXEL_FILTER_BOX});
  satf_image *cluster =
      render(*state, json, (how){0, 0, 0, SATF_PIXEL_FILTER_BOX});
  double width_px = WIDTH * RADIUS * px_per_unit();
  for (int row = 30; row <= 66; row += 12) {
    double a = row_alpha(sparse, row, NULL), b = row_alpha(ref, row, NULL);
    double c = row_alpha(cluster, row, NULL);
    printf("row %d: alpha across the strand %.3f (reference %.3f, width "
           "%.3f px), as a cluster %.3f\n",
           row, a, b, width_px, c);
    assert_near(a, width_px, 0.1 * width_px);
    assert_near(a, b, 0.02);
  }
  double d_ref = fixture_max_diff(sparse, ref, "A");
  double d_cluster = fixture_max_diff(cluster, ref, "A");
  double d_rgb = fixture_max_diff(sparse, ref, "G");
  double d_cluster_rgb = fixture_max_diff(cluster, ref, "G");
  printf("max |alpha - reference|: sparse %.4f, as a cluster %.4f; max "
         "|G - reference| %.4f, as a cluster %.4f\n",
         d_ref, d_cluster, d_rgb, d_cluster_rgb);
  assert_true(d_ref < 0.01);
  assert_true(d_rgb < 0.01);
  /* the shells' records are not the strand: this tells the two apart */
  assert_true(d_cluster > 0.03 || d_cluster_rgb > 0.03);
  satf_image_destroy(sparse);
  satf_image_destroy(ref);
  satf_image_destroy(cluster);
}

/* Mean |difference| of two images' R over the strand's columns. */
static double strand_diff(const satf_image *a, const satf_image *b) {
  double s = 0.0;
  int n = 0;
  for (int row = 30; row <= 66; row++)
    for (int c = W / 2 - 2; c <= W / 2 + 1; c++, n++)
      s += fabs(px(a, "R", c, row) - px(b, "R", c, row));
  return s / n;
}

/* In front of a dense cluster the strand shows; behind it, it barely
 * does: its fragments are sorted with the cluster's (exact mode), or drawn
 * in its instance's place far to near (ordered mode). The reference for
 * both is the dense cluster alone (the strand moved out of the picture). */
static void test_sparse_strand_sorted_with_clusters(void **state) {
  for (int ordered = 0; ordered < 2; ordered++) {
    how h = {-1, 0, ordered, SATF_PIXEL_FILTER_BOX};
    satf_image *alone = render(*state, scene_text(40.0f, 0.0f, 1, 0.0f), h);
    satf_image *front = render(*state, scene_text(0.0f, 2.0f, 1, 0.0f), h);
    satf_image *back = render(*state, scene_text(0.0f, -2.0f, 1, 0.0f), h);
    double df = strand_diff(front, alone), db = strand_diff(back, alone);
    printf("%s: strand in front changes the cluster by %.4f, behind by "
           "%.4f (cluster alpha %.3f)\n",
           ordered ? "ordered" : "exact", df, db, px(alone, "A", W / 2, H / 2));
    assert_true(px(alone, "A", W / 2, H / 2) > 0.7f);
    assert_true(df > 0.01);
    assert_true(db < 0.5 * df);
    satf_image_destroy(alone);
    satf_image_destroy(front);
    satf_image_destroy(back);
  }
}

/* Where a strand covers a pixel whole it is opaque there: the exact mode
 * writes those fragments' depth first (sparse_opaque_depth), and nothing
 * behind them is stored (the ponytail drawn as its strands: 4.2 fragments
 * a pixel without, 0.26 with). The strand here, 2.4 pixels wide, lies in
 * front of the whole cluster (a cluster's fragment has its proxy's depth,
 * the front of the hull holding its hair: a strand at z = 2 is behind
 * that, and hides nothing). Without the pre-pass nothing is hidden. The
 * strand's own fragments are counted with the cluster behind the camera:
 * a scene of strands alone has no fragment arrays (sparse_composite). */
static void test_opaque_strand_hides_what_is_behind(void **state) {
  how h = {-1, 0, 0, SATF_PIXEL_FILTER_BOX};
  long alone, strand, front;
  satf_image *a =
      render_counted(*state, scene_text(40.0f, 0.0f, 1, 0.0f), h, &alone, NULL);
  satf_image *b = render_counted(*state, scene_text(0.0f, 5.0f, 1, 100.0f), h,
                                 &strand, NULL);
  satf_image *c =
      render_counted(*state, scene_text(0.0f, 5.0f, 1, 0.0f), h, &front, NULL);
  long hidden = alone + strand - front;
  printf("fragments: cluster %ld, strand %ld, strand in front of the "
         "cluster %ld (%ld hidden behind it)\n",
         alone, strand, front, hidden);
  assert_true(strand > 100 && alone > 1000);
  assert_true(hidden >= 40);
  satf_image_destroy(a);
  satf_image_destroy(b);
  satf_image_destroy(c);
}

/* A new scene (an animation's next frame) with the cluster moved one unit
 * along x moves its strand by that many pixels. */
static void test_sparse_strand_moves_with_scene(void **state) {
  fixture_gl *f = *state;
  satf_scene *a = fixture_scene(scene_text(0.0f, 0.0f, 0, 0.0f));
  satf_scene *b = fixture_scene(scene_text(1.0f, 0.0f, 0, 0.0f));
  assert_non_null(a);
  assert_non_null(b);
  satf_renderer *r = NULL;
  satf_error err;
  if (satf_renderer_create(a, f->db, W, H, 0, &r, &err) != SATF_OK)
    fail_msg("%s", err.message);
  double c0, c1;
  satf_image *img = NULL;
  if (satf_renderer_render_image(r, 0, &img, NULL, &err) != SATF_OK)
    fail_msg("%s", err.message);
  row_alpha(img, H / 2, &c0);
  satf_image_destroy(img);
  if (satf_renderer_set_scene(r, b, NULL, &err) != SATF_OK)
    fail_msg("%s", err.message);
  if (satf_renderer_render_image(r, 0, &img, NULL, &err) != SATF_OK)
    fail_msg("%s", err.message);
  row_alpha(img, H / 2, &c1);
  satf_image_destroy(img);
  printf("strand centre column %.3f, moved %.3f (expected %.3f)\n", c0, c1 - c0,
         px_per_unit());
  assert_near(c1 - c0, px_per_unit(), 0.3);
  satf_renderer_destroy(r);
  satf_scene_destroy(a);
  satf_scene_destroy(b);
}

static void test_sparse_setting_bounds(void **state) {
  fixture_gl *f = *state;
  satf_scene *s = fixture_scene(scene_text(0.0f, 0.0f, 0, 0.0f));
  assert_non_null(s);
  satf_renderer *r = NULL;
  satf_error err;
  if (satf_renderer_create(s, f->db, W, H, 0, &r, &err) != SATF_OK)
    fail_msg("%s", err.message);
  assert_int_equal(satf_renderer_set_sparse_strands(r, -1, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "sparse strands"));
  assert_int_equal(
      satf_renderer_set_sparse_strands(r, SATF_SPARSE_STRANDS_MAX + 1, &err),
      SATF_ERR_ARGUMENT);
  assert_int_equal(satf_renderer_sparse_strands(r),
                   SATF_SPARSE_STRANDS_DEFAULT);
  assert_int_equal(satf_renderer_set_sparse_strands(r, 0, &err), SATF_OK);
  assert_int_equal(satf_renderer_sparse_strands(r), 0);
  satf_renderer_destroy(r);
  satf_scene_destroy(s);
}

/* A frame of r; the deep opacity map's slab it drew. */
static float frame_slab(satf_renderer *r) {
  satf_image *img = NULL;
  satf_error err;
  if (satf_renderer_render_image(r, 0, &img, NULL, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_image_destroy(img);
  return r->dom.slab;
}

/* The strand path with one strand along the clusters' axis (x = z = 0),
 * `width` wide, or (width 0) back to the clusters. */
static void strand_path(satf_renderer *r, float width) {
  const int counts[1] = {2};
  const float xyz[6] = {0, -3, 0, 0, 3, 0}, w[2] = {width, width};
  satf_error err;
  if (satf_renderer_set_strands(r, width > 0.0f, counts, xyz, w, 0.0f, &err) !=
      SATF_OK)
    fail_msg("%s", err.message);
}

/* The deep opacity map's slab follows the clusters drawn with shells
 * (hierarchy_shell_radius): a shell cluster puts all its alpha at its
 * outer shell's depth, so a slab of the thin sparse cluster's scale
 * would darken its inner layers with its whole optical depth. Drawn as
 * its strand, the sparse cluster (radius 0.1) does not count; drawn as a
 * cluster (sparse strands 0), it does: the mean of 0.1 and 1.5. */
static void test_dom_slab_of_shell_clusters(void **state) {
  fixture_gl *f = *state;
  satf_scene *s = fixture_scene(scene_text(0.0f, 0.0f, 1, 0.0f));
  assert_non_null(s);
  satf_renderer *r = fixture_renderer(s, f->db, W, H, 0);
  assert_non_null(r);
  float slab = frame_slab(r);
  assert_float_equal(hierarchy_shell_radius(r, NULL), 1.5f, 1e-6f);
  /* the strand path of the same scene takes its slab from the shell
   * clusters too, half of theirs (strands.c: a slab from every cluster's
   * mean radius, here 0.8, leaves the shared ponytail's strands at 0.73
   * of Cycles' luminance) */
  strand_path(r, 0.2f);
  float strands = frame_slab(r);
  printf("slab of the clusters %.5f, of their strand path %.5f\n", (double)slab,
         (double)strands);
  assert_float_equal(strands, 0.5f * slab, 1e-4f * slab);
  strand_path(r, 0.0f);
  satf_error err;
  assert_int_equal(satf_renderer_set_sparse_strands(r, 0, &err), SATF_OK);
  assert_float_equal(hierarchy_shell_radius(r, NULL), 0.8f, 1e-6f);
  float all = frame_slab(r);
  printf("slab with the sparse cluster as its strand %.5f, as a cluster "
         "%.5f\n",
         (double)slab, (double)all);
  assert_float_equal(all, slab * 0.8f / 1.5f, 1e-4f * slab);
  satf_renderer_destroy(r);
  satf_scene_destroy(s);
}

/* Two dense clusters of radius `a`, 40 units apart: hair whose clusters
 * are thin against its size. */
static satf_scene *thin_pair(float a) {
  char buf[1024];
  snprintf(buf, sizeof buf,
           "{\"macro_clusters\": ["
           "{\"prototype\": {\"trajectory\": [[-20, -3, 0], [-20, 3, 0]],"
           " \"a\": %g, \"shell\": {\"layers\": 3, \"st\": 4, \"su\": 8},"
           " \"density\": {\"strands\": 400}}},"
           "{\"prototype\": {\"trajectory\": [[20, -3, 0], [20, 3, 0]],"
           " \"a\": %g, \"shell\": {\"layers\": 3, \"st\": 4, \"su\": 8},"
           " \"density\": {\"strands\": 400}}}],"
           " \"camera\": {\"position\": [0, 0, 90], \"target\": [0, 0, 0],"
           "              \"fov_y\": 40},"
           " \"lights\": [{\"direction\": [-1, 0, -1]}],"
           " \"background\": [0, 0, 0]}",
           (double)a, (double)a);
  return fixture_scene(buf);
}

/* Hair cut into thinner clusters is the same hair, and the light falls
 * off through it over the same depth: the slab's scale stops at
 * SHELL_RADIUS_FLOOR of the hair's bounding radius, so clusters of radius
 * 0.2 and 0.4 (both under it) get the same slab, where their mean radii
 * would have made the one half the other; clusters above it keep their
 * own (test_dom_slab_of_shell_clusters). */
static void test_dom_slab_floor(void **state) {
  fixture_gl *f = *state;
  float slab[2], scale[2], floor_r[2];
  for (int k = 0; k < 2; k++) {
    satf_scene *s = thin_pair(k ? 0.4f : 0.2f);
    assert_non_null(s);
    satf_renderer *r = fixture_renderer(s, f->db, W, H, 0);
    assert_non_null(r);
    int shells = 0;
    float c[3];
    scale[k] = hierarchy_shell_radius(r, &shells);
    floor_r[k] = SHELL_RADIUS_FLOOR * view_radius(&r->view, c);
    assert_int_equal(shells, 2);
    slab[k] = frame_slab(r);
    satf_renderer_destroy(r);
    satf_scene_destroy(s);
  }
  printf("floor %.4f %.4f: scale %.4f %.4f, slab %.5f %.5f\n",
         (double)floor_r[0], (double)floor_r[1], (double)scale[0],
         (double)scale[1], (double)slab[0], (double)slab[1]);
  assert_true(floor_r[0] > 0.4f && floor_r[1] > 0.4f);
  assert_float_equal(scale[0], floor_r[0], 1e-6f);
  assert_float_equal(scale[1], floor_r[1], 1e-6f);
  assert_float_equal(slab[0], slab[1], 0.02f * slab[0]);
}

/* In a scene without shell clusters the cluster path draws the same
 * strands as the strand path, with the same slabs (strands.c): here a
 * sparse cluster of radius 3, whose slab (a third of it) is deeper than
 * its strand is wide. */
static void test_dom_slab_without_shells(void **state) {
  fixture_gl *f = *state;
  satf_scene *s = fixture_scene(
      "{\"macro_clusters\": [{\"prototype\": {"
      "  \"trajectory\": [[0, -3, 0], [0, 3, 0]], \"a\": 3,"
      "  \"shell\": {\"layers\": 3, \"st\": 4, \"su\": 8},"
      "  \"density\": {\"type\": \"tracks\", \"slices\": 5,"
      "    \"strand_width\": 0.05,"
      "    \"tracks\": [[0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]]}}}],"
      " \"camera\": {\"position\": [0, 0, 20], \"target\": [0, 0, 0],"
      "              \"fov_y\": 30},"
      " \"lights\": [{\"direction\": [-1, 0, -1]}],"
      " \"background\": [0, 0, 0]}");
  assert_non_null(s);
  satf_renderer *r = fixture_renderer(s, f->db, W, H, 0);
  assert_non_null(r);
  float slab = frame_slab(r);
  strand_path(r, 0.15f);
  float strands = frame_slab(r);
  printf("no shells: slab of the clusters %.5f, of the strand path %.5f\n",
         (double)slab, (double)strands);
  assert_true(slab > 0.0f);
  assert_float_equal(strands, slab, 1e-4f * slab);
  satf_renderer_destroy(r);
  satf_scene_destroy(s);
}

/* The deep opacity map's last layer holds all the hair beyond its third
 * slab, read as spread from there to the texel's last hair
 * (glsl/dom_behind.glsl). Along the light, which comes from +x +z: a
 * strand F in front, the probed strand P five slabs behind it (in the last
 * layer) and four strands G about forty slabs behind P. F shadows P; G,
 * behind P, must not: read as one slab deep, the last layer counted G in
 * front of P and took P's luminance to 2% of its value without G. kk
 * strand path; P's luminance over its columns. */
static double probe_luminance(const fixture_gl *f, int front, int behind) {
  const float a = 0.35f, g = 3.0f; /* 5 and about 42 slabs of 0.1 */
  float xyz[6 * 6], w[6 * 2];
  int counts[6], n = 0;
  const float at[6][2] = {{0, 0},   {a, a},   {-g, -g},
                          {-g, -g}, {-g, -g}, {-g, -g}};
  for (int k = 0; k < 6; k++) {
    if ((k == 1 && !front) || (k >= 2 && !behind))
      continue;
    for (int j = 0; j < 2; j++) {
      float *p = xyz + 6 * n + 3 * j;
      p[0] = at[k][0];
      p[1] = j ? 3.0f : -3.0f;
      p[2] = at[k][1];
      w[2 * n + j] = 0.1f;
    }
    counts[n++] = 2;
  }
  satf_scene *s = fixture_scene(scene_text(0.0f, 0.0f, 0, 0.0f));
  assert_non_null(s);
  satf_renderer *r = fixture_renderer(s, f->db, W, H, 0);
  assert_non_null(r);
  satf_error err;
  if (satf_renderer_set_strands(r, n, counts, xyz, w, 0.0f, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_image *img = NULL;
  if (satf_renderer_render_image(r, 0, &img, NULL, &err) != SATF_OK)
    fail_msg("%s", err.message);
  double sum = 0.0;
  for (int y = H / 2 - 16; y < H / 2 + 16; y++)
    for (int x = W / 2 - 2; x < W / 2 + 2; x++)
      sum += 0.2126 * px(img, "R", x, y) + 0.7152 * px(img, "G", x, y) +
             0.0722 * px(img, "B", x, y);
  printf("probe: front %d behind %d: slab %.4f, luminance %.4f\n", front,
         behind, (double)r->dom.slab, sum);
  satf_image_destroy(img);
  satf_renderer_destroy(r);
  satf_scene_destroy(s);
  return sum;
}

static void test_dom_hair_behind_casts_no_shadow(void **state) {
  double alone = probe_luminance(*state, 0, 0);
  double shadowed = probe_luminance(*state, 1, 0);
  double both = probe_luminance(*state, 1, 1);
  assert_true(alone > 0.0);
  assert_true(shadowed < 0.8 * alone);
  assert_true(both > 0.95 * shadowed);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sparse_cluster_is_its_strand),
      cmocka_unit_test(test_sparse_strand_sorted_with_clusters),
      cmocka_unit_test(test_opaque_strand_hides_what_is_behind),
      cmocka_unit_test(test_sparse_strand_moves_with_scene),
      cmocka_unit_test(test_sparse_setting_bounds),
      cmocka_unit_test(test_strands_alone_without_arrays),
      cmocka_unit_test(test_pass_timing),
      cmocka_unit_test(test_auto_filter_of_sparse_clusters),
      cmocka_unit_test(test_dom_slab_of_shell_clusters),
      cmocka_unit_test(test_dom_slab_floor),
      cmocka_unit_test(test_dom_slab_without_shells),
      cmocka_unit_test(test_dom_hair_behind_casts_no_shadow),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
