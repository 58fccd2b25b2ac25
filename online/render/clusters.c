/* clusters.c - owns the SATF cluster path: a frame as SATF's stages in
 * order (Table 1): the look-ups and maps of every instance and their
 * instance data (cluster_cpu.c: I, C, M), the deep opacity map
 * (cluster_dom.c: S), then the shading and composite (cluster_gpu.c: L)
 * by the renderer's compositing mode. */
#include "renderer_internal.h"

#include <string.h>

#include "draw.h"
#include "path.h"
#include "satf/common.h"
#include "shaders.h"

/* The composite of the renderer's mode; exact mode grows the fragment
 * arrays and draws again when a pixel had more fragments than slots, and
 * where a pixel has more than the arrays' largest size draws once more
 * keeping each pixel's nearest fragments (so the frame does not depend on
 * the order fragments arrive in). */
static satf_status composite(satf_renderer *r, satf_aov aov,
                             const float viewproj[16], long *count,
                             satf_error *err) {
  r->stats.overflow_pixels = 0;
  if (aov != SATF_AOV_DEPTH && r->composite == SATF_COMPOSITE_EXACT &&
      sparse_only(r)) {
    draw_begin_frame(r, aov, viewproj); /* the meshes */
    sparse_composite(r, aov, viewproj);
    return SATF_OK;
  }
  /* the depth needs the fragments in depth order: always the arrays */
  if (r->composite == SATF_COMPOSITE_ORDERED && aov != SATF_AOV_DEPTH)
    return cluster_gpu_ordered(r, aov, viewproj, err);
  long over = 0, ignore = 0;
  GLuint most = cluster_gpu_lists(r, aov, viewproj, 0, count, &over);
  int grown = 0;
  /* the colour's resolve reads the pool; the depth's keeps the arrays */
  satf_status st = lists_grow(
      &r->lists, aov == SATF_AOV_DEPTH ? (int)most + 4 : r->lists.pool_slots,
      &grown, err);
  if (st != SATF_OK)
    return st;
  if (grown)
    cluster_gpu_lists(r, aov, viewproj, 0, count, &over);
  /* the colour's resolve reads the fragments past the slots from the
   * pool where it held them all; else (or for the depth) the nearest
   * passes store each pixel's nearest */
  int pool = over > 0 && aov != SATF_AOV_DEPTH && lists_pool_held(&r->lists);
  if (over > 0 && !pool && (st = lists_alloc_keys(&r->lists, err)) == SATF_OK)
    cluster_gpu_lists(r, aov, viewproj, 1, count, &ignore);
  if (st == SATF_OK)
    cluster_gpu_resolve(r, aov, viewproj, pool);
  /* the pixels that kept their nearest: past the pool's resolve's
   * SATF_MAX_FRAGMENTS, or the nearest passes' slots */
  r->stats.overflow_pixels = pool ? r->lists.deepest_pixels : over;
  return st;
}

static satf_status clusters_frame(satf_renderer *r, satf_aov aov, int refresh,
                                  satf_frame_timing *timing, satf_error *err) {
  satf_frame_timing t;
  memset(&t, 0, sizeof t);
  double t0 = satf_now_seconds();
  satf_status st = refresh ? cluster_cpu_update_maps(r, &t, err) : SATF_OK;
  if (st == SATF_OK)
    st = cluster_cpu_instance_data(r, err);
  if (st != SATF_OK)
    return st;
  double t1 = satf_now_seconds();
  if (refresh && r->effects.cluster_shadows)
    cluster_dom_update(r);
  glFinish();
  double t2 = satf_now_seconds();
  float viewproj[16];
  view_camera(&r->view, viewproj);
  long count = 0;
  memset(r->pass_ms, 0, sizeof r->pass_ms);
  st = composite(r, aov, viewproj, &count, err);
  if (st != SATF_OK)
    return st;
  glFinish();
  double t3 = satf_now_seconds();
  t.shadow_ms = 1e3 * (t2 - t1);
  t.lighting_ms = 1e3 * (t3 - t2);
  t.total_ms = 1e3 * (t3 - t0);
  t.fragments = (long)count;
  t.shells_ms = r->pass_ms[0];
  t.strands_ms = r->pass_ms[1];
  t.resolve_ms = r->pass_ms[2];
  if (timing)
    *timing = t;
  return satf_gl_check("frame", err);
}

/* The sparse clusters' strands and the map threads' scratch; the rest of
 * what the path draws (prototypes, maps, instance buffers) belongs to the
 * hierarchy and resources, which every path reads. */
static void clusters_destroy(satf_renderer *r) {
  sparse_release(r);
  cluster_cpu_release(r);
}

const render_path clusters_path = {"clusters", NULL, clusters_frame,
                                   clusters_destroy};
