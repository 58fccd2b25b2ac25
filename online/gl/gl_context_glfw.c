/* gl_context_glfw.c - an on-screen window and its OpenGL context through
 * GLFW; see gl_context.h. Library satf_glfw, so headless tools never link
 * GLFW. */
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <stdlib.h>

#include "satf/gl.h"

struct satf_gl_window {
  GLFWwindow *window;
  int major, minor;
  char renderer[256];
};

static const int gl_versions[][2] = {{4, 6}, {4, 5}, {4, 3}, {3, 3}};

static const char *glfw_reason(void) {
  const char *desc = NULL;
  int code = glfwGetError(&desc);
  if (code == GLFW_NO_ERROR)
    return "no error reported";
  return desc ? desc : "unknown GLFW error";
}

void satf_gl_window_destroy(satf_gl_window *win) {
  if (!win)
    return;
  if (win->window)
    glfwDestroyWindow(win->window);
  free(win);
}

void satf_gl_window_terminate(void) { glfwTerminate(); }

satf_status satf_gl_window_create(int width, int height, const char *title,
                                  satf_gl_window **out, satf_error *err) {
  *out = NULL;
  if (width <= 0 || height <= 0 || width > 32768 || height > 32768)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "GLFW window: invalid size %dx%d", width, height);
  /* glfwInit is a no-op when GLFW is already initialised. */
  if (glfwInit() != GLFW_TRUE)
    return satf_error_set(err, SATF_ERR_GL,
                          "GLFW window: cannot initialise GLFW: %s",
                          glfw_reason());
  satf_gl_window *win = calloc(1, sizeof *win);
  if (!win)
    return satf_error_set(err, SATF_ERR_NOMEM, "GLFW window: out of memory");
  for (size_t i = 0; i < sizeof gl_versions / sizeof gl_versions[0]; i++) {
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, gl_versions[i][0]);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, gl_versions[i][1]);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
    win->window =
        glfwCreateWindow(width, height, title ? title : "satf", NULL, NULL);
    if (win->window)
      break;
  }
  if (!win->window) {
    satf_gl_window_destroy(win);
    return satf_error_set(err, SATF_ERR_GL,
                          "GLFW window: cannot create a %dx%d window with an "
                          "OpenGL 3.3+ core context: %s",
                          width, height, glfw_reason());
  }
  glfwMakeContextCurrent(win->window);
  glfwSwapInterval(0);
  int fbw = 0, fbh = 0;
  glfwGetFramebufferSize(win->window, &fbw, &fbh);
  satf_status st =
      satf_gl_query_context(fbw, fbh, &win->major, &win->minor, win->renderer,
                            sizeof win->renderer, err);
  if (st != SATF_OK) {
    satf_gl_window_destroy(win);
    return st;
  }
  *out = win;
  return SATF_OK;
}

struct GLFWwindow *satf_gl_window_glfw(satf_gl_window *win) {
  return win->window;
}

satf_status satf_gl_window_make_current(satf_gl_window *win, satf_error *err) {
  glfwMakeContextCurrent(win->window);
  if (glfwGetCurrentContext() != win->window)
    return satf_error_set(err, SATF_ERR_GL,
                          "GLFW window: cannot make current: %s",
                          glfw_reason());
  return SATF_OK;
}

void satf_gl_window_version(const satf_gl_window *win, int *major, int *minor) {
  *major = win->major;
  *minor = win->minor;
}

const char *satf_gl_window_renderer(const satf_gl_window *win) {
  return win->renderer;
}

void satf_gl_window_framebuffer_size(const satf_gl_window *win, int *width,
                                     int *height) {
  glfwGetFramebufferSize(win->window, width, height);
}

int satf_gl_window_should_close(const satf_gl_window *win) {
  return glfwWindowShouldClose(win->window);
}

void satf_gl_window_swap(satf_gl_window *win) { glfwSwapBuffers(win->window); }

void satf_gl_window_poll(satf_gl_window *win) {
  (void)win;
  glfwPollEvents();
}
