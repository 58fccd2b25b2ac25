/* maps_gpu_fiber.c - see maps_gpu_fiber.h. */
#include "maps_gpu_fiber.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "half.h"
#include "maps_gpu_bytes.h"

#include "renderer_internal.h"
#include "storage.h"

void maps_gpu_fiber_defines(const satf_renderer *r, char *out, size_t size) {
  maps_fiber_tables t;
  maps_fiber_tables_get(r->fiber, &t);
  size_t used = strlen(out);
  snprintf(out + used, size - used,
           "#define FIBER_CH %d\n#define FIBER_LEVELS %d\n"
           "#define FIBER_LEVEL_OF ivec3(%d, %d, %d)\n#define MP_SIZE %d\n"
           "#define REL_BINS %d\n#define REL_STRIDE %d\n",
           satf_db_channels(t.db), t.levels, t.level_of[0], t.level_of[1],
           t.level_of[2], t.mp_size, t.rel_bins, t.rel_stride);
}

satf_status maps_gpu_fiber_tables(const satf_renderer *r, GLuint prog,
                                  GLuint records, GLuint mp, GLuint rel,
                                  satf_error *err) {
  maps_fiber_tables t;
  maps_fiber_tables_get(r->fiber, &t);
  const satf_build_params *p = satf_db_params(t.db);
  /* the records as halfs, two samples a word: exactly the values the CPU
   * reads (satf_db_relevel finalises its database, rounding them to
   * halfs), in half the loads and bytes of floats */
  size_t values = maps_gpu_fiber_halfs(p, satf_db_channels(t.db));
  if (p->trace.width % 2)
    return satf_error_set(err, SATF_ERR_INCOMPATIBLE,
                          "fibre records of %d samples: the GPU's physical "
                          "maps read two samples at once (an even width); "
                          "use the CPU's maps (--maps cpu)",
                          p->trace.width);
  satf_status st = storage_fits(values, 2, "fibre record values", "halfs", err);
  if (st != SATF_OK)
    return st;
  uint16_t *h = malloc(values * sizeof *h);
  if (!h)
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate %zu fibre record halfs", values);
  half_pack(satf_db_record_channels(t.db, 0, 0, 0), h, values);
  storage_upload(records, maps_gpu_half_bytes(values), h);
  free(h);
  maps_fiber_shape shape = {t.levels, satf_db_channels(t.db), t.mp_size,
                            t.rel_bins, t.rel_stride};
  storage_upload(mp, maps_gpu_mp_floats(&shape) * sizeof(float), t.mp);
  storage_upload(rel, maps_gpu_rel_floats(p, &shape) * sizeof(float), t.rel);
  glUseProgram(prog);
  glUniform1i(glGetUniformLocation(prog, "u_n_view"), p->n_view);
  glUniform1i(glGetUniformLocation(prog, "u_n_light"), p->n_light);
  glUseProgram(0);
  return satf_gl_check("physical maps (GPU) tables", err);
}

void maps_gpu_fiber_lights(const satf_renderer *r, const inst *in, float *out) {
  satf_fiber_light lights[SATF_SCENE_MAX_LIGHTS];
  maps_fiber_lights(&r->view, in->inv, lights);
  memset(out, 0, MAPS_GPU_FIBER_LIGHT_VEC4S * 4 * sizeof(float));
  for (int l = 0; l < r->view.nlights; l++) {
    memcpy(out + 8 * l, lights[l].local, sizeof lights[l].local);
    memcpy(out + 8 * l + 4, lights[l].rgb, sizeof lights[l].rgb);
  }
}
