/* satf-compare - how close a test frame is to a reference frame of the same
 * camera: soft coverage IoU, alpha error, exposure-normalised luminance
 * SSIM, luminance ratio and chroma angle (metrics.h), optional thresholds
 * for scripts and tests, and a side-by-side difference PNG (side.h). This
 * reads the command line and the two EXRs. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "metrics.h"
#include "satf/common.h"
#include "side.h"

static const char *PROG = "satf-compare";

/* 8192 x 8192: far beyond any preview, small enough to hold in memory. */
#define MAX_PIXELS (8192LL * 8192LL)

static void usage(FILE *out) {
  fprintf(
      out,
      "usage: %s REFERENCE.exr TEST.exr [--png SIDE.png] [--json] "
      "[thresholds]\n"
      "       %s REFERENCE.exr --smooth-bound R\n"
      "\n"
      "Compares two linear RGBA OpenEXR frames of the same camera (colour\n"
      "premultiplied by alpha, over black: satf-render -o writes them so)\n"
      "and prints:\n"
      "  coverage IoU     sum min(alpha) / sum max(alpha) over all pixels\n"
      "                   (1 = same silhouette; thin strands count by their\n"
      "                   alpha)\n"
      "  alpha error      mean |alpha_REF - alpha_TEST| over the pixels "
      "either\n"
      "                   frame covers (alpha > 0.05)\n"
      "  luminance SSIM   structure of the luminance (Rec. 709 weights on "
      "the\n"
      "                   premultiplied colour) over the bounding box of "
      "those\n"
      "                   pixels: TEST is first scaled to REFERENCE's mean\n"
      "                   luminance there (exposure-normalised), both are\n"
      "                   divided by REFERENCE's 99.5th percentile and "
      "clamped\n"
      "                   to [0, 1]; SSIM of Wang et al. 2004 (K1 0.01, K2 "
      "0.03)\n"
      "                   over a 7x7 box window, averaged (1 = same "
      "structure)\n"
      "  luminance ratio  mean luminance of TEST / of REFERENCE over the "
      "pixels\n"
      "                   either covers (1 = same brightness)\n"
      "  chroma angle     degrees between the two frames' colours summed "
      "over\n"
      "                   the pixels both cover (0 = same hue and "
      "saturation)\n"
      "Every figure is defined in docs/import.md, \"Measuring fidelity\".\n"
      "\n"
      "options:\n"
      "  --png SIDE.png          write REFERENCE | TEST | difference side by "
      "side:\n"
      "                          the frames over 18%% grey, the difference "
      "as a\n"
      "                          heat map of the exposure-normalised "
      "luminance\n"
      "                          (red-yellow: TEST brighter, blue-cyan: "
      "darker,\n"
      "                          full at half the white level; dark grey: "
      "equal\n"
      "                          where covered; grey: neither covers)\n"
      "  --json                  print the figures as one JSON object "
      "(keys iou,\n"
      "                          alpha, ssim, ssim4, lum, chroma, ...)\n"
      "  --smooth-bound R        also print REFERENCE against itself "
      "blurred by a\n"
      "                          (2R+1)x(2R+1) box (R 1-16): the IoU and "
      "SSIM a\n"
      "                          preview that gets everything right down "
      "to that\n"
      "                          scale but no finer would score (hair a "
      "pixel\n"
      "                          wide scores far below 1 at R = 1); JSON "
      "keys\n"
      "                          bound_iou, bound_ssim\n"
      "  --min-iou X             fail (exit 1) when coverage IoU < X\n"
      "  --min-ssim X            fail when luminance SSIM < X\n"
      "  --min-ssim4 X           fail when SSIM4 (over 4x4 pixel blocks) < "
      "X\n"
      "  --max-alpha-error X     fail when alpha error > X\n"
      "  --max-lum-error X       fail when |luminance ratio - 1| > X\n"
      "  --max-chroma DEG        fail when chroma angle > DEG\n"
      "  -h, --help              this help\n"
      "\n"
      "exit status: 0 figures printed (and every threshold met), 1 a "
      "threshold\n"
      "not met, 2 bad input (sizes differ, a file missing or damaged, a bad\n"
      "option) or the PNG could not be written.\n",
      PROG, PROG);
}

/* A threshold given on the command line: which figure, which side. */
typedef struct threshold {
  const char *flag;
  const char *key; /* the JSON key of the figure */
  int is_min;
  int given;
  double value;
} threshold;

enum { T_IOU, T_SSIM, T_SSIM4, T_ALPHA, T_LUM, T_CHROMA, T_COUNT };

typedef struct options {
  const char *ref, *test, *png;
  int json;
  long bound; /* --smooth-bound's radius, 0: not asked */
  threshold t[T_COUNT];
} options;

/* Parses argv into o; returns -1 to go on, or the exit status. */
static int parse(int argc, char **argv, options *o) {
  static const threshold defaults[T_COUNT] = {
      {"--min-iou", "iou", 1, 0, 0},
      {"--min-ssim", "ssim", 1, 0, 0},
      {"--min-ssim4", "ssim4", 1, 0, 0},
      {"--max-alpha-error", "alpha", 0, 0, 0},
      {"--max-lum-error", "lum", 0, 0, 0},
      {"--max-chroma", "chroma", 0, 0, 0}};
  memset(o, 0, sizeof *o);
  memcpy(o->t, defaults, sizeof defaults);
  satf_cli_args it;
  satf_cli_begin(&it, PROG, argc, argv);
  while (satf_cli_next(&it)) {
    int matched = 0;
    for (int k = 0; k < T_COUNT && !matched; k++)
      if (satf_cli_is(&it, NULL, o->t[k].flag)) {
        matched = 1;
        double hi = k == T_CHROMA ? 180.0 : k == T_LUM ? 1e6 : 1.0;
        double lo = k == T_SSIM ? -1.0 : 0.0;
        if (satf_cli_value_double(&it, lo, hi, &o->t[k].value))
          return 2;
        o->t[k].given = 1;
      }
    if (matched)
      continue;
    if (satf_cli_is(&it, "-h", "--help")) {
      usage(stdout);
      return 0;
    } else if (satf_cli_is(&it, NULL, "--png")) {
      if (satf_cli_value(&it, &o->png))
        return 2;
    } else if (satf_cli_is(&it, NULL, "--smooth-bound")) {
      if (satf_cli_value_int(&it, 1, COMPARE_BOUND_RADIUS_MAX, &o->bound))
        return 2;
    } else if (satf_cli_is(&it, NULL, "--json")) {
      o->json = 1;
    } else if (satf_cli_positional(&it)) {
      if (!o->ref) {
        o->ref = it.arg;
      } else if (!o->test) {
        o->test = it.arg;
      } else {
        fprintf(stderr, "%s: one reference and one test frame, not '%s' too\n",
                PROG, it.arg);
        return 2;
      }
    } else {
      return satf_cli_unknown(&it);
    }
  }
  if (!o->ref || (!o->test && !o->bound)) {
    fprintf(stderr, "%s: give a reference and a test frame (see --help)\n",
            PROG);
    return 2;
  }
  if (!o->test && (o->png || o->json)) {
    fprintf(stderr,
            "%s: a reference alone (its --smooth-bound) takes no --png or "
            "--json\n",
            PROG);
    return 2;
  }
  satf_error err;
  satf_file_role files[3] = {{"the reference", o->ref, 0},
                             {"the test frame", o->test, 0},
                             {"--png", o->png, 1}};
  if (satf_check_distinct_files(files, 3, &err) != SATF_OK ||
      satf_check_output_extension("--png", o->png, ".png", "a PNG image",
                                  &err) != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 2;
  }
  return -1;
}

/* A frame read from an EXR: its R, G, B, A planes. */
typedef struct frame {
  compare_image img;
  float *planes[4];
} frame;

static satf_status load(const char *path, frame *f, satf_error *err) {
  static const char *const names[4] = {"R", "G", "B", "A"};
  memset(f, 0, sizeof *f);
  satf_status st = satf_exr_read(path, names, 4, MAX_PIXELS, NULL, NULL,
                                 &f->img.width, &f->img.height, f->planes, err);
  if (st != SATF_OK)
    return st;
  f->img.name = path;
  f->img.r = f->planes[0], f->img.g = f->planes[1];
  f->img.b = f->planes[2], f->img.a = f->planes[3];
  return compare_check_finite(&f->img, err);
}

static void unload(frame *f) {
  for (int c = 0; c < 4; c++)
    free(f->planes[c]);
}

static double figure(const compare_result *r, int k) {
  switch (k) {
  case T_IOU: return r->iou;
  case T_SSIM: return r->ssim;
  case T_SSIM4: return r->ssim4;
  case T_ALPHA: return r->alpha_error;
  case T_LUM: return fabs(r->lum_ratio - 1.0);
  default: return r->chroma_deg;
  }
}

/* Whether threshold k is given and not met (a NaN figure never meets it). */
static int fails(const threshold *t, const compare_result *r, int k) {
  if (!t->given)
    return 0;
  double v = figure(r, k);
  return t->is_min ? !(v >= t->value) : !(v <= t->value);
}

static void json_string(const char *s) {
  putchar('"');
  for (; *s; s++) {
    unsigned char c = (unsigned char)*s;
    if (c == '"' || c == '\\')
      printf("\\%c", c);
    else if (c < 0x20)
      printf("\\u%04x", c);
    else
      putchar(c);
  }
  putchar('"');
}

static void json_number(const char *key, double v) {
  printf(", \"%s\": ", key);
  if (isfinite(v))
    printf("%.6f", v);
  else
    printf("null");
}

static void print_json(const options *o, const compare_image *img,
                       const compare_result *r, const compare_result *bound) {
  printf("{\"reference\": ");
  json_string(o->ref);
  printf(", \"test\": ");
  json_string(o->test);
  printf(", \"width\": %d, \"height\": %d", img->width, img->height);
  json_number("iou", r->iou);
  json_number("alpha", r->alpha_error);
  json_number("ssim", r->ssim);
  json_number("ssim4", r->ssim4);
  json_number("lum", r->lum_ratio);
  json_number("chroma", r->chroma_deg);
  printf(", \"union_pixels\": %lld, \"both_pixels\": %lld", r->union_px,
         r->both_px);
  json_number("exposure", r->exposure);
  if (o->bound) {
    printf(", \"bound_radius\": %ld", o->bound);
    json_number("bound_iou", bound->iou);
    json_number("bound_ssim", bound->ssim);
  }
  printf(", \"failed\": [");
  int n = 0;
  for (int k = 0; k < T_COUNT; k++)
    if (fails(&o->t[k], r, k))
      printf("%s\"%s\"", n++ ? ", " : "", o->t[k].flag + 2);
  printf("], \"pass\": %s}\n", n ? "false" : "true");
}

static void print_table(const options *o, const compare_image *img,
                        const compare_result *r, const compare_result *bound) {
  printf("reference        %s (%dx%d)\n", o->ref, img->width, img->height);
  printf("test             %s\n", o->test);
  printf("covered pixels   %lld by either (alpha > %.2g), %lld by both\n",
         r->union_px, COMPARE_COVERED, r->both_px);
  printf("coverage IoU     %.4f   sum min(alpha) / sum max(alpha)\n", r->iou);
  printf("alpha error      %.4f   mean |alpha difference| where either "
         "covers\n",
         r->alpha_error);
  printf("luminance SSIM   %.4f   test luminance x %.4g, 7x7 window over "
         "the covered box\n",
         r->ssim, r->exposure);
  printf("SSIM4            %.4f   the same over 4x4 pixel block means (a "
         "wisp's scale)\n",
         r->ssim4);
  if (isfinite(r->lum_ratio))
    printf("luminance ratio  %.4f   mean test / mean reference where either "
           "covers\n",
           r->lum_ratio);
  else
    printf("luminance ratio  n/a      neither frame covers any pixel\n");
  printf("chroma angle     %.4f   degrees between the summed colours where "
         "both cover\n",
         r->chroma_deg);
  if (o->bound)
    printf("smooth bound     IoU %.4f, SSIM %.4f: REFERENCE against itself "
           "blurred by a %ldx%ld box\n",
           bound->iou, bound->ssim, 2 * o->bound + 1, 2 * o->bound + 1);
  for (int k = 0; k < T_COUNT; k++)
    if (o->t[k].given)
      printf("check %-18s %s %.4g: %s\n", o->t[k].flag,
             o->t[k].is_min ? ">=" : "<=", o->t[k].value,
             fails(&o->t[k], r, k) ? "FAILED" : "ok");
}

/* REFERENCE --smooth-bound R without a test frame: the bound alone. */
static int bound_only(const options *o, frame *ref) {
  compare_result bound;
  satf_error err;
  satf_status st = compare_smooth_bound(&ref->img, (int)o->bound, &bound, &err);
  if (st == SATF_OK)
    printf("reference        %s (%dx%d)\n"
           "smooth bound     IoU %.4f, SSIM %.4f: REFERENCE against itself "
           "blurred by a %ldx%ld box\n",
           o->ref, ref->img.width, ref->img.height, bound.iou, bound.ssim,
           2 * o->bound + 1, 2 * o->bound + 1);
  else
    fprintf(stderr, "%s: %s\n", PROG, err.message);
  unload(ref);
  return st == SATF_OK ? 0 : 2;
}

int main(int argc, char **argv) {
  options o;
  int rc = parse(argc, argv, &o);
  if (rc >= 0)
    return rc;
  satf_error err;
  frame ref, test;
  satf_status st = load(o.ref, &ref, &err);
  if (st == SATF_OK && !o.test)
    return bound_only(&o, &ref);
  if (st == SATF_OK) {
    st = load(o.test, &test, &err);
    if (st != SATF_OK)
      unload(&test);
  }
  if (st != SATF_OK) {
    unload(&ref);
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 2;
  }
  compare_result res, bound;
  memset(&bound, 0, sizeof bound);
  st = compare_measure(&ref.img, &test.img, &res, &err);
  if (st == SATF_OK && o.bound)
    st = compare_smooth_bound(&ref.img, (int)o.bound, &bound, &err);
  if (st == SATF_OK && o.png)
    st = compare_write_side(&ref.img, &test.img, &res, o.png, &err);
  if (st == SATF_OK) {
    if (res.union_px == 0)
      fprintf(stderr,
              "%s: warning: neither frame covers any pixel "
              "(alpha > 0.05 nowhere)\n",
              PROG);
    if (o.json)
      print_json(&o, &ref.img, &res, &bound);
    else
      print_table(&o, &ref.img, &res, &bound);
    rc = 0;
    for (int k = 0; k < T_COUNT; k++)
      if (fails(&o.t[k], &res, k))
        rc = 1;
  } else {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    rc = 2;
  }
  unload(&ref);
  unload(&test);
  return rc;
}
