/* test_gl_headless.c - OpenGL plumbing on a real driver (Mesa llvmpipe).
 *
 * Built twice: as test_gl_headless on a surfaceless EGL context, and with
 * SATF_TEST_WINDOW as test_gl_window on a GLFW window under xvfb-run, where
 * it also reads the window's default framebuffer. Expected pixels are
 * worked out from gl_FragCoord (pixel centres at i + 0.5), so float
 * targets must match exactly. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
/* cmocka needs the headers above first */
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "satf/gl.h"
#include "satf/render.h"

#ifdef SATF_TEST_WINDOW
static satf_gl_window *g_win;
#else
static satf_gl_context *g_ctx;
#endif
static GLuint g_prog, g_vao;

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A triangle covering the whole viewport, from gl_VertexID alone:
 * (-1,-1), (3,-1), (-1,3). */
static const char *vs_src =
    "#version 330 core\n"
    "uniform float u_depth;\n"
    "void main() {\n"
    "  vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0,\n"
    "                float((gl_VertexID & 2) << 1) - 1.0);\n"
    "  gl_Position = vec4(p, u_depth, 1.0);\n"
    "}\n";

static const char *fs_src =
    "#version 330 core\n"
    "uniform vec2 u_scale;\n"
    "layout(location = 0) out vec4 out0;\n"
    "layout(location = 1) out vec4 out1;\n"
    "void main() {\n"
    "  out0 = vec4(gl_FragCoord.xy * u_scale, 0.125, 1.0);\n"
    "  out1 = vec4(-gl_FragCoord.yx, 1.0e6, 0.5);\n"
    "}\n";

static const float clear0[4] = {0.25f, 0.5f, 0.75f, 1.0f};
static const float clear1[4] = {7.0f, 8.0f, 9.0f, 10.0f};

static void draw(float sx, float sy, float depth) {
  glUseProgram(g_prog);
  glUniform2f(glGetUniformLocation(g_prog, "u_scale"), sx, sy);
  glUniform1f(glGetUniformLocation(g_prog, "u_depth"), depth);
  glBindVertexArray(g_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
}

/* Clears, then draws the triangle into the left half only (scissor), so
 * the right half keeps the clear colour. */
static void draw_pattern(int width, int height, int ncolor) {
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_DEPTH_TEST);
  glClearBufferfv(GL_COLOR, 0, clear0);
  if (ncolor > 1)
    glClearBufferfv(GL_COLOR, 1, clear1);
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, 0, width / 2, height);
  draw(1.0f, 1.0f, 0.0f);
  glDisable(GL_SCISSOR_TEST);
}

static int setup(void **state) {
  (void)state;
  satf_error err;
  double t0 = now_s();
#ifdef SATF_TEST_WINDOW
  if (satf_gl_window_create(32, 16, "satf test", &g_win, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  printf("GLFW window context: %.1f ms, GL %s\n", 1e3 * (now_s() - t0),
         satf_gl_window_renderer(g_win));
#else
  if (satf_gl_context_create_headless(64, 48, &g_ctx, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  printf("headless EGL context (first in process): %.1f ms on %s\n",
         1e3 * (now_s() - t0), satf_gl_context_renderer(g_ctx));
#endif
  if (satf_gl_program_build("pattern", vs_src, fs_src, &g_prog, &err) !=
      SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  glGenVertexArrays(1, &g_vao);
  return 0;
}

static int teardown(void **state) {
  (void)state;
  glDeleteVertexArrays(1, &g_vao);
  glDeleteProgram(g_prog);
#ifdef SATF_TEST_WINDOW
  satf_gl_window_destroy(g_win);
  /* glfwTerminate unloads Mesa's GLX driver, whose still-referenced
   * allocations LeakSanitizer then reports (~5 KB, in no known module). */
#ifndef __SANITIZE_ADDRESS__
  satf_gl_window_terminate();
#endif
#else
  satf_gl_context_destroy(g_ctx);
#endif
  return 0;
}

static void test_version_and_renderer(void **state) {
  (void)state;
  int major = 0, minor = 0;
  const char *renderer;
#ifdef SATF_TEST_WINDOW
  satf_gl_window_version(g_win, &major, &minor);
  renderer = satf_gl_window_renderer(g_win);
#else
  satf_gl_context_version(g_ctx, &major, &minor);
  renderer = satf_gl_context_renderer(g_ctx);
  int w = 0, h = 0;
  satf_gl_context_size(g_ctx, &w, &h);
  assert_int_equal(w, 64);
  assert_int_equal(h, 48);
#endif
  assert_true(major * 10 + minor >= 33);
  /* The reported version is what the driver says, not what was asked. */
  GLint m = 0, n = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &m);
  glGetIntegerv(GL_MINOR_VERSION, &n);
  assert_int_equal(m, major);
  assert_int_equal(n, minor);
  assert_string_equal(renderer, (const char *)glGetString(GL_RENDERER));
  assert_true(strlen(renderer) > 0);
  printf("GL %d.%d core on %s\n", major, minor, renderer);
}

/* The renderer strings the maps' default resolves against (satf/render.h,
 * SATF_MAPS_AUTO): as Mesa, NVIDIA, AMD, Intel and others report them. */
static void test_renderer_is_software(void **state) {
  (void)state;
  static const char *software[] = {"llvmpipe (LLVM 15.0.6, 256 bits)",
                                   "softpipe",
                                   "Software Rasterizer",
                                   "Mesa OffScreen / SWRAST",
                                   "Google SwiftShader",
                                   "LLVMPIPE"};
  static const char *hardware[] = {
      "NVIDIA H200/PCIe/SSE2", "AMD Radeon RX 7900 XTX (radeonsi, navi31)",
      "Mesa Intel(R) UHD Graphics 630 (CFL GT2)", "Apple M2", "virgl"};
  for (size_t i = 0; i < sizeof software / sizeof software[0]; i++)
    if (!satf_gl_renderer_is_software(software[i]))
      fail_msg("'%s' is a software rasteriser", software[i]);
  for (size_t i = 0; i < sizeof hardware / sizeof hardware[0]; i++)
    if (satf_gl_renderer_is_software(hardware[i]))
      fail_msg("'%s' is a hardware GPU", hardware[i]);
  assert_true(satf_gl_renderer_is_software(NULL));
  assert_true(satf_gl_renderer_is_software(""));
}

static void check_pattern_bottom_up(const float *px, int w, int h, int index) {
  for (int j = 0; j < h; j++)
    for (int i = 0; i < w; i++) {
      const float *p = px + 4 * ((size_t)j * (size_t)w + (size_t)i);
      float expect[4];
      if (i >= w / 2)
        memcpy(expect, index == 0 ? clear0 : clear1, sizeof expect);
      else if (index == 0) {
        expect[0] = (float)i + 0.5f;
        expect[1] = (float)j + 0.5f;
        expect[2] = 0.125f;
        expect[3] = 1.0f;
      } else {
        expect[0] = -((float)j + 0.5f);
        expect[1] = -((float)i + 0.5f);
        expect[2] = 1.0e6f;
        expect[3] = 0.5f;
      }
      for (int c = 0; c < 4; c++)
        if (p[c] != expect[c]) {
          fail_msg("attachment %d pixel (%d,%d) component %d: got %g, "
                   "expected %g",
                   index, i, j, c, (double)p[c], (double)expect[c]);
        }
    }
}

static void test_pattern_float_target(void **state) {
  (void)state;
  const int w = 16, h = 8;
  satf_error err;
  satf_gl_target *t = NULL;
  const satf_gl_format fmt[2] = {SATF_GL_RGBA32F, SATF_GL_RGBA32F};
  assert_int_equal(satf_gl_target_create(w, h, 2, fmt, &t, &err), SATF_OK);
  assert_int_equal(satf_gl_target_width(t), w);
  assert_int_equal(satf_gl_target_color_count(t), 2);
  assert_true(satf_gl_target_color_texture(t, 1) != 0);
  assert_int_equal(satf_gl_target_color_texture(t, 2), 0);
  satf_gl_target_bind(t);
  draw_pattern(w, h, 2);
  assert_int_equal(satf_gl_check("pattern draw", &err), SATF_OK);

  float px[4 * 16 * 8];
  assert_int_equal(satf_gl_target_read_bottom_up(t, 0, px, 4 * 16 * 8, &err),
                   SATF_OK);
  check_pattern_bottom_up(px, w, h, 0);

  /* Flip into an image: its top row is GL's row h-1, so G = h - 0.5. */
  satf_image *img = NULL;
  const char *names[4] = {"R", "G", "B", "A"};
  assert_int_equal(satf_image_create(w, h, names, 4, &img, &err), SATF_OK);
  assert_int_equal(satf_image_store_interleaved(img, px, 4, names,
                                                SATF_ROWS_BOTTOM_UP, &err),
                   SATF_OK);
  assert_true(satf_image_plane(img, 1)[0] == (float)h - 0.5f);
  assert_true(satf_image_plane(img, 1)[(size_t)(h - 1) * w] == 0.5f);
  assert_true(satf_image_plane(img, 0)[3] == 3.5f);
  satf_image_destroy(img);

  assert_int_equal(satf_gl_target_read_bottom_up(t, 1, px, 4 * 16 * 8, &err),
                   SATF_OK);
  check_pattern_bottom_up(px, w, h, 1);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  satf_gl_target_destroy(t);
}

static void test_pattern_half_target(void **state) {
  (void)state;
  const int w = 16, h = 8;
  satf_error err;
  satf_gl_target *t = NULL;
  const satf_gl_format fmt[1] = {SATF_GL_RGBA16F};
  assert_int_equal(satf_gl_target_create(w, h, 1, fmt, &t, &err), SATF_OK);
  GLint internal = 0;
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_color_texture(t, 0));
  glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_INTERNAL_FORMAT,
                           &internal);
  assert_int_equal(internal, GL_RGBA16F);
  satf_gl_target_bind(t);
  draw_pattern(w, h, 1);
  /* i + 0.5 (< 16) and 0.125 are exact in half precision. */
  float px[4 * 16 * 8];
  assert_int_equal(satf_gl_target_read_bottom_up(t, 0, px, 4 * 16 * 8, &err),
                   SATF_OK);
  check_pattern_bottom_up(px, w, h, 0);
  /* 0.1 is not: it comes back rounded to the nearest half, 0.0999755859. */
  const float tenth[4] = {0.1f, 0.1f, 0.1f, 0.1f};
  glClearBufferfv(GL_COLOR, 0, tenth);
  assert_int_equal(satf_gl_target_read_bottom_up(t, 0, px, 4 * 16 * 8, &err),
                   SATF_OK);
  assert_true(px[0] == 0.0999755859375f);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  satf_gl_target_destroy(t);
}

static void test_depth_attachment(void **state) {
  (void)state;
  const int w = 8, h = 4;
  satf_error err;
  satf_gl_target *t = NULL;
  assert_int_equal(satf_gl_target_create(w, h, 1, NULL, &t, &err), SATF_OK);
  satf_gl_target_bind(t);
  glClearBufferfv(GL_COLOR, 0, clear0);
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  draw(1.0f, 1.0f, 0.0f);  /* window depth 0.5: drawn */
  draw(2.0f, 2.0f, 0.5f);  /* 0.75, behind: rejected */
  draw(3.0f, 3.0f, -0.5f); /* 0.25, in front: drawn */
  glDisable(GL_DEPTH_TEST);
  float px[4 * 8 * 4];
  assert_int_equal(satf_gl_target_read_bottom_up(t, 0, px, 4 * 8 * 4, &err),
                   SATF_OK);
  for (int j = 0; j < h; j++)
    for (int i = 0; i < w; i++) {
      const float *p = px + 4 * (j * w + i);
      assert_true(p[0] == 3.0f * ((float)i + 0.5f));
      assert_true(p[1] == 3.0f * ((float)j + 0.5f));
    }
  float depth[8 * 4];
  glBindFramebuffer(GL_READ_FRAMEBUFFER, satf_gl_target_fbo(t));
  glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
  for (int k = 0; k < w * h; k++)
    assert_float_equal(depth[k], 0.25f, 1e-7f);
  assert_int_equal(satf_gl_check("depth read", &err), SATF_OK);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  satf_gl_target_destroy(t);
}

static void test_target_rejects_bad_arguments(void **state) {
  (void)state;
  satf_error err;
  satf_gl_target *t = NULL;
  assert_int_equal(satf_gl_target_create(0, 4, 1, NULL, &t, &err),
                   SATF_ERR_ARGUMENT);
  assert_null(t);
  assert_int_equal(satf_gl_target_create(4, 4, 0, NULL, &t, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_gl_target_create(4, 4, 99, NULL, &t, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "99 colour attachments"));
  const satf_gl_format bad[1] = {(satf_gl_format)7};
  assert_int_equal(satf_gl_target_create(4, 4, 1, bad, &t, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_gl_target_create(4, 4, 1, NULL, &t, &err), SATF_OK);
  float small[4 * 4 * 4 - 1];
  assert_int_equal(
      satf_gl_target_read_bottom_up(t, 0, small, sizeof small / 4, &err),
      SATF_ERR_ARGUMENT);
  float px[4 * 4 * 4];
  assert_int_equal(satf_gl_target_read_bottom_up(t, 1, px, 64, &err),
                   SATF_ERR_ARGUMENT);
  satf_gl_target_destroy(t);
  assert_int_equal(satf_gl_check("after bad targets", &err), SATF_OK);
}

/* The driver's own log, fetched independently of satf_gl_shader_compile. */
static void driver_compile_log(GLenum stage, const char *src, char *log,
                               size_t size) {
  GLuint s = glCreateShader(stage);
  glShaderSource(s, 1, &src, NULL);
  glCompileShader(s);
  glGetShaderInfoLog(s, (GLsizei)size, NULL, log);
  glDeleteShader(s);
}

static void test_compile_error_carries_driver_log(void **state) {
  (void)state;
  const char *bad = "#version 330 core\n"
                    "out vec4 o;\n"
                    "void main() { o = vec4(undefined_symbol); }\n";
  satf_error err;
  GLuint s = 123;
  assert_int_equal(
      satf_gl_shader_compile(GL_FRAGMENT_SHADER, "bad-frag", bad, &s, &err),
      SATF_ERR_GL);
  assert_int_equal(s, 0);
  printf("%s\n", err.message);
  assert_non_null(strstr(err.message, "'bad-frag'"));
  assert_non_null(strstr(err.message, "fragment"));
  char log[512] = "";
  driver_compile_log(GL_FRAGMENT_SHADER, bad, log, sizeof log);
  char *nl = strchr(log, '\n');
  if (nl)
    *nl = '\0';
  assert_true(strlen(log) > 10);
  assert_non_null(strstr(err.message, log));
  assert_non_null(strstr(err.message, "undefined_symbol"));

  /* Program-level: a function declared but defined in no stage compiles
   * and fails only at link time. */
  const char *fs = "#version 330 core\n"
                   "float v_missing(void);\n"
                   "out vec4 o;\n"
                   "void main() { o = vec4(v_missing()); }\n";
  GLuint p = 9;
  assert_int_equal(satf_gl_program_build("bad-link", vs_src, fs, &p, &err),
                   SATF_ERR_GL);
  assert_int_equal(p, 0);
  printf("%s\n", err.message);
  assert_non_null(strstr(err.message, "'bad-link'"));
  assert_non_null(strstr(err.message, "link failed"));
  assert_non_null(strstr(err.message, "v_missing"));
  if (satf_gl_check("after bad shaders", &err) != SATF_OK)
    fail_msg("%s", err.message);
}

static void test_check_names_gl_errors(void **state) {
  (void)state;
  satf_error err;
  assert_int_equal(satf_gl_check("clean", &err), SATF_OK);
  glEnable(0xFFFF); /* not a capability */
  assert_int_equal(satf_gl_check("probe", &err), SATF_ERR_GL);
  assert_string_equal(err.message, "probe: GL error GL_INVALID_ENUM");
  assert_int_equal(satf_gl_check("drained", &err), SATF_OK);
}

typedef struct debug_log {
  int count, errors;
  GLuint last_id;
  char last[128];
} debug_log;

static void APIENTRY collect(GLenum source, GLenum type, GLuint id,
                             GLenum severity, GLsizei length,
                             const GLchar *message, const void *user) {
  (void)source, (void)severity, (void)length;
  debug_log *d = (debug_log *)(uintptr_t)user;
  d->count++;
  d->errors += type == GL_DEBUG_TYPE_ERROR;
  d->last_id = id;
  snprintf(d->last, sizeof d->last, "%s", message);
}

static void test_debug_output(void **state) {
  (void)state;
  satf_error err;
  debug_log d;
  memset(&d, 0, sizeof d);
  assert_int_equal(satf_gl_debug_enable(collect, &d, &err), SATF_OK);
  glDebugMessageInsert(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_MARKER, 42,
                       GL_DEBUG_SEVERITY_NOTIFICATION, -1, "satf marker");
  assert_int_equal(d.count, 1);
  assert_int_equal(d.last_id, 42);
  assert_string_equal(d.last, "satf marker");
  glEnable(0xFFFF);
  assert_int_equal(d.errors, 1);
  assert_int_equal(glGetError(), GL_INVALID_ENUM);
  glDebugMessageCallback(NULL, NULL);
  glDisable(GL_DEBUG_OUTPUT);
  assert_int_equal(satf_gl_check("after debug", &err), SATF_OK);
}

#ifdef SATF_TEST_WINDOW

static void test_window_default_framebuffer(void **state) {
  (void)state;
  satf_error err;
  int w = 0, h = 0;
  satf_gl_window_framebuffer_size(g_win, &w, &h);
  assert_int_equal(w, 32);
  assert_int_equal(h, 16);
  assert_false(satf_gl_window_should_close(g_win));
  assert_int_equal(satf_gl_window_make_current(g_win, &err), SATF_OK);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDrawBuffer(GL_BACK);
  glViewport(0, 0, w, h);
  glDisable(GL_SCISSOR_TEST);
  glClearBufferfv(GL_COLOR, 0, clear0);
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, 0, w / 2, h);
  draw(1.0f / (float)w, 1.0f / (float)h, 0.0f);
  glDisable(GL_SCISSOR_TEST);
  float px[4 * 32 * 16];
  assert_int_equal(
      satf_gl_read_rgba_bottom_up(0, GL_BACK, w, h, px, 4 * 32 * 16, &err),
      SATF_OK);
  /* The default framebuffer is 8-bit: values come back quantised. */
  const float tol = 0.6f / 255.0f;
  for (int j = 0; j < h; j++)
    for (int i = 0; i < w; i++) {
      const float *p = px + 4 * (j * w + i);
      if (i >= w / 2) {
        for (int c = 0; c < 4; c++)
          assert_float_equal(p[c], clear0[c], tol);
      } else {
        assert_float_equal(p[0], ((float)i + 0.5f) / (float)w, tol);
        assert_float_equal(p[1], ((float)j + 0.5f) / (float)h, tol);
        assert_float_equal(p[2], 0.125f, tol);
        assert_float_equal(p[3], 1.0f, tol);
      }
    }
  satf_gl_window_swap(g_win);
  satf_gl_window_poll(g_win);
  assert_non_null(satf_gl_window_glfw(g_win));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_version_and_renderer),
      cmocka_unit_test(test_renderer_is_software),
      cmocka_unit_test(test_window_default_framebuffer),
      cmocka_unit_test(test_pattern_float_target),
      cmocka_unit_test(test_pattern_half_target),
      cmocka_unit_test(test_depth_attachment),
      cmocka_unit_test(test_target_rejects_bad_arguments),
      cmocka_unit_test(test_compile_error_carries_driver_log),
      cmocka_unit_test(test_check_names_gl_errors),
      cmocka_unit_test(test_debug_output),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}

#else

static void test_second_context_and_switching(void **state) {
  (void)state;
  satf_error err;
  satf_gl_context *other = NULL;
  double t0 = now_s();
  assert_int_equal(satf_gl_context_create_headless(32, 32, &other, &err),
                   SATF_OK);
  printf("headless EGL context (another in process): %.2f ms\n",
         1e3 * (now_s() - t0));
  /* GL objects are per context: the pattern program does not exist here. */
  assert_false(glIsProgram(g_prog));
  satf_gl_context_destroy(other);
  /* Destroying one context must leave the display usable for the other. */
  assert_int_equal(satf_gl_context_make_current(g_ctx, &err), SATF_OK);
  assert_true(glIsProgram(g_prog));
  satf_gl_target *t = NULL;
  assert_int_equal(satf_gl_target_create(4, 4, 1, NULL, &t, &err), SATF_OK);
  satf_gl_target_destroy(t);
}

static void test_context_rejects_bad_sizes(void **state) {
  (void)state;
  satf_error err;
  satf_gl_context *c = (satf_gl_context *)&err;
  assert_int_equal(satf_gl_context_create_headless(0, 10, &c, &err),
                   SATF_ERR_ARGUMENT);
  assert_null(c);
  assert_int_equal(satf_gl_context_create_headless(1 << 30, 10, &c, &err),
                   SATF_ERR_ARGUMENT);
  assert_null(c);
  assert_non_null(strstr(err.message, "exceeds the driver limit"));
  /* The failed attempt may have made its context current and destroyed
   * it; the caller re-selects its own. */
  assert_int_equal(satf_gl_context_make_current(g_ctx, &err), SATF_OK);
}

/* Draws n full-screen triangles, each with colour (k, 0.5, 0.25, 1), and
 * returns the seconds taken. With finish_each every draw is a frame of its
 * own; batched, llvmpipe may drop tiles that a later opaque draw covers
 * entirely, so only per-frame timing is a true fill rate. */
static double time_draws(GLint color, int n, int finish_each) {
  double t0 = now_s();
  for (int k = 0; k < n; k++) {
    glUniform4f(color, (float)k, 0.5f, 0.25f, 1.0f);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    if (finish_each)
      glFinish();
  }
  glFinish();
  return now_s() - t0;
}

/* llvmpipe fill rate: a full-screen triangle (same fragments as a quad)
 * at 640x480 writing a constant colour, with LP_NUM_THREADS at its default
 * (one rasteriser thread per core). */
static void test_fill_rate(void **state) {
  (void)state;
  const char *fs = "#version 330 core\n"
                   "uniform vec4 u_color;\n"
                   "out vec4 o;\n"
                   "void main() { o = u_color; }\n";
  satf_error err;
  GLuint prog = 0;
  assert_int_equal(satf_gl_program_build("fill", vs_src, fs, &prog, &err),
                   SATF_OK);
  const int w = 640, h = 480, n = 100;
  const satf_gl_format fmts[2] = {SATF_GL_RGBA32F, SATF_GL_RGBA16F};
  for (int f = 0; f < 2; f++) {
    satf_gl_target *t = NULL;
    assert_int_equal(satf_gl_target_create(w, h, 1, &fmts[f], &t, &err),
                     SATF_OK);
    satf_gl_target_bind(t);
    glUseProgram(prog);
    glBindVertexArray(g_vao);
    GLint color = glGetUniformLocation(prog, "u_color");
    time_draws(color, 1, 1); /* warm-up: shader JIT */
    for (int finish_each = 1; finish_each >= 0; finish_each--) {
      double dt = time_draws(color, n, finish_each);
      printf("llvmpipe fill rate, %dx%d %s, trivial shader, %s: %.3g "
             "fragments/s (%.3f ms per draw)\n",
             w, h, f == 0 ? "RGBA32F" : "RGBA16F",
             finish_each ? "glFinish per draw" : "batched",
             (double)n * w * h / dt, 1e3 * dt / n);
      float px[4];
      glBindFramebuffer(GL_READ_FRAMEBUFFER, satf_gl_target_fbo(t));
      glReadBuffer(GL_COLOR_ATTACHMENT0);
      glReadPixels(w - 1, h - 1, 1, 1, GL_RGBA, GL_FLOAT, px);
      /* the last draw's colour; 99 is exact in half too */
      assert_true(px[0] == (float)(n - 1));
      assert_true(px[1] == 0.5f && px[2] == 0.25f && px[3] == 1.0f);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    satf_gl_target_destroy(t);
  }
  glDeleteProgram(prog);
  assert_int_equal(satf_gl_check("fill rate", &err), SATF_OK);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_version_and_renderer),
      cmocka_unit_test(test_renderer_is_software),
      cmocka_unit_test(test_pattern_float_target),
      cmocka_unit_test(test_pattern_half_target),
      cmocka_unit_test(test_depth_attachment),
      cmocka_unit_test(test_target_rejects_bad_arguments),
      cmocka_unit_test(test_compile_error_carries_driver_log),
      cmocka_unit_test(test_check_names_gl_errors),
      cmocka_unit_test(test_debug_output),
      cmocka_unit_test(test_second_context_and_switching),
      cmocka_unit_test(test_context_rejects_bad_sizes),
      cmocka_unit_test(test_fill_rate),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}

#endif
