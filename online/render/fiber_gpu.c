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

/* The azimuthal and M_p tables (fiber_gpu.h). Without the memory for
 * them (2.5 MB) they are left unmade: the strands' lobes then read zero. */
static void azimuthal_tables(fiber_gpu *g, const satf_fiber *f) {
  size_t n = (size_t)SATF_FIBER_AZ_LAYERS * SATF_FIBER_AZ_ROWS *
             SATF_FIBER_AZ_COLS * 3;
  size_t nm = (size_t)SATF_FIBER_MP_NODES * SATF_FIBER_MP_NODES * 4;
  float *v = malloc((n > nm ? n : nm) * sizeof *v);
  if (!v)
    return;
  if (!g->mp)
    glGenTextures(1, &g->mp);
  satf_fiber_mp_table(f, f->v[3], SATF_FIBER_MP_NODES, v);
  glActiveTexture(GL_TEXTURE0 + FIBER_AZIMUTHAL_UNIT + 1);
  glBindTexture(GL_TEXTURE_2D, g->mp);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, SATF_FIBER_MP_NODES,
               SATF_FIBER_MP_NODES, 0, GL_RGBA, GL_FLOAT, v);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  satf_fiber_azimuthal_table(f, g->threads, v);
  if (!g->azimuthal)
    glGenTextures(1, &g->azimuthal);
  glActiveTexture(GL_TEXTURE0 + FIBER_AZIMUTHAL_UNIT);
  glBindTexture(GL_TEXTURE_2D_ARRAY, g->azimuthal);
  glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGB32F, SATF_FIBER_AZ_COLS,
               SATF_FIBER_AZ_ROWS, SATF_FIBER_AZ_LAYERS, 0, GL_RGB, GL_FLOAT,
               v);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  /* the light's azimuth is periodic, the inclination clamped */
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
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
    if (g->with_azimuthal)
      azimuthal_tables(g, &f);
    glActiveTexture(GL_TEXTURE0 + FIBER_TABLE_UNIT);
    g->fiber = f;
    g->has_tables = 1;
  }
  glBindTexture(GL_TEXTURE_2D, g->tables);
  for (int k = 0; g->with_global && k < 2; k++) {
    glActiveTexture(GL_TEXTURE0 + FIBER_TABLE_UNIT + 1 + k);
    glBindTexture(GL_TEXTURE_3D, g->global_tabs[k]);
  }
  if (g->with_azimuthal) {
    glActiveTexture(GL_TEXTURE0 + FIBER_AZIMUTHAL_UNIT);
    glBindTexture(GL_TEXTURE_2D_ARRAY, g->azimuthal);
    glUniform1i(glGetUniformLocation(p, "u_fiber_azimuthal"),
                FIBER_AZIMUTHAL_UNIT);
    glActiveTexture(GL_TEXTURE0 + FIBER_AZIMUTHAL_UNIT + 1);
    glBindTexture(GL_TEXTURE_2D, g->mp);
    glUniform1i(glGetUniformLocation(p, "u_fiber_mp"),
                FIBER_AZIMUTHAL_UNIT + 1);
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
  if (g->azimuthal)
    glDeleteTextures(1, &g->azimuthal);
  if (g->mp)
    glDeleteTextures(1, &g->mp);
  memset(g, 0, sizeof *g);
}
