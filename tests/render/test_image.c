/* test_image.c - the float frame and its EXR / PNG writers. Files are read
 * back through independent paths (satf_exr_read and OpenEXRCore's header
 * API, libpng's simplified reader) and compared with values worked out by
 * hand. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
/* cmocka needs the headers above first */
#include <cmocka.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "satf/common.h"
#include "satf/render.h"

static void tmp_path(char *buf, size_t size, const char *name) {
  const char *dir = getenv("SATF_TEST_TMP");
  snprintf(buf, size, "%s/%s", dir ? dir : "/tmp", name);
}

static int exists(const char *path) { return satf_file_size(path) >= 0; }

static void test_create_validates(void **state) {
  (void)state;
  satf_error err;
  satf_image *img = NULL;
  const char *ok[3] = {"R", "diffuse.R", "shadow"};
  const char *dup[3] = {"R", "G", "R"};
  const char *empty[2] = {"R", ""};
  assert_int_equal(satf_image_create(0, 4, ok, 3, &img, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(
      satf_image_create(4, SATF_IMAGE_MAX_SIDE + 1, ok, 3, &img, &err),
      SATF_ERR_ARGUMENT);
  assert_int_equal(satf_image_create(4, 4, ok, 0, &img, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_image_create(4, 4, ok, 65, &img, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_image_create(4, 4, dup, 3, &img, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "'R' appears twice"));
  assert_int_equal(satf_image_create(4, 4, empty, 2, &img, &err),
                   SATF_ERR_ARGUMENT);
  char longname[SATF_IMAGE_MAX_NAME + 2];
  memset(longname, 'x', sizeof longname - 1);
  longname[sizeof longname - 1] = '\0';
  const char *toolong[1] = {longname};
  assert_int_equal(satf_image_create(4, 4, toolong, 1, &img, &err),
                   SATF_ERR_ARGUMENT);
  assert_null(img);

  assert_int_equal(satf_image_create(4, 2, ok, 3, &img, &err), SATF_OK);
  assert_int_equal(satf_image_width(img), 4);
  assert_int_equal(satf_image_height(img), 2);
  assert_int_equal(satf_image_channel_count(img), 3);
  assert_string_equal(satf_image_channel_name(img, 1), "diffuse.R");
  assert_null(satf_image_channel_name(img, 3));
  assert_int_equal(satf_image_channel_index(img, "shadow"), 2);
  assert_int_equal(satf_image_channel_index(img, "diffuse"), -1);
  assert_null(satf_image_plane(img, 3));
  for (int c = 0; c < 3; c++)
    for (int i = 0; i < 8; i++)
      assert_true(satf_image_const_plane(img, c)[i] == 0.0f);
  satf_image_destroy(img);
}

static void test_store_interleaved_flips_rows(void **state) {
  (void)state;
  satf_error err;
  satf_image *img = NULL;
  const char *names[3] = {"A", "R", "shadow"};
  assert_int_equal(satf_image_create(2, 3, names, 3, &img, &err), SATF_OK);
  /* 2x3 pixels, 3 components: value = 100*row + 10*col + component, row
   * counted in memory order. */
  float src[2 * 3 * 3];
  for (int r = 0; r < 3; r++)
    for (int x = 0; x < 2; x++)
      for (int k = 0; k < 3; k++)
        src[(r * 2 + x) * 3 + k] = (float)(100 * r + 10 * x + k);
  const char *map[3] = {"R", NULL, "shadow"};
  assert_int_equal(
      satf_image_store_interleaved(img, src, 3, map, SATF_ROWS_BOTTOM_UP, &err),
      SATF_OK);
  const float *R = satf_image_const_plane(img, 1);
  const float *S = satf_image_const_plane(img, 2);
  /* Top image row is the last memory row (r = 2). */
  assert_true(R[0] == 200.0f && R[1] == 210.0f);
  assert_true(R[4] == 0.0f && R[5] == 10.0f);
  assert_true(S[0] == 202.0f && S[5] == 12.0f);
  /* Skipped component: A untouched. */
  assert_true(satf_image_const_plane(img, 0)[0] == 0.0f);

  assert_int_equal(
      satf_image_store_interleaved(img, src, 3, map, SATF_ROWS_TOP_DOWN, &err),
      SATF_OK);
  assert_true(R[0] == 0.0f && R[5] == 210.0f);

  const char *unknown[3] = {"R", "G", NULL};
  R = satf_image_const_plane(img, 1);
  assert_int_equal(satf_image_store_interleaved(img, src, 3, unknown,
                                                SATF_ROWS_TOP_DOWN, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "'G'"));
  satf_image_destroy(img);
}

/* ---- EXR --------------------------------------------------------------- */

#define EXR_W 5
#define EXR_H 3
#define EXR_NC 9
static const char *exr_names[EXR_NC] = {"R",         "G",         "B",
                                        "A",         "diffuse.R", "diffuse.G",
                                        "diffuse.B", "specI.R",   "shadow"};

static float exr_value(int c, int x, int y) {
  if (c == 3)
    return 1.0f; /* alpha */
  return (float)(c + 1) * 0.1f + (float)x * 0.0137f - (float)y * 0.7f +
         (c == 8 ? 1000.0f : 0.0f);
}

static satf_image *make_exr_image(void) {
  satf_error err;
  satf_image *img = NULL;
  assert_int_equal(
      satf_image_create(EXR_W, EXR_H, exr_names, EXR_NC, &img, &err), SATF_OK);
  for (int c = 0; c < EXR_NC; c++)
    for (int y = 0; y < EXR_H; y++)
      for (int x = 0; x < EXR_W; x++)
        satf_image_plane(img, c)[y * EXR_W + x] = exr_value(c, x, y);
  return img;
}

static void test_exr_roundtrip_half(void **state) {
  (void)state;
  satf_error err;
  char path[1024];
  tmp_path(path, sizeof path, "image_half.exr");
  satf_image *img = make_exr_image();
  assert_int_equal(satf_image_write_exr(img, path, &err), SATF_OK);
  satf_image_destroy(img);

  float *planes[EXR_NC];
  int w = 0, h = 0;
  assert_int_equal(satf_exr_read(path, exr_names, EXR_NC, 1000, NULL, NULL, &w,
                                 &h, planes, &err),
                   SATF_OK);
  assert_int_equal(w, EXR_W);
  assert_int_equal(h, EXR_H);
  for (int c = 0; c < EXR_NC; c++) {
    for (int y = 0; y < EXR_H; y++)
      for (int x = 0; x < EXR_W; x++) {
        float v = exr_value(c, x, y);
        float got = planes[c][y * EXR_W + x];
        /* half: 11 significant bits, round to nearest */
        float tol = fabsf(v) * (1.0f / 2048.0f) + 1e-7f;
        if (fabsf(got - v) > tol)
          fail_msg("%s (%d,%d): %g vs %g", exr_names[c], x, y, (double)got,
                   (double)v);
      }
    free(planes[c]);
  }

  /* The header, read independently: every channel HALF, ZIP. */
  exr_context_t ctx = NULL;
  assert_int_equal(exr_start_read(&ctx, path, NULL), EXR_ERR_SUCCESS);
  exr_compression_t comp = EXR_COMPRESSION_NONE;
  assert_int_equal(exr_get_compression(ctx, 0, &comp), EXR_ERR_SUCCESS);
  assert_int_equal(comp, EXR_COMPRESSION_ZIP);
  const exr_attr_chlist_t *ch = NULL;
  assert_int_equal(exr_get_channels(ctx, 0, &ch), EXR_ERR_SUCCESS);
  assert_int_equal(ch->num_channels, EXR_NC);
  for (int c = 0; c < ch->num_channels; c++)
    assert_int_equal(ch->entries[c].pixel_type, EXR_PIXEL_HALF);
  exr_finish(&ctx);
}

static void test_exr_roundtrip_float_exact(void **state) {
  (void)state;
  satf_error err;
  char path[1024];
  tmp_path(path, sizeof path, "image_float.exr");
  satf_image *img = make_exr_image();
  assert_int_equal(satf_image_write_exr_float(img, path, &err), SATF_OK);
  satf_image_destroy(img);
  float *planes[EXR_NC];
  int w = 0, h = 0;
  assert_int_equal(satf_exr_read(path, exr_names, EXR_NC, 1000, NULL, NULL, &w,
                                 &h, planes, &err),
                   SATF_OK);
  for (int c = 0; c < EXR_NC; c++) {
    for (int i = 0; i < EXR_W * EXR_H; i++)
      assert_true(planes[c][i] == exr_value(c, i % EXR_W, i / EXR_W));
    free(planes[c]);
  }
}

/* ---- PNG --------------------------------------------------------------- */

/* Decodes with libpng's simplified reader into RGBA8, reporting whether
 * the file itself has colour and alpha. */
static unsigned char *read_png(const char *path, int *w, int *h, int *has_color,
                               int *has_alpha) {
  png_image pi;
  memset(&pi, 0, sizeof pi);
  pi.version = PNG_IMAGE_VERSION;
  assert_true(png_image_begin_read_from_file(&pi, path));
  *has_color = (pi.format & PNG_FORMAT_FLAG_COLOR) != 0;
  *has_alpha = (pi.format & PNG_FORMAT_FLAG_ALPHA) != 0;
  pi.format = PNG_FORMAT_RGBA;
  unsigned char *buf = malloc(PNG_IMAGE_SIZE(pi));
  assert_non_null(buf);
  assert_true(png_image_finish_read(&pi, NULL, buf, 0, NULL));
  *w = (int)pi.width;
  *h = (int)pi.height;
  return buf;
}

static void test_png_srgb_bytes(void **state) {
  (void)state;
  satf_error err;
  satf_image *img = NULL;
  const char *rgb[3] = {"R", "G", "B"};
  assert_int_equal(satf_image_create(4, 2, rgb, 3, &img, &err), SATF_OK);
  /* Top row, R: 0, 1, 0.5, 0.0031308 (the toe/power boundary);
   * G: 0.2, 2.0 (clamped), -1 (clamped), NaN; B: 0.18 everywhere.
   * Bottom row: R = 0.01, 0.75; rest 0. */
  float *R = satf_image_plane(img, 0), *G = satf_image_plane(img, 1),
        *B = satf_image_plane(img, 2);
  const float r[4] = {0.0f, 1.0f, 0.5f, 0.0031308f};
  const float g[4] = {0.2f, 2.0f, -1.0f, NAN};
  for (int x = 0; x < 4; x++) {
    R[x] = r[x];
    G[x] = g[x];
    B[x] = 0.18f;
  }
  R[4] = 0.01f;
  R[5] = 0.75f;
  char path[1024];
  tmp_path(path, sizeof path, "image_srgb.png");
  assert_int_equal(satf_image_write_png(img, path, &err), SATF_OK);
  satf_image_destroy(img);

  int w, h, color, alpha;
  unsigned char *px = read_png(path, &w, &h, &color, &alpha);
  assert_int_equal(w, 4);
  assert_int_equal(h, 2);
  assert_true(color);
  assert_false(alpha);
  /* By hand: 12.92 * 0.0031308 * 255 = 10.31 -> 10;
   * (1.055 * 0.5^(1/2.4) - 0.055) * 255 = 187.52 -> 188;
   * 0.2 -> 123.55 -> 124; 0.18 -> 117.65 -> 118;
   * 0.01 -> 25.46 -> 25; 0.75 -> 224.61 -> 225. */
  const unsigned char want_r[4] = {0, 255, 188, 10};
  const unsigned char want_g[4] = {124, 255, 0, 0};
  for (int x = 0; x < 4; x++) {
    assert_int_equal(px[4 * x + 0], want_r[x]);
    assert_int_equal(px[4 * x + 1], want_g[x]);
    assert_int_equal(px[4 * x + 2], 118);
    assert_int_equal(px[4 * x + 3], 255);
  }
  assert_int_equal(px[16 + 0], 25);
  assert_int_equal(px[16 + 4], 225);
  assert_int_equal(px[16 + 5], 0);
  free(px);
}

static void test_png_keeps_straight_alpha(void **state) {
  (void)state;
  satf_error err;
  satf_image *img = NULL;
  const char *rgba[4] = {"R", "G", "B", "A"};
  assert_int_equal(satf_image_create(3, 1, rgba, 4, &img, &err), SATF_OK);
  float *R = satf_image_plane(img, 0), *A = satf_image_plane(img, 3);
  /* Premultiplied: R 0.25 at alpha 0.5 is straight 0.5 -> 188, alpha
   * 0.5 * 255 = 127.5 -> 128. Opaque 1.0 -> 255. Alpha 0 -> all 0. */
  R[0] = 0.25f;
  A[0] = 0.5f;
  R[1] = 1.0f;
  A[1] = 1.0f;
  R[2] = 0.3f;
  A[2] = 0.0f;
  char path[1024];
  tmp_path(path, sizeof path, "image_alpha.png");
  assert_int_equal(satf_image_write_png(img, path, &err), SATF_OK);
  satf_image_destroy(img);
  int w, h, color, alpha;
  unsigned char *px = read_png(path, &w, &h, &color, &alpha);
  assert_true(color);
  assert_true(alpha);
  const unsigned char want[12] = {188, 0, 0, 128, 255, 0, 0, 255, 0, 0, 0, 0};
  for (int i = 0; i < 12; i++)
    assert_int_equal(px[i], want[i]);
  free(px);
}

static void test_png_layers(void **state) {
  (void)state;
  satf_error err;
  satf_image *img = NULL;
  const char *names[5] = {"diffuse.R", "diffuse.G", "diffuse.B", "shadow", "R"};
  assert_int_equal(satf_image_create(2, 1, names, 5, &img, &err), SATF_OK);
  satf_image_plane(img, 0)[0] = 0.5f;
  satf_image_plane(img, 1)[0] = 1.0f;
  satf_image_plane(img, 2)[1] = 0.0031308f;
  satf_image_plane(img, 3)[0] = 0.5f;
  satf_image_plane(img, 3)[1] = 1.0f;
  char path[1024];
  tmp_path(path, sizeof path, "image_diffuse.png");
  assert_int_equal(satf_image_write_png_layer(img, "diffuse", path, &err),
                   SATF_OK);
  int w, h, color, alpha;
  unsigned char *px = read_png(path, &w, &h, &color, &alpha);
  assert_true(color);
  assert_false(alpha);
  const unsigned char want[8] = {188, 255, 0, 255, 0, 0, 10, 255};
  for (int i = 0; i < 8; i++)
    assert_int_equal(px[i], want[i]);
  free(px);

  tmp_path(path, sizeof path, "image_shadow.png");
  assert_int_equal(satf_image_write_png_layer(img, "shadow", path, &err),
                   SATF_OK);
  px = read_png(path, &w, &h, &color, &alpha);
  assert_false(color);
  assert_false(alpha);
  assert_int_equal(px[0], 188);
  assert_int_equal(px[4], 255);
  free(px);

  /* No G and B beside R: not an RGB image. */
  tmp_path(path, sizeof path, "image_none.png");
  assert_int_equal(satf_image_write_png(img, path, &err), SATF_ERR_ARGUMENT);
  assert_int_equal(satf_image_write_png_layer(img, "specI", path, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "'specI'"));
  assert_false(exists(path));
  satf_image_destroy(img);
}

/* ---- failures ---------------------------------------------------------- */

static void test_unwritable_paths(void **state) {
  (void)state;
  satf_error err;
  satf_image *img = NULL;
  const char *rgba[4] = {"R", "G", "B", "A"};
  assert_int_equal(satf_image_create(2, 2, rgba, 4, &img, &err), SATF_OK);

  char path[1024], tmp[1100];
  tmp_path(path, sizeof path, "no_such_dir/out.png");
  assert_int_equal(satf_image_write_png(img, path, &err), SATF_ERR_IO);
  assert_non_null(strstr(err.message, path));
  tmp_path(path, sizeof path, "no_such_dir/out.exr");
  assert_int_equal(satf_image_write_exr(img, path, &err), SATF_ERR_IO);
  assert_non_null(strstr(err.message, path));

  /* The target is a directory: the temporary file is written, the rename
   * fails, and the temporary must be gone. */
  tmp_path(path, sizeof path, "image_dir_target");
  mkdir(path, 0755);
  assert_int_equal(satf_temp_path(path, tmp, sizeof tmp, &err), SATF_OK);
  assert_int_equal(satf_image_write_png(img, path, &err), SATF_ERR_IO);
  assert_non_null(strstr(err.message, path));
  assert_false(exists(tmp));
  assert_int_equal(satf_image_write_exr(img, path, &err), SATF_ERR_IO);
  assert_non_null(strstr(err.message, path));
  assert_false(exists(tmp));
  satf_image_destroy(img);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_create_validates),
      cmocka_unit_test(test_store_interleaved_flips_rows),
      cmocka_unit_test(test_exr_roundtrip_half),
      cmocka_unit_test(test_exr_roundtrip_float_exact),
      cmocka_unit_test(test_png_srgb_bytes),
      cmocka_unit_test(test_png_keeps_straight_alpha),
      cmocka_unit_test(test_png_layers),
      cmocka_unit_test(test_unwritable_paths),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
