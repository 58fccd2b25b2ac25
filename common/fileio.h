/* fileio.h - crash-safe output: write to "PATH.tmp-PID" next to the target,
 * then rename into place, so a killed process never leaves a half-written
 * file under the final name. */
#ifndef SATF_COMMON_FILEIO_H
#define SATF_COMMON_FILEIO_H

#include <stddef.h>

#include "satf/satf.h"

/* Fills tmp with a temporary path in the same directory as path. */
satf_status satf_temp_path(const char *path, char *tmp, size_t size,
                           satf_error *err);
/* fsyncs tmp and renames it to path; removes tmp on failure. */
satf_status satf_commit_temp(const char *tmp, const char *path,
                             satf_error *err);
/* Writes size bytes to path through a temporary file renamed into place. */
satf_status satf_write_file_atomic(const char *path, const void *data,
                                   size_t size, satf_error *err);
/* Size of a file in bytes, or -1. */
long long satf_file_size(const char *path);

#endif
