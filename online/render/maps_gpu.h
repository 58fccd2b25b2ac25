/* maps_gpu.h - the paper's maps (maps.h) built on the GPU: the database's
 * records and maps.c's tables uploaded once, every prototype's sector
 * frames, features and cached neighbours once per geometry, and then per
 * frame two compute passes that write every texel of the instances whose
 * eye or light moved straight into their textures (glsl/maps_kk_cs.glsl),
 * then the s-map sums of eq. 12 (glsl/maps_sums_cs.glsl): no look-up on
 * the CPU and no upload of maps. The CPU's maps (maps.c, cluster_cpu.c) stay
 * the reference. In the physical mode (r->fiber) the pass is
 * glsl/maps_fiber_cs.glsl, an invocation per boundary sector, from the
 * tables maps_gpu_fiber.h uploads: what maps_fiber.c's
 * satf_maps_fiber_build writes, 8 halfs a texel. */
#ifndef SATF_ONLINE_MAPS_GPU_H
#define SATF_ONLINE_MAPS_GPU_H

#include "satf/common.h"

struct satf_renderer;
typedef struct maps_gpu maps_gpu;

/* The program and the database's tables for renderer r's maps (r->maps,
 * r->map_opt), in *out. */
satf_status maps_gpu_create(const struct satf_renderer *r, maps_gpu **out,
                            satf_error *err);
void maps_gpu_destroy(maps_gpu *g);

/* Every layer of the n instances r->insts[moved[0..n)] (each of a
 * prototype drawn as a cluster), written into their textures, ready to be
 * fetched when this returns; the geometry of any instance whose
 * satf_shell_geom.serial changed is uploaded again first. *upload_ms: the
 * CPU's time uploading (geometry, the instances' eyes and lights). */
satf_status maps_gpu_build(struct satf_renderer *r, maps_gpu *g,
                           const int *moved, int n, double *upload_ms,
                           satf_error *err);

#endif
