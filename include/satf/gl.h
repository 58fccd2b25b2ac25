/* gl.h - OpenGL for satf (online/gl/): the single include for GL entry
 * points, headless EGL contexts and GLFW windows, and small GL helpers
 * (shaders, programs, render targets, read-back). */
#ifndef SATF_GL_H
#define SATF_GL_H

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
#include <stddef.h>

#include "satf/satf.h"

#ifdef __cplusplus
extern "C" {
#endif

/* OpenGL 3.3+/4.x core entry points are declared by the Khronos core-profile
 * header with prototypes enabled, and resolved at link time against
 * libglvnd's libOpenGL (CMake target OpenGL::OpenGL). libOpenGL forwards
 * every call through libGLdispatch to whichever context is current on the
 * calling thread, so the same code runs on a headless EGL context
 * (gl_context_egl.c) and on a GLX context made by GLFW
 * (gl_context_glfw.c), with no loader and no function-pointer tables.
 *
 * Headers: GL/glcorearb.h comes from Debian's libgl-dev, libOpenGL.so from
 * libopengl-dev, EGL headers and libEGL.so from libegl-dev. Only core
 * functions exported by libOpenGL (up to 4.5) may be called directly;
 * extension-only functions need eglGetProcAddress/glfwGetProcAddress. */

/* ---- Contexts ----
 * owns the creation of OpenGL contexts.
 *
 * Two kinds, each in its own library so a headless tool never links GLFW
 * or needs an X display:
 *   satf_gl_context (library satf_gl): a headless EGL context with no
 *     default framebuffer; render into a satf_gl_target (below).
 *   satf_gl_window (library satf_glfw): a GLFW window and its context, for
 *     the interactive viewer.
 * Both ask for the newest core profile first (4.6, 4.5, 4.3: SSBOs, atomic
 * counters and image load/store for order-independent transparency) and
 * fall back to 3.3; the version actually obtained is reported, so callers
 * choose their code path from it. Creation makes the context current on
 * the calling thread. All GL calls go through online/gl.h. */

/* ---- headless (EGL) ---------------------------------------------------- */

typedef struct satf_gl_context satf_gl_context;

/* Creates a headless core-profile context for frames of width x height
 * (checked against the driver's viewport and renderbuffer limits) and makes
 * it current. Tries Mesa's surfaceless platform, then each EGL device
 * (EGL_EXT_platform_device, e.g. NVIDIA without X). */
satf_status satf_gl_context_create_headless(int width, int height,
                                            satf_gl_context **out,
                                            satf_error *err);
/* Releases the context (un-currenting it if current). NULL is a no-op. */
void satf_gl_context_destroy(satf_gl_context *ctx);
/* Makes ctx current on the calling thread. */
satf_status satf_gl_context_make_current(const satf_gl_context *ctx,
                                         satf_error *err);
/* The GL version obtained (GL_MAJOR_VERSION / GL_MINOR_VERSION). */
void satf_gl_context_version(const satf_gl_context *ctx, int *major,
                             int *minor);
/* GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)". */
const char *satf_gl_context_renderer(const satf_gl_context *ctx);
/* The frame size given at creation. */
void satf_gl_context_size(const satf_gl_context *ctx, int *width, int *height);

/* ---- window (GLFW) ----------------------------------------------------- */

typedef struct satf_gl_window satf_gl_window;
struct GLFWwindow;

/* Initialises GLFW if needed and opens a width x height window (screen
 * coordinates) with a double-buffered core-profile context, made current,
 * with vsync off so frame times measure rendering. */
satf_status satf_gl_window_create(int width, int height, const char *title,
                                  satf_gl_window **out, satf_error *err);
/* Closes the window. NULL is a no-op. GLFW itself stays initialised. */
void satf_gl_window_destroy(satf_gl_window *win);
/* Shuts GLFW down; call once at program end after the last window is
 * destroyed. */
void satf_gl_window_terminate(void);

/* For input callbacks and anything else GLFW-specific. */
struct GLFWwindow *satf_gl_window_glfw(satf_gl_window *win);
satf_status satf_gl_window_make_current(satf_gl_window *win, satf_error *err);
void satf_gl_window_version(const satf_gl_window *win, int *major, int *minor);
const char *satf_gl_window_renderer(const satf_gl_window *win);
/* Default framebuffer size in pixels (differs from the window size on
 * high-DPI screens). */
void satf_gl_window_framebuffer_size(const satf_gl_window *win, int *width,
                                     int *height);
int satf_gl_window_should_close(const satf_gl_window *win);
void satf_gl_window_swap(satf_gl_window *win);
/* Processes pending window-system events (all windows). */
void satf_gl_window_poll(satf_gl_window *win);

/* ---- Helpers ----
 * owns the small OpenGL plumbing every pass needs: error
 * checks, shader/program building with the driver's log in the error,
 * offscreen render targets (float colour attachments for the frame and its
 * AOVs, plus depth), read-back, and KHR_debug output. Needs a current
 * context (above). */

/* Drains glGetError; if any error was pending, fails with SATF_ERR_GL and
 * a message "LABEL: GL error GL_INVALID_ENUM[, ...]". */
satf_status satf_gl_check(const char *label, satf_error *err);

/* Reads the current context's version and renderer string, fails unless
 * it is at least 3.3 core and frames of width x height fit the viewport
 * and renderbuffer limits. Used by the context constructors. */
satf_status satf_gl_query_context(int width, int height, int *major, int *minor,
                                  char *renderer, size_t renderer_size,
                                  satf_error *err);

/* 1 where a GL_RENDERER string names a rasteriser that runs on the CPU
 * (Mesa's llvmpipe, softpipe and swrast, SwiftShader, the "Software
 * Rasterizer" of other drivers), else 0; NULL and "" count as software.
 * Needs no context. */
int satf_gl_renderer_is_software(const char *renderer);

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

#ifdef __cplusplus
}
#endif
#endif
