/* gl_util.h - owns the small OpenGL plumbing every pass needs: error
 * checks, shader/program building with the driver's log in the error,
 * offscreen render targets (float colour attachments for the frame and its
 * AOVs, plus depth), read-back, and KHR_debug output. Needs a current
 * context (gl_context.h). Library satf_gl. */
#ifndef SATF_ONLINE_GL_UTIL_H
#define SATF_ONLINE_GL_UTIL_H

#include <stddef.h>

#include "online/gl.h"
#include "satf/satf.h"

/* Drains glGetError; if any error was pending, fails with SATF_ERR_GL and
 * a message "LABEL: GL error GL_INVALID_ENUM[, ...]". */
satf_status satf_gl_check(const char *label, satf_error *err);

/* Reads the current context's version and renderer string, fails unless
 * it is at least 3.3 core and frames of width x height fit the viewport
 * and renderbuffer limits. Used by the context constructors. */
satf_status satf_gl_query_context(int width, int height, int *major, int *minor,
                                  char *renderer, size_t renderer_size,
                                  satf_error *err);

/* ---- shaders ----------------------------------------------------------- */

/* Compiles one shader stage (GL_VERTEX_SHADER, GL_FRAGMENT_SHADER,
 * GL_COMPUTE_SHADER, ...). On failure the message names the label and
 * carries the driver's info log. */
satf_status satf_gl_shader_compile(GLenum stage, const char *label,
                                   const char *source, GLuint *out,
                                   satf_error *err);
/* Links the given compiled shaders; on failure the message names the
 * label and carries the driver's link log. Shaders are left attached and
 * owned by the caller. */
satf_status satf_gl_program_link(const char *label, const GLuint *shaders,
                                 int nshaders, GLuint *out, satf_error *err);
/* Compiles a vertex + fragment pair and links them; the shader objects are
 * deleted afterwards. */
satf_status satf_gl_program_build(const char *label, const char *vertex_src,
                                  const char *fragment_src, GLuint *out,
                                  satf_error *err);
/* Same for a compute program (GL 4.3+). */
satf_status satf_gl_program_build_compute(const char *label,
                                          const char *compute_src, GLuint *out,
                                          satf_error *err);

/* ---- render targets ---------------------------------------------------- */

typedef enum satf_gl_format {
  SATF_GL_RGBA32F, /* exact float frames; read-back is bit-exact */
  SATF_GL_RGBA16F  /* half the bandwidth; values rounded to half */
} satf_gl_format;

/* A framebuffer object with ncolor colour textures (attachment i is
 * GL_COLOR_ATTACHMENT0 + i, fragment output location i) and a 32-bit
 * float depth texture, all width x height. */
typedef struct satf_gl_target satf_gl_target;

satf_status satf_gl_target_create(int width, int height, int ncolor,
                                  const satf_gl_format *formats,
                                  satf_gl_target **out, satf_error *err);
/* Deletes the GL objects; needs the creating context current. */
void satf_gl_target_destroy(satf_gl_target *t);
/* Binds the FBO for drawing, enables all colour attachments as draw
 * buffers and sets the viewport to the whole target. */
void satf_gl_target_bind(const satf_gl_target *t);
GLuint satf_gl_target_fbo(const satf_gl_target *t);
GLuint satf_gl_target_color_texture(const satf_gl_target *t, int index);
GLuint satf_gl_target_depth_texture(const satf_gl_target *t);
int satf_gl_target_width(const satf_gl_target *t);
int satf_gl_target_height(const satf_gl_target *t);
int satf_gl_target_color_count(const satf_gl_target *t);

/* Reads colour attachment `index` as interleaved float RGBA, rows in GL
 * order: BOTTOM row first. dst holds dst_floats floats, at least
 * 4 * width * height. Hand the result to satf_image_store_interleaved
 * with SATF_ROWS_BOTTOM_UP. */
satf_status satf_gl_target_read_bottom_up(const satf_gl_target *t, int index,
                                          float *dst, size_t dst_floats,
                                          satf_error *err);
/* Reads a width x height block at the origin of `read_buffer` (e.g.
 * GL_BACK of the default framebuffer, fbo 0, or GL_COLOR_ATTACHMENTi) as
 * interleaved float RGBA, BOTTOM row first. Restores the read binding. */
satf_status satf_gl_read_rgba_bottom_up(GLuint fbo, GLenum read_buffer,
                                        int width, int height, float *dst,
                                        size_t dst_floats, satf_error *err);

/* ---- debug output ------------------------------------------------------ */

/* Routes KHR_debug messages (core in 4.3) synchronously to fn, or to a
 * stderr printer when fn is NULL. Fails with SATF_ERR_GL when the context
 * has neither GL 4.3 nor GL_KHR_debug. */
satf_status satf_gl_debug_enable(GLDEBUGPROC fn, const void *user,
                                 satf_error *err);

#endif
