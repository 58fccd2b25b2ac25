/* lod_frame.c - owns the level of detail's per-frame state (lod.h has
 * the rules): each instance's level and proxy for the camera, the frame's
 * LOD mix, and the buffer of the instances' mean alpha per shell layer
 * that glsl/shade_fs.glsl gives the layers a level skips. */
#include <math.h>
#include <string.h>

#include "mat4.h"
#include "renderer_internal.h"
#include "satf/math.h"

void lod_screen_size(const satf_renderer *r, int i, float *width_px,
                     float *sag_px) {
  const inst *in = &r->insts[i];
  const proto *p = &r->protos[in->proto];
  /* pixels per scene unit at distance 1 */
  float focal = 0.5f * (float)r->height /
                tanf(0.5f * r->camera.fov_y * SATF_PI_F / 180.0f);
  /* uniform scale: hierarchy.c refuses the rest */
  float c[3], d[3];
  satf_mat4_point(in->m, p->lod_sphere, c);
  float scale =
      sqrtf(in->m[0] * in->m[0] + in->m[4] * in->m[4] + in->m[8] * in->m[8]);
  for (int a = 0; a < 3; a++)
    d[a] = c[a] - r->camera.position[a];
  float dist =
      sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - scale * p->lod_sphere[3];
  float px = dist > 0.0f ? focal * scale / dist : 1e30f;
  *width_px = p->lod_width * px;
  *sag_px = p->lod_sag * px;
}

void lod_update(satf_renderer *r) {
  satf_render_stats *s = &r->stats;
  memset(s->lod_levels, 0, sizeof s->lod_levels);
  s->lod_single = s->lod_coarse = 0;
  for (int i = 0; i < r->ninsts; i++) {
    inst *in = &r->insts[i];
    int layers = r->protos[in->proto].layers;
    float width = 1e30f, sag = 1e30f;
    if (r->lod)
      lod_screen_size(r, i, &width, &sag);
    in->lod = lod_level(width, layers, &r->lod_opt);
    in->lod_proxy = r->lod ? lod_proxy(width, sag, in->lod_proxy, &r->lod_opt)
                           : LOD_PROXY_FULL;
    int n = (int)in->lod;
    s->lod_levels[n < SATF_LOD_LEVELS ? n : SATF_LOD_LEVELS - 1]++;
    s->lod_single += layers > 1 && in->lod >= (float)lod_level_cap(layers);
    s->lod_coarse += in->lod_proxy != LOD_PROXY_FULL;
  }
}

satf_status lod_alloc(satf_renderer *r, satf_error *err) {
  r->lod_stride = 1;
  for (int m = 0; m < r->nprotos; m++)
    if (r->protos[m].layers > r->lod_stride)
      r->lod_stride = r->protos[m].layers;
  size_t n = (size_t)(r->ninsts > 0 ? r->ninsts : 1) * (size_t)r->lod_stride;
  glGenBuffers(1, &r->lod_alpha);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->lod_alpha);
  glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(n * sizeof(float)), NULL,
               GL_DYNAMIC_DRAW);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  return satf_gl_check("level of detail buffer", err);
}

void lod_mean_alpha(satf_renderer *r, int i) {
  const inst *in = &r->insts[i];
  int layers = r->protos[in->proto].layers;
  size_t n = satf_maps_layer_texels(&in->geom, r->w);
  float mean[SATF_SCENE_MAX_LAYERS];
  /* alpha: the maps' second channel, the physical maps' key-light slice's
   * fourth (maps.h, maps_fiber.h) */
  int channel = r->fiber ? 3 : 1;
  for (int k = 0; k < layers && k < SATF_SCENE_MAX_LAYERS; k++) {
    const float *t = in->texels + (size_t)(k * r->slices) * n * 4;
    double sum = 0.0;
    for (size_t x = 0; x < n; x++)
      sum += t[4 * x + (size_t)channel];
    mean[k] = n > 0 ? (float)(sum / (double)n) : 0.0f;
  }
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->lod_alpha);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER,
                  (GLintptr)((size_t)i * (size_t)r->lod_stride * sizeof(float)),
                  (GLsizeiptr)((size_t)layers * sizeof(float)), mean);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
}

void lod_release(satf_renderer *r) {
  if (r->lod_alpha)
    glDeleteBuffers(1, &r->lod_alpha);
  r->lod_alpha = 0;
}
