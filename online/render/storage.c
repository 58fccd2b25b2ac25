/* storage.c - see storage.h. */
#include "storage.h"

#include <stdint.h>

void storage_upload(GLuint buf, size_t bytes, const void *data) {
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buf);
  glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(bytes > 0 ? bytes : 4),
               data, GL_STATIC_DRAW);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
}

satf_status storage_fits(size_t n, size_t size, const char *what,
                         const char *as, satf_error *err) {
  GLint64 most = 0; /* at least 2^27 bytes (OpenGL 4.3) */
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &most);
  if (n > (size_t)INT32_MAX || (double)n * (double)size > (double)most)
    return satf_error_set(err, SATF_ERR_INCOMPATIBLE,
                          "database of %zu %s (%.0f MB as %s): more than the "
                          "GPU's maps can read in one buffer (%.0f MB here); "
                          "use the CPU's maps (--maps cpu)",
                          n, what, (double)n * (double)size * 1e-6, as,
                          (double)most * 1e-6);
  return SATF_OK;
}
