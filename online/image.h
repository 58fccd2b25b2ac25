/* image.h - owns the renderer's frame in memory and on disk: a float image
 * of named planar channels ("R", "G", "B", "A" for the beauty pass, plus
 * AOVs named like "diffuse.R" or single-channel "shadow"), written as
 * OpenEXR (through db/exr_io.h) or as an 8-bit sRGB PNG for viewing.
 *
 * Row order: every plane is stored TOP row first (image convention, as
 * EXR and PNG store them). GL reads back bottom row first; convert with
 * satf_image_store_interleaved(..., SATF_ROWS_BOTTOM_UP, ...).
 *
 * Colour is linear and, where an alpha channel exists, premultiplied by
 * alpha (what "over" blending in the renderer produces and what EXR
 * expects). Library satf_image. */
#ifndef SATF_ONLINE_IMAGE_H
#define SATF_ONLINE_IMAGE_H

#include "satf/satf.h"

#define SATF_IMAGE_MAX_CHANNELS 64
#define SATF_IMAGE_MAX_SIDE 32768
#define SATF_IMAGE_MAX_NAME 255

typedef struct satf_image satf_image;

typedef enum satf_row_order {
  SATF_ROWS_TOP_DOWN, /* first row in memory is the top of the picture */
  SATF_ROWS_BOTTOM_UP /* first row is the bottom (glReadPixels) */
} satf_row_order;

/* Creates a width x height image with nchannels channels named names[i]
 * (copied; non-empty, unique, at most SATF_IMAGE_MAX_NAME bytes), all
 * pixels zero. */
satf_status satf_image_create(int width, int height, const char *const *names,
                              int nchannels, satf_image **out, satf_error *err);
void satf_image_destroy(satf_image *img);

int satf_image_width(const satf_image *img);
int satf_image_height(const satf_image *img);
int satf_image_channel_count(const satf_image *img);
const char *satf_image_channel_name(const satf_image *img, int channel);
/* Index of the channel called name, or -1. */
int satf_image_channel_index(const satf_image *img, const char *name);
/* width * height floats, top row first; NULL for a bad index. */
float *satf_image_plane(satf_image *img, int channel);
const float *satf_image_const_plane(const satf_image *img, int channel);

/* Scatters interleaved pixels (src_channels floats per pixel, width x
 * height pixels, rows in `order`) into channels: component k goes to the
 * channel named names[k], or is skipped when names[k] is NULL. An unknown
 * name is an error and nothing is written. */
satf_status satf_image_store_interleaved(satf_image *img, const float *src,
                                         int src_channels,
                                         const char *const *names,
                                         satf_row_order order, satf_error *err);

/* Writes every channel as HALF with ZIP compression. */
satf_status satf_image_write_exr(const satf_image *img, const char *path,
                                 satf_error *err);
/* Writes every channel as 32-bit FLOAT with ZIP compression (for AOVs like
 * depth that half precision would ruin). */
satf_status satf_image_write_exr_float(const satf_image *img, const char *path,
                                       satf_error *err);

/* Writes channels R, G, B (and A if present) as an 8-bit sRGB PNG: RGBA
 * when the image has A, RGB otherwise. Alpha is kept: colour is divided by
 * alpha (PNG stores straight alpha) before the sRGB transfer function;
 * alpha itself is stored linearly, as PNG requires. Values are clamped to
 * [0, 1]; NaN becomes 0. Written through a temporary file renamed into
 * place. */
satf_status satf_image_write_png(const satf_image *img, const char *path,
                                 satf_error *err);
/* Same for one layer: "LAYER.R", "LAYER.G", "LAYER.B" (+ "LAYER.A"), or a
 * single channel named LAYER (e.g. "shadow"), written as 8-bit grey. */
satf_status satf_image_write_png_layer(const satf_image *img, const char *layer,
                                       const char *path, satf_error *err);

#endif
