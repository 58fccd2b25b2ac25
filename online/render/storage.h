/* storage.h - the shader storage buffers of the maps' compute passes
 * (maps_gpu.h, maps_gpu_fiber.h): a table uploaded, and whether a
 * database's table fits one buffer. */
#ifndef SATF_ONLINE_STORAGE_H
#define SATF_ONLINE_STORAGE_H

#include <stddef.h>

#include "satf/common.h"
#include "satf/gl.h"

/* Buffer buf's store replaced by `bytes` of data (4 where bytes is 0). */
void storage_upload(GLuint buf, size_t bytes, const void *data);
/* SATF_OK where n values of `size` bytes (a database's `what`, as `as`)
 * fit in one shader storage buffer and are indexed by an int; else
 * SATF_ERR_INCOMPATIBLE and a message pointing to the CPU's maps. */
satf_status storage_fits(size_t n, size_t size, const char *what,
                         const char *as, satf_error *err);

#endif
