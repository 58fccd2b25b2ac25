/* depth.h - SATF_AOV_DEPTH's composite (private to online/render), under
 * the paths: the depth where a pixel's fragments, front to back, first
 * reach half coverage, from the per-pixel fragment arrays (lists.h)
 * resolved by glsl/resolve_fs.glsl compiled with DEPTH. The cluster path
 * fills the arrays itself (cluster_gpu.c); the paths that blend by
 * drawing order (strands.c, baseline.c) hand depth_lists their fill. */
#ifndef SATF_RENDER_DEPTH_H
#define SATF_RENDER_DEPTH_H

#include "satf/gl.h"
#include "satf/render.h"

/* Draws the hair's fragments into the bound arrays with a list program
 * (glsl/list_write.glsl) in u_list_mode `mode`; culling is off and the
 * depth test against the meshes set. */
typedef void (*depth_fill_fn)(satf_renderer *r, void *ctx,
                              const float viewproj[16], int mode);
/* The frame's depth into r's target: the meshes' (draw_begin_frame), then
 * the hair's from `fill`, the arrays grown, and the nearest fragments kept
 * where a pixel receives more than they hold (as the cluster path's exact
 * composite: only the nearest decide where half coverage is reached). */
satf_status depth_lists(satf_renderer *r, const float viewproj[16],
                        depth_fill_fn fill, void *ctx, satf_error *err);
/* The filled arrays resolved into r's target: the hair's depth where it
 * reaches half coverage, what the target holds (meshes or background)
 * elsewhere. */
void depth_resolve(const satf_renderer *r, const float viewproj[16]);

#endif
