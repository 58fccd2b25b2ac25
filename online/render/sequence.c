/* sequence.c - batch rendering of animation frames (satf/render.h). */
#include "satf/render.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/scene.h"

satf_status satf_sequence_check_pattern(const char *pattern, satf_error *err) {
  int conversions = 0;
  for (const char *p = pattern; *p; p++) {
    if (*p != '%')
      continue;
    const char *q = p + 1;
    while (*q >= '0' && *q <= '9')
      q++;
    if (*q != 'd' || conversions++)
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "%s: a frame pattern needs exactly one integer "
                            "conversion such as %%04d and no other %%",
                            pattern);
    p = q;
  }
  if (conversions != 1)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: a frame pattern needs one integer conversion "
                          "such as %%04d",
                          pattern);
  return SATF_OK;
}

static void frame_path(const char *pattern, int frame, char *out, size_t size) {
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
  snprintf(out, size, pattern, frame); /* checked by check_pattern */
#pragma GCC diagnostic pop
}

/* The EXR at path decodes completely at w x h, with the AOV layers when
 * they were asked for ("shadow.Y" stands for them: written last). */
static int exr_complete(const char *path, int w, int h, int aovs) {
  const char *names[2] = {"A", "shadow.Y"};
  float *planes[2] = {NULL, NULL};
  int fw = 0, fh = 0;
  satf_status st = satf_exr_read(path, names, aovs ? 2 : 1, 1LL << 28, NULL,
                                 NULL, &fw, &fh, planes, NULL);
  free(planes[0]);
  free(planes[1]);
  return st == SATF_OK && fw == w && fh == h;
}

static int png_complete(const char *path, int w, int h) {
  int fw = 0, fh = 0;
  return satf_image_png_size(path, &fw, &fh, NULL) == SATF_OK && fw == w &&
         fh == h;
}

/* --resume skips a frame only when every output it asks for is on disk,
 * complete and of this run's size (a missing PNG, or a frame rendered at
 * another --size, is rendered again), and the contact sheet can take its
 * thumbnail from the EXR. */
static int frame_done(const satf_renderer *r, const satf_sequence_opts *o,
                      const char *exr, const char *png) {
  int w, h;
  satf_renderer_size(r, &w, &h);
  if (!o->resume || (!exr[0] && !png[0]) || (o->contact_sheet && !exr[0]))
    return 0;
  return (!exr[0] || exr_complete(exr, w, h, o->aovs)) &&
         (!png[0] || png_complete(png, w, h));
}

enum { SHEET_COLUMNS = 8, SHEET_SCALE = 4 };

typedef struct sheet {
  satf_image *img;
  int tw, th, columns;
  int first;   /* the frame number of cell 0, for the labels */
  float bg[3]; /* behind the frames' premultiplied colour */
} sheet;

/* 3x5 pixel digits: one byte per row, bit 2 the left column. */
static const unsigned char DIGIT_ROWS[10][5] = {
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7},
    {5, 5, 7, 1, 1}, {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1},
    {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}};

/* Writes the frame number in white on a black box in the top-left corner
 * of cell i, scaled with the thumbnail; nothing when the cell is too small
 * to hold it. */
static void sheet_label(sheet *s, int i, int frame) {
  char text[16];
  int n = snprintf(text, sizeof text, "%d", frame);
  int k = s->th >= 60 ? 2 : 1, bw = (4 * n + 1) * k, bh = 7 * k;
  if (n <= 0 || bw > s->tw || bh > s->th)
    return;
  int cx = (i % s->columns) * s->tw, cy = (i / s->columns) * s->th;
  int sw = satf_image_width(s->img);
  for (int y = 0; y < bh; y++)
    for (int x = 0; x < bw; x++) {
      int gx = x / k - 1, gy = y / k - 1, on = 0;
      if (gy >= 0 && gy < 5 && gx >= 0 && gx % 4 < 3 && gx / 4 < n &&
          text[gx / 4] >= '0' && text[gx / 4] <= '9')
        on = DIGIT_ROWS[text[gx / 4] - '0'][gy] >> (2 - gx % 4) & 1;
      for (int c = 0; c < 3; c++)
        satf_image_plane(s->img, c)[(size_t)(cy + y) * sw + cx + x] =
            on ? 1.0f : 0.0f;
    }
}

/* Box-filtered thumbnail of the R, G, B planes of a frame into cell i,
 * composited over the background by the A plane (rgb[3]; NULL: opaque).
 * "Over" is linear, so the box filter may come first. */
static void sheet_put(sheet *s, const float *const rgb[4], int w, int h,
                      int i) {
  int cx = (i % s->columns) * s->tw, cy = (i / s->columns) * s->th;
  int sw = satf_image_width(s->img);
  for (int c = 0; c < 3; c++) {
    float *dst = satf_image_plane(s->img, c);
    for (int y = 0; y < s->th; y++)
      for (int x = 0; x < s->tw; x++) {
        float sum = 0.0f, alpha = 0.0f;
        int n = 0;
        for (int dy = 0; dy < SHEET_SCALE; dy++)
          for (int dx = 0; dx < SHEET_SCALE; dx++) {
            int px = x * SHEET_SCALE + dx, py = y * SHEET_SCALE + dy;
            if (px < w && py < h) {
              sum += rgb[c][(size_t)py * w + px];
              alpha += rgb[3] ? rgb[3][(size_t)py * w + px] : 1.0f;
              n++;
            }
          }
        /* premultiplied "over" (Porter & Duff 1984) */
        dst[(size_t)(cy + y) * sw + cx + x] =
            n ? (sum + (n - alpha) * s->bg[c]) / (float)n : 0.0f;
      }
  }
  sheet_label(s, i, s->first + i);
}

/* A frame on disk: premultiplied R, G, B, A (or, written with
 * background_in_exr, colour already over the background: A is ignored). */
static satf_status sheet_from_file(sheet *s, const char *path, int i,
                                   int flattened, satf_error *err) {
  const char *names[4] = {"R", "G", "B", "A"};
  float *planes[4] = {NULL, NULL, NULL, NULL};
  int w, h;
  satf_status st =
      satf_exr_read(path, names, 4, 1LL << 28, NULL, NULL, &w, &h, planes, err);
  if (st == SATF_OK) {
    const float *rgb[4] = {planes[0], planes[1], planes[2],
                           flattened ? NULL : planes[3]};
    sheet_put(s, rgb, w, h, i);
  }
  for (int c = 0; c < 4; c++)
    free(planes[c]);
  return st;
}

/* The output patterns and the frame range. */
static satf_status check_opts(const satf_sequence_opts *o, satf_error *err) {
  satf_status st = SATF_OK;
  if (o->exr_pattern)
    st = satf_sequence_check_pattern(o->exr_pattern, err);
  if (st == SATF_OK && o->png_pattern)
    st = satf_sequence_check_pattern(o->png_pattern, err);
  if (st != SATF_OK)
    return st;
  if (o->last < o->first || o->last - o->first > 1000000)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "frame range %d-%d", o->first,
                          o->last);
  return SATF_OK;
}

/* The contact sheet of `count` thumbnails, SHEET_COLUMNS across at most. */
static satf_status sheet_create(const satf_renderer *r, int count, sheet *sh,
                                satf_error *err) {
  const char *names[3] = {"R", "G", "B"};
  int w, h;
  satf_renderer_size(r, &w, &h);
  /* at least one pixel per thumbnail, however small the frames */
  sh->tw = w >= SHEET_SCALE ? w / SHEET_SCALE : 1;
  sh->th = h >= SHEET_SCALE ? h / SHEET_SCALE : 1;
  sh->columns = count < SHEET_COLUMNS ? count : SHEET_COLUMNS;
  int rows = (count + sh->columns - 1) / sh->columns;
  return satf_image_create(sh->tw * sh->columns, sh->th * rows, names, 3,
                           &sh->img, err);
}

/* Frame f of `scene` switched into the renderer (*snap keeps the snapshot
 * the renderer reads), rendered, written to exr and png when they are
 * set, and put on the contact sheet. */
static satf_status render_one(satf_renderer *r, const satf_scene *scene,
                              const satf_sequence_opts *o, int f,
                              const char *exr, const char *png,
                              satf_scene **snap, sheet *sh,
                              satf_frame_timing *t, satf_error *err) {
  satf_scene *next = NULL;
  satf_status st = satf_scene_at_frame(scene, (double)f, &next, err);
  if (st == SATF_OK)
    st = satf_renderer_set_scene(r, next, NULL, err);
  satf_scene_destroy(*snap); /* the renderer now reads `next` */
  *snap = next;
  satf_image *img = NULL;
  if (st == SATF_OK)
    st = satf_renderer_render_image(r, o->aovs, &img, t, err);
  if (st == SATF_OK && o->background_in_exr)
    satf_image_flatten(img); /* the PNG and the sheet are unchanged by it */
  if (st == SATF_OK && exr[0])
    st = satf_image_write_exr(img, exr, err);
  if (st == SATF_OK && png[0])
    st = satf_image_write_png_rgb(img, png, err);
  if (st == SATF_OK && sh->img) {
    const float *rgb[4] = {
        satf_image_const_plane(img, 0), satf_image_const_plane(img, 1),
        satf_image_const_plane(img, 2), satf_image_const_plane(img, 3)};
    satf_image_background(img, sh->bg); /* black once flattened */
    sheet_put(sh, rgb, satf_image_width(img), satf_image_height(img),
              f - o->first);
  }
  satf_image_destroy(img);
  return st;
}

static void timing_add(satf_frame_timing *sum, const satf_frame_timing *t) {
  sum->index_ms += t->index_ms;
  sum->maps_ms += t->maps_ms;
  sum->upload_ms += t->upload_ms;
  sum->lighting_ms += t->lighting_ms;
  sum->shadow_ms += t->shadow_ms;
  sum->total_ms += t->total_ms;
}

static void timing_divide(satf_frame_timing *m, double n) {
  m->index_ms /= n;
  m->maps_ms /= n;
  m->upload_ms /= n;
  m->lighting_ms /= n;
  m->shadow_ms /= n;
  m->total_ms /= n;
}

satf_status satf_sequence_render(satf_renderer *r, const satf_scene *scene,
                                 const satf_sequence_opts *o,
                                 satf_sequence_stats *stats, satf_error *err) {
  memset(stats, 0, sizeof *stats);
  satf_status st = check_opts(o, err);
  if (st != SATF_OK)
    return st;
  int count = o->last - o->first + 1;
  sheet sh = {NULL, 0, 0, SHEET_COLUMNS, o->first, {0, 0, 0}};
  if (o->contact_sheet && (st = sheet_create(r, count, &sh, err)) != SATF_OK)
    return st;
  satf_progress prog;
  satf_progress_begin(&prog, stderr, "rendering", "frames", 1, o->quiet);
  double t0 = satf_now_seconds();
  satf_scene *snap = NULL;
  for (int f = o->first; f <= o->last && st == SATF_OK; f++) {
    if (o->stop && *o->stop) {
      stats->interrupted = 1;
      break;
    }
    char exr[4096] = "", png[4096] = "";
    if (o->exr_pattern)
      frame_path(o->exr_pattern, f, exr, sizeof exr);
    if (o->png_pattern)
      frame_path(o->png_pattern, f, png, sizeof png);
    if (frame_done(r, o, exr, png)) {
      if (sh.img) {
        /* the colour the renderer puts behind its frames (renderer.c) */
        for (int c = 0; c < 3; c++)
          sh.bg[c] = scene->background[c];
        st = sheet_from_file(&sh, exr, f - o->first, o->background_in_exr, err);
      }
      stats->skipped++;
    } else {
      satf_frame_timing t;
      st = render_one(r, scene, o, f, exr, png, &snap, &sh, &t, err);
      if (st == SATF_OK) {
        stats->rendered++;
        timing_add(&stats->mean, &t);
      }
    }
    satf_progress_update(&prog, (size_t)(f - o->first + 1), (size_t)count);
  }
  satf_progress_end(&prog);
  /* hand the renderer back its original scene before the snapshot goes */
  satf_error ignore;
  if (snap)
    satf_renderer_set_scene(r, scene, NULL, &ignore);
  satf_scene_destroy(snap);
  stats->seconds = satf_now_seconds() - t0;
  if (stats->rendered > 0)
    timing_divide(&stats->mean, stats->rendered);
  if (st == SATF_OK && sh.img)
    st = satf_image_write_png(sh.img, o->contact_sheet, err);
  satf_image_destroy(sh.img);
  return st;
}
