/* image.c - the renderer's frame in memory and on disk (satf/render.h). */
#define _POSIX_C_SOURCE 200809L
#include "satf/render.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"

struct satf_image {
  int width, height, nchannels;
  char *names[SATF_IMAGE_MAX_CHANNELS];
  float *data;         /* nchannels planes of width * height, top row first */
  float background[3]; /* behind the premultiplied R, G, B */
  /* the camera it was seen from (satf_image_set_camera), row-major */
  int has_camera;
  float world_to_camera[16], world_to_ndc[16];
};

static size_t plane_size(const satf_image *img) {
  return (size_t)img->width * (size_t)img->height;
}

void satf_image_destroy(satf_image *img) {
  if (!img)
    return;
  for (int c = 0; c < img->nchannels; c++)
    free(img->names[c]);
  free(img->data);
  free(img);
}

static satf_status check_names(const char *const *names, int nchannels,
                               satf_error *err) {
  for (int c = 0; c < nchannels; c++) {
    if (!names[c] || names[c][0] == '\0')
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "image: channel %d has an empty name", c);
    if (strlen(names[c]) > SATF_IMAGE_MAX_NAME)
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "image: channel name '%.40s...' is longer than "
                            "%d bytes",
                            names[c], SATF_IMAGE_MAX_NAME);
    for (int d = 0; d < c; d++)
      if (strcmp(names[c], names[d]) == 0)
        return satf_error_set(err, SATF_ERR_ARGUMENT,
                              "image: channel name '%s' appears twice",
                              names[c]);
  }
  return SATF_OK;
}

satf_status satf_image_create(int width, int height, const char *const *names,
                              int nchannels, satf_image **out,
                              satf_error *err) {
  *out = NULL;
  if (width <= 0 || height <= 0 || width > SATF_IMAGE_MAX_SIDE ||
      height > SATF_IMAGE_MAX_SIDE)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "image: size %dx%d outside 1..%d per side", width,
                          height, SATF_IMAGE_MAX_SIDE);
  if (nchannels <= 0 || nchannels > SATF_IMAGE_MAX_CHANNELS)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "image: %d channels (need 1..%d)", nchannels,
                          SATF_IMAGE_MAX_CHANNELS);
  satf_status st = check_names(names, nchannels, err);
  if (st != SATF_OK)
    return st;
  satf_image *img = calloc(1, sizeof *img);
  if (!img)
    return satf_error_set(err, SATF_ERR_NOMEM, "image: out of memory");
  img->width = width;
  img->height = height;
  img->data = calloc(plane_size(img) * (size_t)nchannels, sizeof(float));
  for (int c = 0; c < nchannels && img->data; c++) {
    img->names[c] = strdup(names[c]);
    if (!img->names[c])
      break;
    img->nchannels = c + 1;
  }
  if (!img->data || img->nchannels != nchannels) {
    satf_image_destroy(img);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "image: cannot allocate %dx%d x %d channels", width,
                          height, nchannels);
  }
  *out = img;
  return SATF_OK;
}

int satf_image_width(const satf_image *img) { return img->width; }
int satf_image_height(const satf_image *img) { return img->height; }
int satf_image_channel_count(const satf_image *img) { return img->nchannels; }

const char *satf_image_channel_name(const satf_image *img, int channel) {
  return channel >= 0 && channel < img->nchannels ? img->names[channel] : NULL;
}

int satf_image_channel_index(const satf_image *img, const char *name) {
  for (int c = 0; name && c < img->nchannels; c++)
    if (strcmp(img->names[c], name) == 0)
      return c;
  return -1;
}

float *satf_image_plane(satf_image *img, int channel) {
  if (channel < 0 || channel >= img->nchannels)
    return NULL;
  return img->data + plane_size(img) * (size_t)channel;
}

const float *satf_image_const_plane(const satf_image *img, int channel) {
  if (channel < 0 || channel >= img->nchannels)
    return NULL;
  return img->data + plane_size(img) * (size_t)channel;
}

satf_status satf_image_store_interleaved(satf_image *img, const float *src,
                                         int src_channels,
                                         const char *const *names,
                                         satf_row_order order,
                                         satf_error *err) {
  if (src_channels <= 0 || src_channels > SATF_IMAGE_MAX_CHANNELS)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "image: %d interleaved components (need 1..%d)",
                          src_channels, SATF_IMAGE_MAX_CHANNELS);
  if (order != SATF_ROWS_TOP_DOWN && order != SATF_ROWS_BOTTOM_UP)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "image: unknown row order %d",
                          (int)order);
  int target[SATF_IMAGE_MAX_CHANNELS];
  for (int k = 0; k < src_channels; k++) {
    target[k] = names[k] ? satf_image_channel_index(img, names[k]) : -1;
    if (names[k] && target[k] < 0)
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "image: no channel named '%s'", names[k]);
  }
  size_t w = (size_t)img->width, h = (size_t)img->height;
  size_t stride = (size_t)src_channels;
  for (int k = 0; k < src_channels; k++) {
    if (target[k] < 0)
      continue;
    float *dst = satf_image_plane(img, target[k]);
    for (size_t y = 0; y < h; y++) {
      size_t src_row = order == SATF_ROWS_BOTTOM_UP ? h - 1 - y : y;
      const float *s = src + src_row * w * stride + (size_t)k;
      for (size_t x = 0; x < w; x++)
        dst[y * w + x] = s[x * stride];
    }
  }
  return SATF_OK;
}

void satf_image_set_background(satf_image *img, const float rgb[3]) {
  memcpy(img->background, rgb, sizeof img->background);
}

void satf_image_background(const satf_image *img, float rgb[3]) {
  memcpy(rgb, img->background, sizeof img->background);
}

/* Premultiplied "over": C = C_fg + (1 - A_fg) C_bg (Porter & Duff 1984). */
void satf_image_flatten(satf_image *img) {
  static const char *const names[4] = {"R", "G", "B", "A"};
  int idx[4];
  for (int k = 0; k < 4; k++)
    if ((idx[k] = satf_image_channel_index(img, names[k])) < 0)
      return;
  const float *a = satf_image_const_plane(img, idx[3]);
  for (int c = 0; c < 3; c++) {
    float *p = satf_image_plane(img, idx[c]);
    for (size_t i = 0; i < plane_size(img); i++)
      p[i] += (1.0f - a[i]) * img->background[c];
    img->background[c] = 0.0f;
  }
}

/* ---- OpenEXR ----------------------------------------------------------- */

void satf_image_set_camera(satf_image *img, const float world_to_camera[16],
                           const float world_to_ndc[16]) {
  memcpy(img->world_to_camera, world_to_camera, sizeof img->world_to_camera);
  memcpy(img->world_to_ndc, world_to_ndc, sizeof img->world_to_ndc);
  img->has_camera = 1;
}

int satf_image_camera(const satf_image *img, float world_to_camera[16],
                      float world_to_ndc[16]) {
  if (img->has_camera) {
    memcpy(world_to_camera, img->world_to_camera, sizeof img->world_to_camera);
    memcpy(world_to_ndc, img->world_to_ndc, sizeof img->world_to_ndc);
  }
  return img->has_camera;
}

/* The camera as the standard header attributes (OpenEXR's standard
 * attributes, as Nuke and Blender write them): Imath matrices multiply row
 * vectors, so they are the transposes of the column-vector matrices the
 * renderer keeps. */
static satf_status camera_attrs(void *ctx, exr_context_t exr, int part,
                                satf_error *err) {
  const satf_image *img = ctx;
  if (!img->has_camera)
    return SATF_OK;
  const float *m[2] = {img->world_to_camera, img->world_to_ndc};
  static const char *const names[2] = {"worldToCamera", "worldToNDC"};
  for (int k = 0; k < 2; k++) {
    exr_attr_m44f_t t;
    for (int i = 0; i < 4; i++)
      for (int j = 0; j < 4; j++)
        t.m[4 * i + j] = m[k][4 * j + i];
    if (exr_attr_set_m44f(exr, part, names[k], &t) != EXR_ERR_SUCCESS)
      return satf_error_set(err, SATF_ERR_IO, "cannot write the %s attribute",
                            names[k]);
  }
  return SATF_OK;
}

/* The channel's name in a file of layers (AOVs): every channel of one
 * view layer, LAYER.PASS.CHANNEL, as Blender and Nuke write multilayer
 * files, the beauty as its "Combined" pass and Z as "Depth" (a compositor
 * lists a channel without a layer under an unnamed layer, which Blender's
 * image node cannot select). A file without layers keeps R G B A Z. */
static void file_channel_name(const char *name, int layered, char *out,
                              size_t size) {
  if (!layered)
    snprintf(out, size, "%s", name);
  else if (strchr(name, '.'))
    snprintf(out, size, "%s.%s", SATF_IMAGE_VIEW_LAYER, name);
  else
    snprintf(out, size, "%s.%s.%s", SATF_IMAGE_VIEW_LAYER,
             strcmp(name, "Z") == 0 ? "Depth" : "Combined", name);
}

static satf_status write_exr(const satf_image *img, const char *path,
                             exr_pixel_type_t type, satf_error *err) {
  satf_exr_channel channels[SATF_IMAGE_MAX_CHANNELS];
  exr_pixel_type_t types[SATF_IMAGE_MAX_CHANNELS];
  char names[SATF_IMAGE_MAX_CHANNELS][SATF_IMAGE_MAX_NAME + 32];
  int layered = 0;
  for (int c = 0; c < img->nchannels; c++)
    layered |= strchr(img->names[c], '.') != NULL;
  for (int c = 0; c < img->nchannels; c++) {
    file_channel_name(img->names[c], layered, names[c], sizeof names[c]);
    channels[c].name = names[c];
    channels[c].data = satf_image_const_plane(img, c);
    /* depth stays FLOAT in a HALF file: HALF ends at 65504 (Blender's and
     * Nuke's no-hit depth is 1e10) and keeps 11 bits */
    types[c] = strcmp(img->names[c], "Z") == 0 ? EXR_PIXEL_FLOAT : type;
  }
  satf_exr_write_opts opts = {type, EXR_COMPRESSION_ZIP, camera_attrs,
                              (void *)img, 0};
  return satf_exr_write_typed(path, img->width, img->height, channels, types,
                              img->nchannels, &opts, err);
}

satf_status satf_image_write_exr(const satf_image *img, const char *path,
                                 satf_error *err) {
  return write_exr(img, path, EXR_PIXEL_HALF, err);
}

satf_status satf_image_write_exr_float(const satf_image *img, const char *path,
                                       satf_error *err) {
  return write_exr(img, path, EXR_PIXEL_FLOAT, err);
}

/* ---- PNG --------------------------------------------------------------- */

/* The sRGB transfer function (IEC 61966-2-1), piecewise: linear toe below
 * 0.0031308, 1/2.4 power above; quantised to the nearest 8-bit code. */
static unsigned char srgb_encode8(float linear) {
  if (!(linear > 0.0f))
    return 0;
  if (linear >= 1.0f)
    return 255;
  double v = linear <= 0.0031308 ? 12.92 * linear
                                 : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
  return (unsigned char)(v * 255.0 + 0.5);
}

static unsigned char linear_encode8(float v) {
  if (!(v > 0.0f))
    return 0;
  if (v >= 1.0f)
    return 255;
  return (unsigned char)(v * 255.0f + 0.5f);
}

typedef struct png_msg {
  char text[256];
} png_msg;

static void on_png_error(png_structp png, png_const_charp msg) {
  png_msg *m = png_get_error_ptr(png);
  if (m)
    snprintf(m->text, sizeof m->text, "%s", msg);
  png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg) {
  (void)png, (void)msg;
}

static satf_status png_encode(FILE *f, const unsigned char *pixels, int width,
                              int height, int ncomp, const char *path,
                              satf_error *err) {
  png_msg msg = {{0}};
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &msg,
                                            on_png_error, on_png_warning);
  png_infop info = png ? png_create_info_struct(png) : NULL;
  if (!info) {
    png_destroy_write_struct(&png, NULL);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "%s: cannot set up the PNG encoder", path);
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot write PNG: %s", path,
                          msg.text);
  }
  static const int color_type[5] = {0, PNG_COLOR_TYPE_GRAY,
                                    PNG_COLOR_TYPE_GRAY_ALPHA,
                                    PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGBA};
  png_init_io(png, f);
  png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8,
               color_type[ncomp], PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  size_t row = (size_t)width * (size_t)ncomp;
  for (int y = 0; y < height; y++)
    png_write_row(png, pixels + (size_t)y * row);
  png_write_end(png, NULL);
  png_destroy_write_struct(&png, &info);
  return SATF_OK;
}

/* Finds the colour channels of a layer: "R","G","B"[,"A"] for the empty
 * layer, "L.R","L.G","L.B"[,"L.A"], or the single channel "L.Y" or "L".
 * Returns the component count (1, 3 or 4; alpha last) or 0. */
static int find_layer(const satf_image *img, const char *layer, int idx[4]) {
  static const char *const suffix[4] = {"R", "G", "B", "A"};
  char name[SATF_IMAGE_MAX_NAME + 3];
  int n = 0;
  for (int k = 0; k < 4; k++) {
    if (layer[0])
      snprintf(name, sizeof name, "%s.%s", layer, suffix[k]);
    else
      snprintf(name, sizeof name, "%s", suffix[k]);
    idx[k] = satf_image_channel_index(img, name);
    if (idx[k] < 0)
      break;
    n++;
  }
  if (n >= 3)
    return n;
  if (!layer[0])
    return 0;
  snprintf(name, sizeof name, "%s.Y", layer);
  idx[0] = satf_image_channel_index(img, name);
  if (idx[0] < 0)
    idx[0] = satf_image_channel_index(img, layer);
  return idx[0] >= 0 ? 1 : 0;
}

/* Converts premultiplied linear float to straight-alpha sRGB bytes. */
static void encode_pixels(const satf_image *img, const int idx[4], int ncomp,
                          unsigned char *out) {
  size_t npix = plane_size(img);
  int has_alpha = ncomp == 4;
  int ncolor = has_alpha ? 3 : ncomp;
  const float *alpha = has_alpha ? satf_image_const_plane(img, idx[3]) : NULL;
  for (size_t i = 0; i < npix; i++) {
    float a = alpha ? alpha[i] : 1.0f;
    for (int k = 0; k < ncolor; k++) {
      float c = satf_image_const_plane(img, idx[k])[i];
      if (alpha)
        c = a > 0.0f ? c / a : 0.0f;
      out[i * (size_t)ncomp + (size_t)k] = srgb_encode8(c);
    }
    if (alpha)
      out[i * (size_t)ncomp + 3] = linear_encode8(a);
  }
}

satf_status satf_image_write_png_layer(const satf_image *img, const char *layer,
                                       const char *path, satf_error *err) {
  if (!layer)
    layer = "";
  int idx[4];
  int ncomp = find_layer(img, layer, idx);
  if (ncomp == 0)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: image has no layer '%s' (need channels "
                          "%s%sR, %s%sG, %s%sB or a single channel of that "
                          "name)",
                          path, layer, layer, layer[0] ? "." : "", layer,
                          layer[0] ? "." : "", layer, layer[0] ? "." : "");
  unsigned char *pixels = malloc(plane_size(img) * (size_t)ncomp);
  if (!pixels)
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "%s: cannot allocate %dx%d PNG pixels", path,
                          img->width, img->height);
  encode_pixels(img, idx, ncomp, pixels);

  char tmp[4096];
  satf_status st = satf_temp_path(path, tmp, sizeof tmp, err);
  FILE *f = st == SATF_OK ? fopen(tmp, "wb") : NULL;
  if (st == SATF_OK && !f)
    st = satf_error_set(err, SATF_ERR_IO, "%s: cannot create %s: %s", path, tmp,
                        strerror(errno));
  if (f) {
    st = png_encode(f, pixels, img->width, img->height, ncomp, path, err);
    if (fclose(f) != 0 && st == SATF_OK)
      st = satf_error_set(err, SATF_ERR_IO, "%s: cannot write %s: %s", path,
                          tmp, strerror(errno));
    if (st == SATF_OK)
      st = satf_commit_temp(tmp, path, err);
    else
      remove(tmp);
  }
  free(pixels);
  return st;
}

satf_status satf_image_write_png(const satf_image *img, const char *path,
                                 satf_error *err) {
  return satf_image_write_png_layer(img, "", path, err);
}

satf_status satf_image_png_size(const char *path, int *width, int *height,
                                satf_error *err) {
  png_image png;
  memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path))
    return satf_error_set(err, SATF_ERR_FORMAT, "%s: not a readable PNG: %s",
                          path, png.message);
  png.format = PNG_FORMAT_RGBA;
  size_t bytes = PNG_IMAGE_SIZE(png);
  void *pixels =
      png.width <= 16384 && png.height <= 16384 ? malloc(bytes) : NULL;
  if (!pixels) {
    png_image_free(&png);
    return satf_error_set(err, SATF_ERR_FORMAT, "%s: PNG of %ux%u pixels", path,
                          png.width, png.height);
  }
  int ok = png_image_finish_read(&png, NULL, pixels, 0, NULL);
  free(pixels);
  if (!ok)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: damaged PNG: %s", path,
                          png.message);
  *width = (int)png.width;
  *height = (int)png.height;
  return SATF_OK;
}

satf_status satf_image_write_png_rgb(const satf_image *img, const char *path,
                                     satf_error *err) {
  const char *names[3] = {"R", "G", "B"};
  satf_image *rgb = NULL;
  int w = satf_image_width(img), h = satf_image_height(img);
  satf_status st = satf_image_create(w, h, names, 3, &rgb, err);
  const float *a =
      satf_image_const_plane(img, satf_image_channel_index(img, "A"));
  for (int c = 0; c < 3 && st == SATF_OK; c++) {
    const float *src =
        satf_image_const_plane(img, satf_image_channel_index(img, names[c]));
    if (!src) {
      st = satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: image has no channel '%s'", path, names[c]);
      break;
    }
    /* premultiplied "over" the background (Porter & Duff 1984) */
    float *dst = satf_image_plane(rgb, c);
    for (size_t i = 0; i < plane_size(img); i++)
      dst[i] = src[i] + (a ? (1.0f - a[i]) * img->background[c] : 0.0f);
  }
  if (st == SATF_OK)
    st = satf_image_write_png(rgb, path, err);
  satf_image_destroy(rgb);
  return st;
}
