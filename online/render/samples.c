/* samples.c - owns anti-aliasing by jittered supersampling: a frame is
 * drawn samples times with the camera moved by a sub-pixel offset each
 * time (view_camera reads the view's jitter) and the premultiplied results are
 * averaged, a box filter one pixel wide. Per-pixel fragment arrays and
 * image-store compositing (shade_fs.glsl) cannot use GL multisampling, and
 * rendering at a multiple of the resolution would multiply the arrays'
 * memory (16 to 64 slots of 16 bytes per pixel); accumulating samples costs
 * time only. The maps and the deep opacity map are made once per frame. */
#include "samples.h"

#include <math.h>

#include "shaders.h"

/* The radical inverse of i in `base` (Halton 1964). */
static float radical_inverse(unsigned i, unsigned base) {
  float inv = 1.0f / (float)base, f = inv, x = 0.0f;
  for (; i > 0; i /= base, f *= inv)
    x += f * (float)(i % base);
  return x;
}

void samples_offset(int index, int count, float offset[2]) {
  if (count <= 1) { /* one sample: the pixel centre, as without sampling */
    offset[0] = offset[1] = 0.0f;
    return;
  }
  /* Halton (2, 3) from index 1 (index 0 is the corner): low discrepancy
   * in the pixel for every prefix, so any count covers it evenly */
  offset[0] = radical_inverse((unsigned)index + 1u, 2u) - 0.5f;
  offset[1] = radical_inverse((unsigned)index + 1u, 3u) - 0.5f;
}

static satf_status ensure_accum(sample_accum *a, int width, int height,
                                satf_error *err) {
  if (!a->prog) {
    satf_status st = shaders_program("anti-aliasing", satf_glsl_fullscreen_vs,
                                     satf_glsl_accum_fs, "", &a->prog, err);
    if (st != SATF_OK)
      return st;
  }
  if (a->target && (a->size[0] != width || a->size[1] != height)) {
    satf_gl_target_destroy(a->target);
    a->target = NULL;
  }
  if (!a->target) {
    const satf_gl_format f = SATF_GL_RGBA32F; /* sums of many samples */
    satf_status st =
        satf_gl_target_create(width, height, 1, &f, &a->target, err);
    if (st != SATF_OK)
      return st;
    a->size[0] = width;
    a->size[1] = height;
  }
  return SATF_OK;
}

/* Draws `from`'s colour times weight into the bound target. */
static void blit_weighted(const sample_accum *a, const satf_gl_target *from,
                          GLuint vao, float weight) {
  glUseProgram(a->prog);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_color_texture(from, 0));
  glUniform1i(glGetUniformLocation(a->prog, "u_image"), 0);
  glUniform1f(glGetUniformLocation(a->prog, "u_weight"), weight);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_SCISSOR_TEST);
  shaders_fullscreen(vao);
}

satf_status samples_add(sample_accum *a, const satf_gl_target *frame,
                        GLuint vao, int index, int count, satf_error *err) {
  satf_status st = ensure_accum(a, satf_gl_target_width(frame),
                                satf_gl_target_height(frame), err);
  if (st != SATF_OK)
    return st;
  satf_gl_target_bind(a->target);
  if (index == 0) {
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
  }
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE);
  blit_weighted(a, frame, vao, 1.0f / (float)count);
  glDisable(GL_BLEND);
  return satf_gl_check("anti-aliasing sample", err);
}

satf_status samples_finish(sample_accum *a, satf_gl_target *frame, GLuint vao,
                           satf_error *err) {
  satf_gl_target_bind(frame);
  blit_weighted(a, a->target, vao, 1.0f);
  return satf_gl_check("anti-aliasing", err);
}

void samples_release(sample_accum *a) {
  if (a->prog)
    glDeleteProgram(a->prog);
  a->prog = 0;
  satf_gl_target_destroy(a->target);
  a->target = NULL;
}
