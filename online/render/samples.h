/* samples.h - anti-aliasing by jittered supersampling (private to
 * online/render): the sub-pixel offsets and the accumulator the samples
 * of a frame are averaged in. samples.c owns it. */
#ifndef SATF_RENDER_SAMPLES_H
#define SATF_RENDER_SAMPLES_H

#include "satf/gl.h"
#include "satf/render.h"

typedef struct sample_accum {
  GLuint prog;
  satf_gl_target *target;
  int size[2];
} sample_accum;

/* The camera offset, in pixels within [-1/2, 1/2], of sample `index` of
 * `count` (0, 0 when count is 1). */
void samples_offset(int index, int count, float offset[2]);
/* Adds `frame`, weighted 1/count, into the accumulator (cleared at 0);
 * `vao` an empty vertex array for the full-screen triangle. */
satf_status samples_add(sample_accum *a, const satf_gl_target *frame,
                        GLuint vao, int index, int count, satf_error *err);
/* The accumulated average back into `frame`. */
satf_status samples_finish(sample_accum *a, satf_gl_target *frame, GLuint vao,
                           satf_error *err);
void samples_release(sample_accum *a);

#endif
