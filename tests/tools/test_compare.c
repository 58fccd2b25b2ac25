/* test_compare.c - satf-compare's measures (tools/satf-compare/metrics.h)
 * on images built here, whose figures are known by hand. */
#include "test_util.h"

#include "metrics.h"
#include "satf/common.h"

enum { W = 48, H = 32 };

/* Owned planes behind a compare_image. */
typedef struct img {
  float r[W * H], g[W * H], b[W * H], a[W * H];
  compare_image view;
} img;

static img *make(const char *name) {
  img *m = calloc(1, sizeof *m);
  assert_non_null(m);
  m->view = (compare_image){name, W, H, m->r, m->g, m->b, m->a};
  return m;
}

/* A textured hair-like patch: alpha 1 inside a disc, colour a smooth
 * pattern of stripes and a gradient (premultiplied: alpha is 1 or 0), so
 * SSIM has structure to compare. */
static img *patch(const char *name) {
  img *m = make(name);
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      int i = y * W + x;
      double dx = x - W / 2.0, dy = y - H / 2.0;
      if (dx * dx + dy * dy > 14.0 * 14.0)
        continue;
      double v = 0.3 + 0.25 * sin(x * 0.9 + y * 0.3) + 0.01 * y;
      m->a[i] = 1.0f;
      m->r[i] = (float)(0.9 * v);
      m->g[i] = (float)(0.6 * v);
      m->b[i] = (float)(0.3 * v);
    }
  return m;
}

static img *copy(const img *src, const char *name) {
  img *m = make(name);
  memcpy(m->r, src->r, sizeof m->r);
  memcpy(m->g, src->g, sizeof m->g);
  memcpy(m->b, src->b, sizeof m->b);
  memcpy(m->a, src->a, sizeof m->a);
  return m;
}

static void measure(const img *ref, const img *test, compare_result *r) {
  satf_error err;
  satf_status st = compare_measure(&ref->view, &test->view, r, &err);
  if (st != SATF_OK)
    print_error("%s\n", err.message);
  assert_int_equal(st, SATF_OK);
}

static void identical_images_agree_fully(void **state) {
  (void)state;
  img *a = patch("a.exr"), *b = copy(a, "b.exr");
  compare_result r;
  measure(a, b, &r);
  assert_near(r.iou, 1.0, 1e-12);
  assert_near(r.alpha_error, 0.0, 1e-12);
  assert_near(r.ssim, 1.0, 1e-12);
  assert_near(r.lum_ratio, 1.0, 1e-12);
  assert_near(r.chroma_deg, 0.0, 1e-9);
  assert_true(r.union_px > 500 && r.union_px == r.both_px);
  free(a), free(b);
}

/* The reference covers everything, the test its left half: the min sums to
 * half the max, exactly. */
static void half_coverage_is_iou_one_half(void **state) {
  (void)state;
  img *a = make("full.exr"), *b = make("half.exr");
  for (int i = 0; i < W * H; i++) {
    a->a[i] = 1.0f;
    a->r[i] = a->g[i] = a->b[i] = 0.5f;
    if (i % W < W / 2) {
      b->a[i] = 1.0f;
      b->r[i] = b->g[i] = b->b[i] = 0.5f;
    }
  }
  compare_result r;
  measure(a, b, &r);
  assert_true(r.iou == 0.5);
  assert_true(r.alpha_error == 0.5); /* over the union: every pixel */
  assert_int_equal(r.union_px, W * H);
  assert_int_equal(r.both_px, W * H / 2);
  assert_near(r.lum_ratio, 0.5, 1e-12);
  assert_near(r.chroma_deg, 0.0, 1e-9);
  /* soft coverage: alpha 0.25 against 1 counts a quarter */
  for (int i = 0; i < W * H; i++)
    b->a[i] = 0.25f;
  measure(a, b, &r);
  assert_near(r.iou, 0.25, 1e-12);
  free(a), free(b);
}

/* Twice as bright: the same structure once exposure is normalised, and the
 * ratio says 2. */
static void brightness_scale_shows_in_ratio_not_ssim(void **state) {
  (void)state;
  img *a = patch("a.exr"), *b = copy(a, "b.exr");
  for (int i = 0; i < W * H; i++) {
    b->r[i] *= 2.0f;
    b->g[i] *= 2.0f;
    b->b[i] *= 2.0f;
  }
  compare_result r;
  measure(a, b, &r);
  assert_near(r.ssim, 1.0, 1e-9);
  assert_near(r.lum_ratio, 2.0, 1e-9);
  assert_near(r.exposure, 0.5, 1e-9);
  assert_near(r.iou, 1.0, 1e-12);
  assert_near(r.chroma_deg, 0.0, 1e-6);
  free(a), free(b);
}

/* Yellow (1, 1, 0) against magenta (1, 0, 1) at equal alpha, every pixel
 * scaled alike: cos = 1 / (sqrt 2 sqrt 2) = 1/2, 60 degrees. */
static void hue_shift_gives_its_angle(void **state) {
  (void)state;
  img *a = patch("a.exr"), *b = copy(a, "b.exr");
  for (int i = 0; i < W * H; i++) {
    float v = a->r[i];
    a->r[i] = v, a->g[i] = v, a->b[i] = 0.0f;
    b->r[i] = v, b->g[i] = 0.0f, b->b[i] = v;
  }
  compare_result r;
  measure(a, b, &r);
  assert_near(r.chroma_deg, 60.0, 1e-9);
  assert_near(r.iou, 1.0, 1e-12);
  /* pure red against pure green: a right angle */
  for (int i = 0; i < W * H; i++) {
    float v = a->r[i];
    a->g[i] = 0.0f;
    b->r[i] = 0.0f, b->g[i] = v, b->b[i] = 0.0f;
  }
  measure(a, b, &r);
  assert_near(r.chroma_deg, 90.0, 1e-9);
  free(a), free(b);
}

/* A pattern against its photographic negative (same mean, so exposure
 * leaves it): anti-correlated structure gives an SSIM well below zero; a
 * half-pixel blur of it lands in between. The measure can fail. */
static void different_structure_lowers_ssim(void **state) {
  (void)state;
  img *a = make("a.exr"), *b = make("b.exr"), *c = make("c.exr");
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      int i = y * W + x;
      float v = ((x / 2 + y / 2) % 2) ? 0.8f : 0.2f;
      a->a[i] = b->a[i] = c->a[i] = 1.0f;
      a->r[i] = a->g[i] = a->b[i] = v;
      b->r[i] = b->g[i] = b->b[i] = 1.0f - v;
    }
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      int i = y * W + x, j = y * W + (x + 1 < W ? x + 1 : x);
      c->r[i] = c->g[i] = c->b[i] = 0.5f * (a->r[i] + a->r[j]);
    }
  compare_result r;
  measure(a, b, &r);
  assert_true(r.ssim < -0.5);
  assert_near(r.lum_ratio, 1.0, 1e-6); /* 0.2f + 0.8f in float */
  measure(a, c, &r);
  assert_true(r.ssim > 0.2 && r.ssim < 0.95);
  free(a), free(b), free(c);
}

/* SSIM4 averages 4x4 pixel blocks first: a one-pixel checkerboard against
 * its negative is anti-correlated pixel by pixel (SSIM well below zero)
 * but the same grey at a wisp's scale (SSIM4 1), while squares of 8
 * pixels against their negative stay anti-correlated at both scales. */
static void ssim4_sees_blocks_not_pixels(void **state) {
  (void)state;
  for (int size = 1; size <= 8; size += 7) {
    img *a = make("a.exr"), *b = make("b.exr");
    for (int y = 0; y < H; y++)
      for (int x = 0; x < W; x++) {
        int i = y * W + x;
        float v = ((x / size + y / size) % 2) ? 0.8f : 0.2f;
        a->a[i] = b->a[i] = 1.0f;
        a->r[i] = a->g[i] = a->b[i] = v;
        b->r[i] = b->g[i] = b->b[i] = 1.0f - v;
      }
    compare_result r;
    measure(a, b, &r);
    assert_true(r.ssim < -0.5);
    if (size == 1)
      assert_near(r.ssim4, 1.0, 1e-6);
    else
      assert_true(r.ssim4 < -0.5);
    measure(a, a, &r);
    assert_near(r.ssim4, 1.0, 1e-12);
    free(a), free(b);
  }
}

static void mismatched_sizes_are_refused(void **state) {
  (void)state;
  img *a = patch("ref.exr"), *b = copy(a, "small.exr");
  b->view.width = W / 2;
  compare_result r;
  satf_error err;
  assert_int_equal(compare_measure(&a->view, &b->view, &r, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "ref.exr is 48x32"));
  assert_non_null(strstr(err.message, "small.exr is 24x32"));
  free(a), free(b);
}

static void empty_frames_and_nan_are_reported(void **state) {
  (void)state;
  img *a = make("a.exr"), *b = make("b.exr");
  compare_result r;
  measure(a, b, &r);
  assert_int_equal(r.union_px, 0);
  assert_true(isnan(r.lum_ratio));
  assert_near(r.ssim, 0.0, 0.0);
  assert_near(r.chroma_deg, 90.0, 0.0);
  b->g[5 * W + 7] = NAN;
  satf_error err;
  assert_int_equal(compare_check_finite(&b->view, &err), SATF_ERR_CORRUPT);
  assert_non_null(strstr(err.message, "b.exr: pixel (7, 5) channel G"));
  assert_int_equal(compare_check_finite(&a->view, &err), SATF_OK);
  free(a), free(b);
}

/* The white point: the 99.5th percentile of the reference's luminance in
 * the union, interpolated as numpy.percentile does. 200 covered pixels of
 * luminance 0, 1, ..., 199 (grey, so luminance = the value): position
 * 0.995 * 199 = 198.005 -> 198.005. */
static void white_point_is_numpy_percentile(void **state) {
  (void)state;
  img *a = make("a.exr"), *b = make("b.exr");
  for (int i = 0; i < 200; i++) {
    a->a[i] = b->a[i] = 1.0f;
    a->r[i] = a->g[i] = a->b[i] = (float)i;
    b->r[i] = b->g[i] = b->b[i] = (float)i;
  }
  compare_result r;
  measure(a, b, &r);
  assert_near(r.white, 198.005, 1e-9);
  assert_int_equal(r.box[0], 0);
  assert_int_equal(r.box[2], W - 1);
  assert_int_equal(r.box[1], 0);
  assert_int_equal(r.box[3], 199 / W);
  free(a), free(b);
}

/* The EXRs the command-line tests of satf-compare read (tests/tools/
 * CMakeLists.txt, fixture compare_input): a patch, its copy, the copy twice
 * as bright, a full frame and its left half, and a frame of another size;
 * half floats with ZIP, as satf-render writes them. */
static void write_exr(const img *m, const char *name, int width) {
  char path[512];
  satf_exr_channel ch[4] = {{"A", m->a}, {"B", m->b}, {"G", m->g}, {"R", m->r}};
  satf_exr_write_opts opts = {EXR_PIXEL_HALF, EXR_COMPRESSION_ZIP, NULL, NULL,
                              0};
  satf_error err;
  satf_status st = satf_exr_write(test_path(path, sizeof path, name), width, H,
                                  ch, 4, &opts, &err);
  if (st != SATF_OK)
    print_error("%s\n", err.message);
  assert_int_equal(st, SATF_OK);
}

static void writes_cli_inputs(void **state) {
  (void)state;
  img *a = patch("a"), *b = copy(a, "b"), *full = make("f"), *half = make("h");
  for (int i = 0; i < W * H; i++) {
    b->r[i] *= 2.0f, b->g[i] *= 2.0f, b->b[i] *= 2.0f;
    full->a[i] = 1.0f;
    full->r[i] = full->g[i] = full->b[i] = 0.5f;
    if (i % W < W / 2) {
      half->a[i] = 1.0f;
      half->r[i] = half->g[i] = half->b[i] = 0.5f;
    }
  }
  write_exr(a, "cmp_ref.exr", W);
  write_exr(a, "cmp_same.exr", W);
  write_exr(b, "cmp_bright.exr", W);
  write_exr(full, "cmp_full.exr", W);
  write_exr(half, "cmp_half.exr", W);
  write_exr(a, "cmp_small.exr", W / 2); /* 24x32 of the planes' start */
  free(a), free(b), free(full), free(half);
}

/* One-pixel stripes (columns of alpha 1 and 0, white where covered)
 * against themselves blurred by a 3x3 box: per row, the blurred columns
 * are 2/3 at x = 0, then 1/3 under the covered columns and 2/3 under the
 * empty ones, and 1/3 at x = 47 (edges clamped), so sum min = 2/3 + 23/3
 * and sum max = 1 + 23 + 23 (2/3) + 1/3: IoU 25 / 119. A flat frame is
 * its own blur: the bound is 1. */
static void smooth_bound_of_stripes_and_flat(void **state) {
  (void)state;
  img *stripes = make("stripes"), *flat = make("flat");
  for (int i = 0; i < W * H; i++) {
    float v = (i % W) % 2 == 0 ? 1.0f : 0.0f;
    stripes->r[i] = stripes->g[i] = stripes->b[i] = stripes->a[i] = v;
    flat->a[i] = 1.0f;
    flat->r[i] = flat->g[i] = flat->b[i] = 0.5f;
  }
  compare_result r;
  satf_error err;
  assert_int_equal(compare_smooth_bound(&stripes->view, 1, &r, &err), SATF_OK);
  assert_true(fabs(r.iou - 25.0 / 119.0) < 1e-6);
  assert_true(r.ssim < 0.5);
  assert_int_equal(compare_smooth_bound(&flat->view, 4, &r, &err), SATF_OK);
  assert_true(fabs(r.iou - 1.0) < 1e-9);
  assert_true(fabs(r.ssim - 1.0) < 1e-9);
  assert_int_equal(compare_smooth_bound(&flat->view, 0, &r, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "radius 0 is out of range"));
  assert_int_equal(compare_smooth_bound(&flat->view, 17, &r, &err),
                   SATF_ERR_ARGUMENT);
  free(stripes), free(flat);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(identical_images_agree_fully),
      cmocka_unit_test(half_coverage_is_iou_one_half),
      cmocka_unit_test(brightness_scale_shows_in_ratio_not_ssim),
      cmocka_unit_test(hue_shift_gives_its_angle),
      cmocka_unit_test(different_structure_lowers_ssim),
      cmocka_unit_test(ssim4_sees_blocks_not_pixels),
      cmocka_unit_test(mismatched_sizes_are_refused),
      cmocka_unit_test(empty_frames_and_nan_are_reported),
      cmocka_unit_test(white_point_is_numpy_percentile),
      cmocka_unit_test(smooth_bound_of_stripes_and_flat),
      cmocka_unit_test(writes_cli_inputs),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
