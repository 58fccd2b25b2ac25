/* strands.c - owns the strand path (satf_renderer_set_strands): the
 * scene's source strands drawn as ribbons of their own width (ribbons.c)
 * in the clusters' place, under the same lights, material, shading model
 * and meshes, with a deep opacity map of the strands themselves (kept
 * while the lights, the strands and the scene stand: draw_dom_lights). Slow
 * next to the clusters, but what they approximate: the two images differ
 * only by the clusters. */
#include "renderer_internal.h"

#include <string.h>

#include "depth.h"
#include "draw.h"
#include "path.h"
#include "satf/common.h"

static void strands_destroy(satf_renderer *r) {
  strands_gpu_destroy(r->strands);
  r->strands = NULL;
}

/* Grows the view's bounds by the strands; called every frame, since a
 * scene switch (satf_renderer_set_scene) takes the new scene's bounds. */
static void grow_bounds(satf_renderer *r, const strands_gpu *s) {
  float lo[3], hi[3];
  strands_gpu_bounds(s, lo, hi);
  view_grow(&r->view, lo, hi);
}

satf_status satf_renderer_set_strands(satf_renderer *r, int n_strands,
                                      const int *counts, const float *xyz,
                                      const float *thickness,
                                      float default_width, satf_error *err) {
  strands_gpu *s = NULL;
  /* with the list program: the depth AOV sorts the strands' fragments */
  satf_status st = strands_gpu_create(n_strands, counts, xyz, thickness,
                                      default_width, 1, 1, &s, err);
  if (st != SATF_OK)
    return st;
  strands_destroy(r);
  r->strands = s;
  r->dom.valid = r->fill_dom.valid = 0; /* other hair casts the shadows */
  if (s)
    grow_bounds(r, s);
  return SATF_OK;
}

int satf_renderer_strand_count(const satf_renderer *r) {
  return strands_gpu_count(r->strands);
}

/* The deep opacity map with the strands in the clusters' place: the first
 * hair's depth from the strand segments and the meshes, then each
 * segment's coverage summed into the slab it falls in. */
static void dom_strands(satf_renderer *r, void *ctx, int opacity) {
  strands_gpu_dom(r, ctx, opacity);
}

/* The strand path's deep opacity map slab over the cluster path's (both
 * at least a strand deep, below). Against Cycles (compare-cycles.sh,
 * 640x480), the shared ponytail's strands front-lit / back-lit come to
 * luminance 0.94 / 0.92 at one half and 1.09 / 1.27 at the clusters' own
 * slab; a straight curtain's to 0.92 and 1.13. */
#define STRAND_SLAB_SHARE 0.5f

/* The scale of the deep opacity map's slabs (dom_place): the scene's
 * shell clusters' (hierarchy_shell_radius), as the cluster path's,
 * whatever the share of single strands, but STRAND_SLAB_SHARE of it, since
 * a strand's alpha lies at its own depth and a shell cluster's at its
 * outer shell's; in a scene without shells the cluster path draws the
 * same strands as these, with the same slabs. */
static float slab_scale(const satf_renderer *r) {
  int shells = 0;
  float radius = hierarchy_shell_radius(r, &shells);
  return shells > 0 ? STRAND_SLAB_SHARE * radius : radius;
}

/* The slabs are at least a strand deep: the strands' median width, or the
 * clusters' density strand diameter where the strands have none. */
static float hair_width(const satf_renderer *r) {
  float w = strands_gpu_width(r->strands);
  return w > 0.0f ? w : hierarchy_density_width(r);
}

/* The depth AOV's fill (depth.h): every fragment, whole or partly
 * covered, into the per-pixel arrays. */
static void depth_fill(satf_renderer *r, void *ctx, const float viewproj[16],
                       int mode) {
  strands_gpu *s = ctx;
  strands_gpu_begin(r, s, SATF_AOV_DEPTH, viewproj, mode);
  strands_gpu_draw(s, 0, strands_gpu_segments(s));
}

static satf_status strands_frame(satf_renderer *r, satf_aov aov, int refresh,
                                 satf_frame_timing *timing, satf_error *err) {
  strands_gpu *s = r->strands;
  satf_frame_timing t;
  memset(&t, 0, sizeof t);
  double t0 = satf_now_seconds();
  grow_bounds(r, s);
  /* the opacity map's passes add or keep the nearest, in any order */
  strands_gpu_sort(s, r->view.camera.position);
  double t1 = satf_now_seconds();
  if (refresh && r->effects.cluster_shadows)
    draw_dom_lights(r, slab_scale(r), hair_width(r), dom_strands, s);
  glFinish();
  double t2 = satf_now_seconds();
  float viewproj[16];
  view_camera(&r->view, viewproj);
  if (aov == SATF_AOV_DEPTH) {
    satf_status st = depth_lists(r, viewproj, depth_fill, s, err);
    if (st != SATF_OK)
      return st;
  } else {
    draw_begin_frame(r, aov, viewproj); /* the meshes */
    strands_gpu_composite(r, s, aov, viewproj);
  }
  glFinish();
  double t3 = satf_now_seconds();
  /* Table 1's stages: sorting the segments stands for I, the strands'
   * opacity map for S, their shading for L; there are no maps (C, M) */
  t.index_ms = 1e3 * (t1 - t0);
  t.shadow_ms = 1e3 * (t2 - t1);
  t.lighting_ms = 1e3 * (t3 - t2);
  t.total_ms = 1e3 * (t3 - t0);
  if (timing)
    *timing = t;
  r->stats.overflow_pixels = 0;
  return satf_gl_check("strand frame", err);
}

const render_path strands_path = {"strands", NULL, strands_frame,
                                  strands_destroy};
