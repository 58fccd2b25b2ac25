/* lod_frame.c - owns the level of detail's per-frame state (lod.h has
 * the rules): each instance's level and proxy for the camera, and the
 * frame's LOD mix. */
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
  float focal = 0.5f * (float)r->view.height /
                tanf(0.5f * r->view.camera.fov_y * SATF_PI_F / 180.0f);
  /* uniform scale: hierarchy.c refuses the rest */
  float c[3], d[3];
  satf_mat4_point(in->m, p->lod_sphere, c);
  float scale =
      sqrtf(in->m[0] * in->m[0] + in->m[4] * in->m[4] + in->m[8] * in->m[8]);
  for (int a = 0; a < 3; a++)
    d[a] = c[a] - r->view.camera.position[a];
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
