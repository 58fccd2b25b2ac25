/* shaders.h - GLSL sources of the online renderer (OpenGL 4.3 core),
 * written in glsl/ (shaders.c). The fragment shaders size their light and
 * fragment arrays by SATF_MAX_LIGHTS and SATF_MAX_FRAGMENTS, which a
 * program must #define after the #version line (the renderer does, from
 * SATF_SCENE_MAX_LIGHTS and SATF_MAX_FRAGMENTS below: resources.c). */
#ifndef SATF_ONLINE_SHADERS_H
#define SATF_ONLINE_SHADERS_H

/* The lighting functions alone (no #version), for tests that evaluate them:
 * float kk_diffuse(vec3 t, vec3 l); float kk_specular(vec3 t, vec3 l,
 * vec3 v, float exponent); vec3 shifted(vec3 t, vec3 n, float s). */
extern const char *const satf_glsl_lighting;
extern const char *const satf_glsl_layer_vs;   /* outer shell, light passes */
extern const char *const satf_glsl_cluster_vs; /* outer shell + local frame */
extern const char *const satf_glsl_shade_fs;   /* eq. 8-14 along each ray */
extern const char *const satf_glsl_dom_fs;     /* deep opacity map slabs */
extern const char *const satf_glsl_depth_fs;   /* light-space depth only */
extern const char *const satf_glsl_fullscreen_vs;
extern const char *const satf_glsl_resolve_fs; /* eq. 14, sorted */
/* the nearest passes' depth mask (lists.c) */
extern const char *const satf_glsl_overflow_mask_fs;
extern const char *const satf_glsl_display_fs; /* linear -> sRGB blit */
extern const char *const satf_glsl_accum_fs;   /* anti-aliasing samples */
extern const char *const satf_glsl_mesh_vs;    /* opaque meshes */
extern const char *const satf_glsl_mesh_fs;
extern const char *const satf_glsl_empty_fs;    /* depth only */
extern const char *const satf_glsl_dom_mesh_fs; /* meshes in the DOM */
/* Scheuermann 2004 (paper 002), the --no-satf baseline: layer patches, its
 * pixel shader, and its diffuse and noise terms alone (no #version), for
 * tests: float scheuermann_diffuse(vec3 n, vec3 l);
 * float scheuermann_noise_mask(float noise, float strength). */
extern const char *const satf_glsl_baseline_vs;
extern const char *const satf_glsl_baseline_fs;
extern const char *const satf_glsl_baseline_lighting;
/* the strand reference path (strands.c) */
extern const char *const satf_glsl_strand_vs;     /* segments as ribbons */
extern const char *const satf_glsl_strand_fs;     /* eq. 9-11, coverage */
extern const char *const satf_glsl_strand_dom_fs; /* strands in the DOM */
/* the physical strands' light per point (compute) */
extern const char *const satf_glsl_strand_light_cs;
/* the maps built on the GPU (maps_gpu.c): the paper's, their s-map sums
 * and the physical mode's */
extern const char *const satf_glsl_maps_kk_cs;
extern const char *const satf_glsl_maps_sums_cs;
extern const char *const satf_glsl_maps_fiber_cs;
/* The fibre model of satf/fiber.h alone (no #version), for tests that
 * evaluate it: struct Fiber; vec3 fiber_single(Fiber f, vec3 wo, vec3 wi,
 * float h); vec3 fiber_dual_shade(Fiber f, sampler2D tables, vec3 wo,
 * vec3 wi, float h, float n_hairs); float fiber_mp(...), fiber_np(...). */
extern const char *const satf_glsl_fiber;
/* fiber.glsl with the cluster path's part (fiber_cluster.glsl): vec3
 * key_global(vec3 hair, vec3 v, vec3 l, out vec3 back) from the tables
 * fiber_gpu_bind uploads. */
extern const char *const satf_glsl_fiber_cluster;

/* Fragments (one per cluster a pixel's ray meets) kept by the resolve. */
#define SATF_MAX_FRAGMENTS 64
/* vec4s of the physical strands' light per point (strand_light_cs.glsl) */
#define STRAND_LIGHT_VEC4 6

#include "satf/gl.h"

/* One program, its shaders given SATF_MAX_LIGHTS and SATF_MAX_FRAGMENTS
 * (and `extra`) after their #version lines. */
satf_status shaders_program(const char *label, const char *vs, const char *fs,
                            const char *extra, GLuint *out, satf_error *err);
/* The same for a compute shader. */
satf_status shaders_compute(const char *label, const char *cs,
                            const char *extra, GLuint *out, satf_error *err);
/* The triangle satf_glsl_fullscreen_vs makes of vertices 0 to 2, which
 * covers the viewport, drawn with the bound program (`vao`: an empty
 * vertex array). */
void shaders_fullscreen(GLuint vao);

#endif
