/* fiber_gpu.h - the scene material's fibre (satf/fiber.h) on the GPU, for
 * the programs that include glsl/fiber.glsl (the cluster path's physical
 * mode and the strand reference): its uniforms and Zinke's dual-scattering
 * tables as a texture, recomputed only when the material changes. */
#ifndef SATF_ONLINE_FIBER_GPU_H
#define SATF_ONLINE_FIBER_GPU_H

#include "satf/fiber.h"
#include "satf/gl.h"
#include "satf/scene.h"

/* Rows (|theta| bins) of the dual-scattering tables, and the texture unit
 * they are bound to; the global term's tables take the next two. */
#define FIBER_TABLE_ROWS 32
#define FIBER_TABLE_UNIT 6
#define FIBER_AZIMUTHAL_UNIT (FIBER_TABLE_UNIT + 3)

typedef struct fiber_gpu {
  GLuint tables; /* RGB32F, SATF_FIBER_DUAL_FIELDS x FIBER_TABLE_ROWS */
  int has_tables;
  satf_fiber fiber; /* what the tables were computed for */
  /* set by the owner before the first bind: also the global term per
   * vertex of the cluster path (satf_fiber_dual_global_table), two RGB32F
   * 3-D textures (global, back) that glsl/fiber_cluster.glsl filters,
   * where evaluating it per vertex cost anim_8's physical shading pass 9
   * of its 71 ms (llvmpipe runs vertices on one thread) */
  int with_global, threads; /* threads: for computing them (0: all) */
  GLuint global_tabs[2];
  /* set by the owner before the first bind: also the lobes' azimuthal
   * scattering over each half of the fibre (satf_fiber_azimuthal_table,
   * 1.5 MB) as an RGB32F 2-D array texture on FIBER_AZIMUTHAL_UNIT and
   * their M_p (satf_fiber_mp_table, 1 MB) as an RGBA32F texture on the
   * next unit, which the physical strands' light per point reads
   * (strand_fiber.glsl) */
  int with_azimuthal;
  GLuint azimuthal, mp;
} fiber_gpu;

/* The material's fibre: its absorption from melanin and redness or given
 * directly, the tilt from the scene's degrees. */
void fiber_from_material(const satf_scene_material *m, satf_fiber *f);

/* Sets program p's u_fiber_* uniforms and binds the tables on
 * FIBER_TABLE_UNIT (the active texture unit is left at 0). */
void fiber_gpu_bind(fiber_gpu *g, const satf_scene_material *m, GLuint p);
void fiber_gpu_release(fiber_gpu *g);

#endif
