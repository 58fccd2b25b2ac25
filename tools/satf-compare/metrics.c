/* metrics.c - the measures of metrics.h, term by term as
 * ../shared/tools/fidelity.py defines them (A = reference, B = test):
 *
 *   union   pixels where alpha_A > 0.05 or alpha_B > 0.05
 *   both    pixels where alpha_A > 0.05 and alpha_B > 0.05
 *   iou     sum min(alpha_A, alpha_B) / max(sum max(alpha_A, alpha_B), 1e-9)
 *   alpha   mean |alpha_A - alpha_B| over the union (1 when it is empty)
 *   lum     mean L_B / max(mean L_A, 1e-9), means over the union
 *   ssim    over the union's bounding box: x = clamp(L_B * s / w, 0, 1),
 *           y = clamp(L_A / w, 0, 1) with s = mean L_A / max(mean L_B,
 *           1e-9) over the union (exposure normalisation) and w =
 *           max(99.5th percentile of L_A in the union, 1e-6); the mean of
 *           the SSIM map (0 when the union is empty)
 *   ssim4   the same SSIM of x and y after averaging both over 4x4 pixel
 *           blocks (the box's top-left floor(w/4) x floor(h/4) blocks;
 *           ssim itself when fewer than 4 blocks span either side): the
 *           look at a wisp's scale, without the placement of single
 *           sub-pixel strands
 *   chroma  angle in degrees between sum RGB_A and sum RGB_B over "both"
 *           (90 when no pixel is covered by both)
 *
 * L is the luminance of the premultiplied colour, so a half-covered pixel
 * counts half: structure is compared as the eye sees it over black. */
#include "metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

double compare_luminance(double r, double g, double b) {
  /* ITU-R BT.709 luma coefficients, applied to linear RGB. */
  return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

satf_status compare_check_finite(const compare_image *img, satf_error *err) {
  const float *planes[4] = {img->r, img->g, img->b, img->a};
  static const char names[4] = {'R', 'G', 'B', 'A'};
  size_t n = (size_t)img->width * (size_t)img->height;
  for (int c = 0; c < 4; c++)
    for (size_t i = 0; i < n; i++)
      if (!isfinite(planes[c][i]))
        return satf_error_set(err, SATF_ERR_CORRUPT,
                              "%s: pixel (%zu, %zu) channel %c is not finite",
                              img->name, i % (size_t)img->width,
                              i / (size_t)img->width, names[c]);
  return SATF_OK;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* numpy.percentile's default ("linear"): position q (n - 1) in the sorted
 * values, interpolated between its neighbours. Sorts v. */
static double percentile(double *v, size_t n, double q) {
  qsort(v, n, sizeof *v, cmp_double);
  double pos = q * (double)(n - 1);
  size_t lo = (size_t)floor(pos);
  size_t hi = lo + 1 < n ? lo + 1 : lo;
  double f = pos - (double)lo;
  return v[lo] + f * (v[hi] - v[lo]);
}

/* Mean over the (2r+1)^2 window around each pixel, indices clamped to the
 * image (fidelity.py pads with the edge values): separable, since clamping
 * acts on each axis alone. tmp holds w * h doubles. */
static void box_mean(const double *in, double *out, double *tmp, int w, int h,
                     int r) {
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      double s = 0.0;
      for (int d = -r; d <= r; d++) {
        int xx = x + d < 0 ? 0 : x + d >= w ? w - 1 : x + d;
        s += in[(size_t)y * (size_t)w + (size_t)xx];
      }
      tmp[(size_t)y * (size_t)w + (size_t)x] = s;
    }
  double norm = 1.0 / ((2.0 * r + 1.0) * (2.0 * r + 1.0));
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      double s = 0.0;
      for (int d = -r; d <= r; d++) {
        int yy = y + d < 0 ? 0 : y + d >= h ? h - 1 : y + d;
        s += tmp[(size_t)yy * (size_t)w + (size_t)x];
      }
      out[(size_t)y * (size_t)w + (size_t)x] = s * norm;
    }
}

/* Mean SSIM of x against y (w x h): Wang, Bovik, Sheikh and Simoncelli
 * 2004, "Image quality assessment: from error visibility to structural
 * similarity", eq. 13 with K1 = 0.01, K2 = 0.03 and dynamic range L = 1,
 * local statistics over a 7x7 box instead of their 11x11 Gaussian (as
 * fidelity.py computes them). */
static satf_status ssim_mean(const double *x, const double *y, int w, int h,
                             double *out, satf_error *err) {
  size_t n = (size_t)w * (size_t)h;
  double *buf = malloc(8 * n * sizeof *buf);
  if (!buf)
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "SSIM: cannot allocate %dx%d pixels", w, h);
  double *mx = buf, *my = buf + n, *sxx = buf + 2 * n, *syy = buf + 3 * n,
         *sxy = buf + 4 * n, *prod = buf + 5 * n, *tmp = buf + 6 * n;
  const int r = COMPARE_SSIM_RADIUS;
  box_mean(x, mx, tmp, w, h, r);
  box_mean(y, my, tmp, w, h, r);
  for (size_t i = 0; i < n; i++)
    prod[i] = x[i] * x[i];
  box_mean(prod, sxx, tmp, w, h, r);
  for (size_t i = 0; i < n; i++)
    prod[i] = y[i] * y[i];
  box_mean(prod, syy, tmp, w, h, r);
  for (size_t i = 0; i < n; i++)
    prod[i] = x[i] * y[i];
  box_mean(prod, sxy, tmp, w, h, r);
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  double sum = 0.0;
  for (size_t i = 0; i < n; i++) {
    double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i];
    double cxy = sxy[i] - mx[i] * my[i];
    sum += ((2.0 * mx[i] * my[i] + c1) * (2.0 * cxy + c2)) /
           ((mx[i] * mx[i] + my[i] * my[i] + c1) * (vx + vy + c2));
  }
  free(buf);
  *out = sum / (double)n;
  return SATF_OK;
}

/* The angle between two colour vectors in degrees; atan2 of the cross and
 * dot products is the same angle as acos of the normalised dot product but
 * stays accurate near 0. */
static double angle_deg(const double a[3], const double b[3]) {
  double cx = a[1] * b[2] - a[2] * b[1], cy = a[2] * b[0] - a[0] * b[2],
         cz = a[0] * b[1] - a[1] * b[0];
  double cross = sqrt(cx * cx + cy * cy + cz * cz);
  double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  if (cross == 0.0 && dot == 0.0)
    return 90.0; /* a zero vector: no colour to compare */
  return atan2(cross, dot) * (180.0 / 3.14159265358979323846);
}

/* Replaces the first bw x bh values of v (row-major, bw wide) by the means
 * of the COMPARE_BLOCK^2 blocks of v (w wide) they stand for. Block k
 * writes v[k] after reading pixels at indices >= k only, so this works in
 * place. */
static void block_mean(double *v, int w, int bw, int bh) {
  const int b = COMPARE_BLOCK;
  for (int j = 0; j < bh; j++)
    for (int i = 0; i < bw; i++) {
      double s = 0.0;
      for (int dy = 0; dy < b; dy++)
        for (int dx = 0; dx < b; dx++)
          s += v[(size_t)(b * j + dy) * (size_t)w + (size_t)(b * i + dx)];
      v[(size_t)j * (size_t)bw + (size_t)i] = s / (double)(b * b);
    }
}

/* The SSIM term: exposure-normalised, white point from the reference. */
static satf_status ssim_term(const compare_image *ref,
                             const compare_image *test, const double *lum_ref,
                             const double *lum_test, compare_result *res,
                             satf_error *err) {
  int x0 = res->box[0], y0 = res->box[1];
  int w = res->box[2] - x0 + 1, h = res->box[3] - y0 + 1;
  size_t nb = (size_t)w * (size_t)h, width = (size_t)ref->width;
  double *inside = malloc((size_t)res->union_px * sizeof *inside);
  double *x = malloc(nb * sizeof *x), *y = malloc(nb * sizeof *y);
  if (!inside || !x || !y) {
    free(inside), free(x), free(y);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "SSIM: cannot allocate %dx%d pixels", w, h);
  }
  size_t k = 0;
  for (size_t i = 0; i < width * (size_t)ref->height; i++)
    if (ref->a[i] > COMPARE_COVERED || test->a[i] > COMPARE_COVERED)
      inside[k++] = lum_ref[i];
  double white = percentile(inside, k, 0.995);
  res->white = white > 1e-6 ? white : 1e-6;
  for (int j = 0; j < h; j++)
    for (int i = 0; i < w; i++) {
      size_t src = (size_t)(y0 + j) * width + (size_t)(x0 + i);
      double vx = lum_test[src] * res->exposure / res->white;
      double vy = lum_ref[src] / res->white;
      x[(size_t)j * (size_t)w + (size_t)i] = vx < 0 ? 0 : vx > 1 ? 1 : vx;
      y[(size_t)j * (size_t)w + (size_t)i] = vy < 0 ? 0 : vy > 1 ? 1 : vy;
    }
  satf_status st = ssim_mean(x, y, w, h, &res->ssim, err);
  res->ssim4 = res->ssim;
  if (st == SATF_OK && w >= 4 * COMPARE_BLOCK && h >= 4 * COMPARE_BLOCK) {
    /* in place: block (i, j) reads only pixels at or after its own index */
    int bw = w / COMPARE_BLOCK, bh = h / COMPARE_BLOCK;
    block_mean(x, w, bw, bh);
    block_mean(y, w, bw, bh);
    st = ssim_mean(x, y, bw, bh, &res->ssim4, err);
  }
  free(inside), free(x), free(y);
  return st;
}

satf_status compare_measure(const compare_image *ref, const compare_image *test,
                            compare_result *res, satf_error *err) {
  memset(res, 0, sizeof *res);
  if (ref->width != test->width || ref->height != test->height)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "sizes differ: %s is %dx%d, %s is %dx%d", ref->name,
                          ref->width, ref->height, test->name, test->width,
                          test->height);
  size_t width = (size_t)ref->width, n = width * (size_t)ref->height;
  double *lum_ref = malloc(n * sizeof *lum_ref);
  double *lum_test = malloc(n * sizeof *lum_test);
  if (!lum_ref || !lum_test) {
    free(lum_ref), free(lum_test);
    return satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate %dx%d pixels",
                          ref->width, ref->height);
  }
  double sum_min = 0, sum_max = 0, sum_dalpha = 0, sum_lr = 0, sum_lt = 0;
  double col_ref[3] = {0, 0, 0}, col_test[3] = {0, 0, 0};
  for (int c = 0; c < 4; c++)
    res->box[c] = -1;
  for (size_t i = 0; i < n; i++) {
    double ar = ref->a[i], at = test->a[i];
    sum_min += ar < at ? ar : at;
    sum_max += ar > at ? ar : at;
    lum_ref[i] = compare_luminance(ref->r[i], ref->g[i], ref->b[i]);
    lum_test[i] = compare_luminance(test->r[i], test->g[i], test->b[i]);
    int in_ref = ar > COMPARE_COVERED, in_test = at > COMPARE_COVERED;
    if (!in_ref && !in_test)
      continue;
    res->union_px++;
    sum_dalpha += fabs(ar - at);
    sum_lr += lum_ref[i];
    sum_lt += lum_test[i];
    int x = (int)(i % width), y = (int)(i / width);
    if (res->box[0] < 0) {
      res->box[0] = res->box[2] = x;
      res->box[1] = res->box[3] = y;
    }
    res->box[0] = x < res->box[0] ? x : res->box[0];
    res->box[2] = x > res->box[2] ? x : res->box[2];
    res->box[3] = y; /* rows come in order */
    if (in_ref && in_test) {
      res->both_px++;
      col_ref[0] += ref->r[i], col_ref[1] += ref->g[i], col_ref[2] += ref->b[i];
      col_test[0] += test->r[i], col_test[1] += test->g[i],
          col_test[2] += test->b[i];
    }
  }
  res->iou = sum_min / (sum_max > 1e-9 ? sum_max : 1e-9);
  res->chroma_deg = res->both_px ? angle_deg(col_ref, col_test) : 90.0;
  satf_status st = SATF_OK;
  if (res->union_px == 0) {
    res->alpha_error = 1.0;
    res->lum_ratio = NAN;
    res->ssim = 0.0;
    res->exposure = 1.0;
    res->white = 1.0;
  } else {
    double u = (double)res->union_px;
    double mean_ref = sum_lr / u, mean_test = sum_lt / u;
    res->alpha_error = sum_dalpha / u;
    res->lum_ratio = mean_test / (mean_ref > 1e-9 ? mean_ref : 1e-9);
    res->exposure = mean_ref / (mean_test > 1e-9 ? mean_test : 1e-9);
    st = ssim_term(ref, test, lum_ref, lum_test, res, err);
  }
  free(lum_ref), free(lum_test);
  return st;
}

satf_status compare_smooth_bound(const compare_image *ref, int radius,
                                 compare_result *res, satf_error *err) {
  memset(res, 0, sizeof *res);
  if (radius < 1 || radius > COMPARE_BOUND_RADIUS_MAX)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "smooth bound: radius %d is out of range [1, %d]",
                          radius, COMPARE_BOUND_RADIUS_MAX);
  int w = ref->width, h = ref->height;
  size_t n = (size_t)w * (size_t)h;
  double *in = malloc(n * sizeof *in), *out = malloc(n * sizeof *out),
         *tmp = malloc(n * sizeof *tmp);
  float *blur = malloc(4 * n * sizeof *blur);
  satf_status st = SATF_OK;
  if (!in || !out || !tmp || !blur) {
    st = satf_error_set(err, SATF_ERR_NOMEM,
                        "smooth bound: cannot allocate %dx%d pixels", w, h);
  } else {
    /* the same clamped box as SSIM's windows, on every channel of the
     * premultiplied colour, so the blurred frame is itself a frame */
    const float *src[4] = {ref->r, ref->g, ref->b, ref->a};
    for (int c = 0; c < 4; c++) {
      for (size_t i = 0; i < n; i++)
        in[i] = src[c][i];
      box_mean(in, out, tmp, w, h, radius);
      for (size_t i = 0; i < n; i++)
        blur[(size_t)c * n + i] = (float)out[i];
    }
    compare_image smooth = {"the smoothed reference",
                            w,
                            h,
                            blur,
                            blur + n,
                            blur + 2 * n,
                            blur + 3 * n};
    st = compare_measure(ref, &smooth, res, err);
  }
  free(in), free(out), free(tmp), free(blur);
  return st;
}
