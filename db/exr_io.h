/* exr_io.h - the one place satf reads and writes OpenEXR files, through
 * OpenEXRCore: single-part scanline images of planar float channels, plus a
 * callback for custom header attributes. Used by the HRIR database (whose
 * container is an EXR image) and by the renderer's frame output. */
#ifndef SATF_DB_EXR_IO_H
#define SATF_DB_EXR_IO_H

#include <openexr.h>

#include "satf/satf.h"

typedef struct satf_exr_channel {
  const char *name;
  const float *data; /* width x height, row-major, top row first */
} satf_exr_channel;

/* Adds custom attributes to the part before the header is written. */
typedef satf_status (*satf_exr_attr_writer)(void *ctx, exr_context_t exr,
                                            int part, satf_error *err);
/* Inspects the header after it is read and before any pixel is allocated;
 * returning non-OK aborts the read with that error. */
typedef satf_status (*satf_exr_attr_reader)(void *ctx, exr_const_context_t exr,
                                            int part, int width, int height,
                                            satf_error *err);

typedef struct satf_exr_write_opts {
  exr_pixel_type_t pixel_type;   /* EXR_PIXEL_HALF or EXR_PIXEL_FLOAT */
  exr_compression_t compression; /* e.g. EXR_COMPRESSION_ZIP */
  satf_exr_attr_writer attrs;    /* may be NULL */
  void *attrs_ctx;
} satf_exr_write_opts;

/* Writes through a temporary file renamed into place. */
satf_status satf_exr_write(const char *path, int width, int height,
                           const satf_exr_channel *channels, int nchannels,
                           const satf_exr_write_opts *opts, satf_error *err);

/* Reads the named channels of a single-part scanline file into planes[i]
 * (malloc'd, width*height floats each, caller frees). A channel missing
 * from the file is an error. max_pixels bounds width*height. */
satf_status satf_exr_read(const char *path, const char *const *names,
                          int nnames, long long max_pixels,
                          satf_exr_attr_reader attrs, void *attrs_ctx,
                          int *width, int *height, float **planes,
                          satf_error *err);

#endif
