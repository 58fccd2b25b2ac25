/* gl_context.h - owns the creation of OpenGL contexts.
 *
 * Two kinds, each in its own library so a headless tool never links GLFW
 * or needs an X display:
 *   satf_gl_context (library satf_gl): a headless EGL context with no
 *     default framebuffer; render into a satf_gl_target (gl_util.h).
 *   satf_gl_window (library satf_glfw): a GLFW window and its context, for
 *     the interactive viewer.
 * Both ask for the newest core profile first (4.6, 4.5, 4.3: SSBOs, atomic
 * counters and image load/store for order-independent transparency) and
 * fall back to 3.3; the version actually obtained is reported, so callers
 * choose their code path from it. Creation makes the context current on
 * the calling thread. All GL calls go through online/gl.h. */
#ifndef SATF_ONLINE_GL_CONTEXT_H
#define SATF_ONLINE_GL_CONTEXT_H

#include "satf/satf.h"

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

#endif
