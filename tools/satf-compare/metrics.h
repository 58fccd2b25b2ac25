/* metrics.h - satf-compare's image-fidelity measures: soft coverage IoU,
 * mean alpha error, exposure-normalised luminance SSIM, mean luminance
 * ratio and chroma angle between a reference frame and a test frame of the
 * same camera. Pure functions of two in-memory RGBA images (linear colour,
 * premultiplied by alpha, as satf-render writes EXRs), so the tool and the
 * unit tests compute exactly the same numbers.
 *
 * The definitions follow ../shared/tools/fidelity.py term by term, so that
 *   satf-compare REFERENCE.exr TEST.exr   and
 *   fidelity.py TEST.exr REFERENCE.exr    (its satf frame first)
 * print the same figures. */
#ifndef SATF_TOOLS_COMPARE_METRICS_H
#define SATF_TOOLS_COMPARE_METRICS_H

#include "satf/satf.h"

/* A pixel counts as covered when its alpha is above this (fidelity.py's
 * silhouette threshold: keeps faint anti-aliasing and noise out of the
 * averages). */
#define COMPARE_COVERED 0.05
/* SSIM window: a (2r+1)^2 = 7x7 box, edges clamped (fidelity.py's box()). */
#define COMPARE_SSIM_RADIUS 3
/* SSIM4's blocks: 4x4 pixels averaged before the SSIM (fidelity.py's
 * ssim4); at least 4 blocks a side, else ssim4 is ssim. */
#define COMPARE_BLOCK 4

/* Linear RGBA planes, width * height floats each, row-major; colour
 * premultiplied by alpha. name (a file name) is quoted in messages. */
typedef struct compare_image {
  const char *name;
  int width, height;
  const float *r, *g, *b, *a;
} compare_image;

typedef struct compare_result {
  double iou;         /* sum min(alpha) / sum max(alpha) */
  double alpha_error; /* mean |alpha_ref - alpha_test| over the union */
  double ssim;        /* luminance SSIM over the union's bounding box */
  double ssim4;       /* the same over 4x4 pixel block means */
  double lum_ratio;   /* mean lum test / mean lum ref over the union; NaN
                         when the union is empty */
  double chroma_deg;  /* angle between the summed colours where both cover */
  long long union_px; /* pixels either image covers */
  long long both_px;  /* pixels both images cover */
  int box[4];         /* the union's bounding box x0, y0, x1, y1
                         (inclusive); all -1 when the union is empty */
  double exposure;    /* factor that scaled the test luminance for SSIM */
  double white;       /* luminance mapped to 1 for SSIM (99.5th percentile
                         of the reference inside the union) */
} compare_result;

/* Rec. 709 / sRGB luminance of linear RGB. */
double compare_luminance(double r, double g, double b);

/* Checks that every value of img is finite (a NaN would silently poison
 * every average): "NAME: pixel (X, Y) channel C is not finite". */
satf_status compare_check_finite(const compare_image *img, satf_error *err);

/* Measures test against ref. Images of different sizes are refused
 * (SATF_ERR_ARGUMENT, "sizes differ: REF is WxH, TEST is WxH"). */
satf_status compare_measure(const compare_image *ref, const compare_image *test,
                            compare_result *out, satf_error *err);

/* The figures of ref against itself blurred by a (2 radius + 1)^2 box
 * (edges clamped, every channel): what a test frame that reproduces the
 * reference exactly down to that scale, but no finer, would score. A
 * bound, not a target: a preview that does not place each strand where
 * the reference has it cannot be expected to beat it (strands a pixel
 * wide score far below 1 at radius 1). */
#define COMPARE_BOUND_RADIUS_MAX 16
satf_status compare_smooth_bound(const compare_image *ref, int radius,
                                 compare_result *out, satf_error *err);

#endif
