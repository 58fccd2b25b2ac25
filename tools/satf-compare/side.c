/* side.c - the side-by-side PNG of side.h, drawn into a satf_image and
 * written with the renderer's PNG writer (satf/render.h), which applies the
 * sRGB transfer function to the linear values set here. */
#include "side.h"

#include <math.h>
#include <stdlib.h>

#include "satf/render.h"

/* Linear colours of the heat map's stops: at |d| = 0, 0.25 and >= 0.5. */
static const float HEAT_ZERO[3] = {0.035f, 0.035f, 0.035f};
static const float HEAT_UP[2][3] = {{0.75f, 0.04f, 0.02f}, {1.0f, 0.85f, 0.1f}};
static const float HEAT_DOWN[2][3] = {{0.02f, 0.08f, 0.85f},
                                      {0.1f, 0.8f, 1.0f}};

static void heat(double d, float rgb[3]) {
  const float(*stops)[3] = d >= 0 ? HEAT_UP : HEAT_DOWN;
  double t = fabs(d) / 0.25;
  const float *lo = t < 1.0 ? HEAT_ZERO : stops[0];
  const float *hi = t < 1.0 ? stops[0] : stops[1];
  double f = t < 1.0 ? t : t - 1.0 > 1.0 ? 1.0 : t - 1.0;
  for (int c = 0; c < 3; c++)
    rgb[c] = (float)(lo[c] + f * (hi[c] - lo[c]));
}

satf_status compare_write_side(const compare_image *ref,
                               const compare_image *test,
                               const compare_result *res, const char *path,
                               satf_error *err) {
  static const char *const names[3] = {"R", "G", "B"};
  int w = ref->width, h = ref->height;
  satf_image *img = NULL;
  satf_status st = satf_image_create(3 * w, h, names, 3, &img, err);
  if (st != SATF_OK)
    return st;
  float *out[3];
  for (int c = 0; c < 3; c++)
    out[c] = satf_image_plane(img, c);
  const compare_image *panel[2] = {ref, test};
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      size_t i = (size_t)y * (size_t)w + (size_t)x;
      size_t row = (size_t)y * 3 * (size_t)w;
      for (int p = 0; p < 2; p++) {
        const compare_image *im = panel[p];
        const float *src[3] = {im->r, im->g, im->b};
        float behind = (1.0f - im->a[i]) * COMPARE_SIDE_GREY;
        for (int c = 0; c < 3; c++)
          out[c][row + (size_t)p * (size_t)w + (size_t)x] =
              src[c][i] + (behind > 0 ? behind : 0);
      }
      float rgb[3] = {COMPARE_SIDE_GREY, COMPARE_SIDE_GREY, COMPARE_SIDE_GREY};
      if (ref->a[i] > COMPARE_COVERED || test->a[i] > COMPARE_COVERED) {
        double lr = compare_luminance(ref->r[i], ref->g[i], ref->b[i]);
        double lt = compare_luminance(test->r[i], test->g[i], test->b[i]);
        heat((lt * res->exposure - lr) / res->white, rgb);
      }
      for (int c = 0; c < 3; c++)
        out[c][row + 2 * (size_t)w + (size_t)x] = rgb[c];
    }
  st = satf_image_write_png(img, path, err);
  satf_image_destroy(img);
  return st;
}
