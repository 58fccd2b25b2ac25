/* fiber_gpu.c - see fiber_gpu.h. */
#include "fiber_gpu.h"

#include <stdlib.h>
#include <string.h>

#include "satf/math.h"

void fiber_from_material(const satf_scene_material *m, satf_fiber *f) {
  memset(f, 0, sizeof *f); /* compared bytewise (fiber_gpu_bind) */
  satf_fiber_material fm;
  fm.melanin = m->melanin;
  fm.redness = m->redness;
  fm.roughness = m->roughness;
  fm.radial_roughness = m->radial_roughness;
  fm.cuticle_tilt = m->cuticle_tilt * SATF_PI_F / 180.0f;
  fm.ior = m->ior;
  if (m->has_absorption)
    satf_fiber_init_sigma_a(f, m->absorption, fm.roughness, fm.radial_roughness,
                            fm.cuticle_tilt, fm.ior);
  else
    satf_fiber_init(f, &fm);
}

/* The global term's tables (fiber_gpu.h), for fibre f and its dual
 * tables tab. Without the memory for them (1.2 MB) they are left unmade:
 * the term then reads zero (the unbound 3-D texture samples black), the
 * forward-scattered light is left out rather than the frame failing. */
static void global_tables(fiber_gpu *g, const satf_fiber *f, const float *tab) {
  const int nh = SATF_FIBER_GLOBAL_NH, nd = SATF_FIBER_GLOBAL_ND;
  const int np = SATF_FIBER_GLOBAL_NPHI;
  size_t n = (size_t)nh * nd * np * 3;
  float *v = malloc(2 * n * sizeof *v);
  if (!v)
    return;
  satf_fiber_dual_global_table(f, tab, FIBER_TABLE_ROWS, g->threads, v, v + n);
  if (!g->global_tabs[0])
    glGenTextures(2, g->global_tabs);
  for (int k = 0; k < 2; k++) {
    glActiveTexture(GL_TEXTURE0 + FIBER_TABLE_UNIT + 1 + k);
    glBindTexture(GL_TEXTURE_3D, g->global_tabs[k]);
    glTexImage3D(GL_TEXTURE_3D, 0, GL_RGB32F, nh, nd, np, 0, GL_RGB, GL_FLOAT,
                 v + (size_t)k * n);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  }
  free(v);
}

void fiber_gpu_bind(fiber_gpu *g, const satf_scene_material *m, GLuint p) {
  satf_fiber f;
  fiber_from_material(m, &f);
  /* made and bound on its own unit: whatever texture is bound on the
   * active one (a deep opacity map) stays */
  glActiveTexture(GL_TEXTURE0 + FIBER_TABLE_UNIT);
  if (!g->has_tables || memcmp(&f, &g->fiber, sizeof f) != 0) {
    float tab[FIBER_TABLE_ROWS * SATF_FIBER_DUAL_FIELDS * 3];
    satf_fiber_dual_tables(&f, FIBER_TABLE_ROWS, tab);
    if (!g->tables)
      glGenTextures(1, &g->tables);
    glBindTexture(GL_TEXTURE_2D, g->tables);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, SATF_FIBER_DUAL_FIELDS,
                 FIBER_TABLE_ROWS, 0, GL_RGB, GL_FLOAT, tab);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    if (g->with_global)
      global_tables(g, &f, tab);
    glActiveTexture(GL_TEXTURE0 + FIBER_TABLE_UNIT);
    g->fiber = f;
    g->has_tables = 1;
  }
  glBindTexture(GL_TEXTURE_2D, g->tables);
  for (int k = 0; g->with_global && k < 2; k++) {
    glActiveTexture(GL_TEXTURE0 + FIBER_TABLE_UNIT + 1 + k);
    glBindTexture(GL_TEXTURE_3D, g->global_tabs[k]);
  }
  glActiveTexture(GL_TEXTURE0);
  if (g->with_global) {
    glUniform1i(glGetUniformLocation(p, "u_fiber_global"),
                FIBER_TABLE_UNIT + 1);
    glUniform1i(glGetUniformLocation(p, "u_fiber_back"), FIBER_TABLE_UNIT + 2);
  }
  glUniform1i(glGetUniformLocation(p, "u_fiber_tables"), FIBER_TABLE_UNIT);
  glUniform1f(glGetUniformLocation(p, "u_fiber_eta"), f.eta);
  glUniform1f(glGetUniformLocation(p, "u_fiber_s"), f.s);
  glUniform1f(glGetUniformLocation(p, "u_fiber_alpha"), f.alpha);
  glUniform4fv(glGetUniformLocation(p, "u_fiber_v"), 1, f.v);
  glUniform3fv(glGetUniformLocation(p, "u_fiber_sigma_a"), 1, f.sigma_a);
}

void fiber_gpu_release(fiber_gpu *g) {
  if (g->tables)
    glDeleteTextures(1, &g->tables);
  if (g->global_tabs[0])
    glDeleteTextures(2, g->global_tabs);
  memset(g, 0, sizeof *g);
}
