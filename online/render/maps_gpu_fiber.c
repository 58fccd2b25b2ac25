/* maps_gpu_fiber.c - see maps_gpu_fiber.h. */
#include "maps_gpu_fiber.h"

#include <stdio.h>
#include <string.h>

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
  /* the records as floats, as the CPU's maps read them (a re-levelled
   * database's values are no halfs) */
  size_t values = (size_t)p->samples * (size_t)p->n_view * (size_t)p->n_light *
                  (size_t)satf_db_channels(t.db) * (size_t)p->trace.width;
  satf_status st =
      storage_fits(values, 4, "fibre record values", "floats", err);
  if (st != SATF_OK)
    return st;
  storage_upload(records, values * sizeof(float),
                 satf_db_record_channels(t.db, 0, 0, 0));
  storage_upload(mp, (size_t)t.mp_size * (size_t)t.mp_size * 4 * sizeof(float),
                 t.mp);
  storage_upload(rel,
                 (size_t)p->samples * (size_t)t.rel_bins *
                     (size_t)t.rel_stride * sizeof(float),
                 t.rel);
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
