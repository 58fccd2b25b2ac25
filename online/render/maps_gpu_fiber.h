/* maps_gpu_fiber.h - the physical mode's part of the GPU's maps
 * (maps_gpu.h, glsl/maps_fiber_cs.glsl): what satf_maps_fiber keeps
 * (maps_fiber.h: the re-levelled records, M_p's table, the
 * orientation-free levels) uploaded once, and every frame the lights of
 * the instances built, in their frames. */
#ifndef SATF_ONLINE_MAPS_GPU_FIBER_H
#define SATF_ONLINE_MAPS_GPU_FIBER_H

#include <stddef.h>

#include "satf/common.h"
#include "satf/gl.h"
#include "satf/scene.h"

struct satf_renderer;
struct inst;

/* vec4s of an instance's entry of the lights' buffer: SATF_MAX_LIGHTS
 * lights of two (the light in the instance's frame, its irradiance) */
#define MAPS_GPU_FIBER_LIGHT_VEC4S (2 * SATF_SCENE_MAX_LIGHTS)

/* Appends the shader's defines for r->fiber's tables to out (size bytes
 * in all). */
void maps_gpu_fiber_defines(const struct satf_renderer *r, char *out,
                            size_t size);
/* Uploads r->fiber's records, M_p table and levels into bufs (bindings
 * 0, 7 and 8 of maps_fiber_cs.glsl) and sets program prog's uniforms for
 * them. */
satf_status maps_gpu_fiber_tables(const struct satf_renderer *r, GLuint prog,
                                  GLuint records, GLuint mp, GLuint rel,
                                  satf_error *err);
/* Instance in's lights, MAPS_GPU_FIBER_LIGHT_VEC4S * 4 floats into out. */
void maps_gpu_fiber_lights(const struct satf_renderer *r, const struct inst *in,
                           float *out);

#endif
