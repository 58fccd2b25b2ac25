/* gl_util.c - see gl_util.h. */
#include "satf/gl.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *gl_error_name(GLenum e) {
  switch (e) {
  case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
  case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
  case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
  case GL_INVALID_FRAMEBUFFER_OPERATION:
    return "GL_INVALID_FRAMEBUFFER_OPERATION";
  case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
  case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
  case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
  case GL_CONTEXT_LOST: return "GL_CONTEXT_LOST";
  }
  return "unknown GL error";
}

satf_status satf_gl_check(const char *label, satf_error *err) {
  char names[256] = "";
  size_t used = 0;
  /* Bounded: a lost context may report GL_CONTEXT_LOST forever. */
  for (int i = 0; i < 8; i++) {
    GLenum e = glGetError();
    if (e == GL_NO_ERROR)
      break;
    int n = snprintf(names + used, sizeof names - used, "%s%s",
                     used ? ", " : "", gl_error_name(e));
    if (n > 0 && (size_t)n < sizeof names - used)
      used += (size_t)n;
  }
  if (used == 0)
    return SATF_OK;
  return satf_error_set(err, SATF_ERR_GL, "%s: GL error %s", label, names);
}

satf_status satf_gl_query_context(int width, int height, int *major, int *minor,
                                  char *renderer, size_t renderer_size,
                                  satf_error *err) {
  GLint maj = 0, min = 0, profile = 0, viewport[2] = {0, 0}, rb = 0, tex = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &maj);
  glGetIntegerv(GL_MINOR_VERSION, &min);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &rb);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &tex);
  const GLubyte *name = glGetString(GL_RENDERER);
  snprintf(renderer, renderer_size, "%s", name ? (const char *)name : "?");
  *major = maj;
  *minor = min;
  if (maj * 10 + min < 33 || !(profile & GL_CONTEXT_CORE_PROFILE_BIT))
    return satf_error_set(
        err, SATF_ERR_GL,
        "OpenGL context: got %d.%d (%s profile) on %s, "
        "need 3.3 core",
        maj, min, profile & GL_CONTEXT_CORE_PROFILE_BIT ? "core" : "compat",
        renderer);
  int limit = viewport[0] < viewport[1] ? viewport[0] : viewport[1];
  limit = rb < limit ? rb : limit;
  limit = tex < limit ? tex : limit;
  if (width > limit || height > limit)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "OpenGL context: frame %dx%d exceeds the driver "
                          "limit of %d pixels per side on %s",
                          width, height, limit, renderer);
  return satf_gl_check("OpenGL context query", err);
}

/* Whether `needle` (lower case) occurs in `hay`, ignoring case. */
static int contains_nocase(const char *hay, const char *needle) {
  size_t n = strlen(needle);
  for (; *hay; hay++) {
    size_t i = 0;
    while (i < n && hay[i] && tolower((unsigned char)hay[i]) == needle[i])
      i++;
    if (i == n)
      return 1;
  }
  return 0;
}

int satf_gl_renderer_is_software(const char *renderer) {
  /* GL_RENDERER as the CPU rasterisers report it: Mesa's "llvmpipe (LLVM
   * 15.0.6, 256 bits)", "softpipe", "Software Rasterizer" (swrast and
   * others), Google's "SwiftShader" */
  static const char *names[] = {"llvmpipe", "softpipe", "swrast", "software",
                                "swiftshader"};
  if (!renderer || !renderer[0])
    return 1;
  for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
    if (contains_nocase(renderer, names[i]))
      return 1;
  return 0;
}

/* ---- shaders ----------------------------------------------------------- */

static const char *stage_name(GLenum stage) {
  switch (stage) {
  case GL_VERTEX_SHADER: return "vertex";
  case GL_FRAGMENT_SHADER: return "fragment";
  case GL_GEOMETRY_SHADER: return "geometry";
  case GL_TESS_CONTROL_SHADER: return "tess control";
  case GL_TESS_EVALUATION_SHADER: return "tess evaluation";
  case GL_COMPUTE_SHADER: return "compute";
  }
  return "unknown stage";
}

/* Copies a GL info log into buf, dropping trailing newlines so it sits
 * neatly at the end of an error message. */
static void trim_log(char *buf) {
  size_t n = strlen(buf);
  while (n > 0 && (buf[n - 1] == '\n' || buf[n - 1] == ' '))
    buf[--n] = '\0';
}

satf_status satf_gl_shader_compile(GLenum stage, const char *label,
                                   const char *source, GLuint *out,
                                   satf_error *err) {
  *out = 0;
  if (!source)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "shader '%s': no source",
                          label);
  GLuint s = glCreateShader(stage);
  if (s == 0)
    return satf_error_set(err, SATF_ERR_GL,
                          "shader '%s': cannot create a %s shader (%s)", label,
                          stage_name(stage), gl_error_name(glGetError()));
  glShaderSource(s, 1, &source, NULL);
  glCompileShader(s);
  GLint ok = GL_FALSE;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[640] = "";
    glGetShaderInfoLog(s, (GLsizei)sizeof log, NULL, log);
    trim_log(log);
    glDeleteShader(s);
    return satf_error_set(err, SATF_ERR_GL,
                          "shader '%s' (%s): compile failed: %s", label,
                          stage_name(stage), log[0] ? log : "(no log)");
  }
  *out = s;
  return SATF_OK;
}

satf_status satf_gl_program_link(const char *label, const GLuint *shaders,
                                 int nshaders, GLuint *out, satf_error *err) {
  *out = 0;
  if (nshaders <= 0 || nshaders > 8)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "program '%s': %d shaders (need 1..8)", label,
                          nshaders);
  GLuint p = glCreateProgram();
  if (p == 0)
    return satf_error_set(err, SATF_ERR_GL, "program '%s': cannot create (%s)",
                          label, gl_error_name(glGetError()));
  for (int i = 0; i < nshaders; i++)
    glAttachShader(p, shaders[i]);
  glLinkProgram(p);
  GLint ok = GL_FALSE;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[640] = "";
    glGetProgramInfoLog(p, (GLsizei)sizeof log, NULL, log);
    trim_log(log);
    glDeleteProgram(p);
    return satf_error_set(err, SATF_ERR_GL, "program '%s': link failed: %s",
                          label, log[0] ? log : "(no log)");
  }
  *out = p;
  return SATF_OK;
}

static satf_status build(const char *label, const GLenum *stages,
                         const char *const *sources, int n, GLuint *out,
                         satf_error *err) {
  GLuint shaders[2] = {0, 0};
  satf_status st = SATF_OK;
  for (int i = 0; i < n && st == SATF_OK; i++)
    st = satf_gl_shader_compile(stages[i], label, sources[i], &shaders[i], err);
  if (st == SATF_OK)
    st = satf_gl_program_link(label, shaders, n, out, err);
  for (int i = 0; i < n; i++)
    if (shaders[i])
      glDeleteShader(shaders[i]);
  return st;
}

satf_status satf_gl_program_build(const char *label, const char *vertex_src,
                                  const char *fragment_src, GLuint *out,
                                  satf_error *err) {
  const GLenum stages[2] = {GL_VERTEX_SHADER, GL_FRAGMENT_SHADER};
  const char *sources[2] = {vertex_src, fragment_src};
  return build(label, stages, sources, 2, out, err);
}

satf_status satf_gl_program_build_compute(const char *label,
                                          const char *compute_src, GLuint *out,
                                          satf_error *err) {
  const GLenum stages[1] = {GL_COMPUTE_SHADER};
  const char *sources[1] = {compute_src};
  return build(label, stages, sources, 1, out, err);
}

/* ---- render targets ---------------------------------------------------- */

#define SATF_GL_MAX_TARGET_COLORS 16

struct satf_gl_target {
  GLuint fbo;
  GLuint color[SATF_GL_MAX_TARGET_COLORS];
  GLuint depth;
  int width, height, ncolor;
};

static GLuint make_texture(GLint internal_format, GLenum format, int width,
                           int height) {
  GLuint tex = 0;
  glGenTextures(1, &tex);
  glBindTexture(GL_TEXTURE_2D, tex);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexImage2D(GL_TEXTURE_2D, 0, internal_format, width, height, 0, format,
               GL_FLOAT, NULL);
  return tex;
}

static const char *fbo_status_name(GLenum s) {
  switch (s) {
  case GL_FRAMEBUFFER_UNDEFINED: return "GL_FRAMEBUFFER_UNDEFINED";
  case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT:
    return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
  case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT:
    return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
  case GL_FRAMEBUFFER_UNSUPPORTED: return "GL_FRAMEBUFFER_UNSUPPORTED";
  case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE:
    return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
  }
  return "incomplete";
}

satf_status satf_gl_target_create(int width, int height, int ncolor,
                                  const satf_gl_format *formats,
                                  satf_gl_target **out, satf_error *err) {
  *out = NULL;
  GLint max_attach = 0, max_draw = 0, max_size = 0, max_rb = 0;
  glGetIntegerv(GL_MAX_COLOR_ATTACHMENTS, &max_attach);
  glGetIntegerv(GL_MAX_DRAW_BUFFERS, &max_draw);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_rb);
  int max_colors = max_attach < max_draw ? max_attach : max_draw;
  if (max_colors > SATF_GL_MAX_TARGET_COLORS)
    max_colors = SATF_GL_MAX_TARGET_COLORS;
  max_size = max_rb < max_size ? max_rb : max_size;
  if (width <= 0 || height <= 0 || width > max_size || height > max_size)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "render target: size %dx%d outside 1..%d", width,
                          height, max_size);
  if (ncolor <= 0 || ncolor > max_colors)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "render target: %d colour attachments (this "
                          "driver allows 1..%d)",
                          ncolor, max_colors);
  for (int i = 0; formats && i < ncolor; i++)
    if (formats[i] != SATF_GL_RGBA32F && formats[i] != SATF_GL_RGBA16F)
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "render target: attachment %d has unknown "
                            "format %d",
                            i, (int)formats[i]);
  satf_gl_target *t = calloc(1, sizeof *t);
  if (!t)
    return satf_error_set(err, SATF_ERR_NOMEM, "render target: out of memory");
  t->width = width;
  t->height = height;
  t->ncolor = ncolor;

  GLint prev_draw = 0, prev_read = 0, prev_tex = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prev_draw);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &prev_read);
  glGetIntegerv(GL_TEXTURE_BINDING_2D, &prev_tex);
  glGenFramebuffers(1, &t->fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
  for (int i = 0; i < ncolor; i++) {
    satf_gl_format f = formats ? formats[i] : SATF_GL_RGBA32F;
    t->color[i] = make_texture(f == SATF_GL_RGBA16F ? GL_RGBA16F : GL_RGBA32F,
                               GL_RGBA, width, height);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i,
                           GL_TEXTURE_2D, t->color[i], 0);
  }
  t->depth =
      make_texture(GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, width, height);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D,
                         t->depth, 0);
  GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glBindTexture(GL_TEXTURE_2D, (GLuint)prev_tex);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)prev_draw);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)prev_read);
  satf_status st = satf_gl_check("render target create", err);
  if (st == SATF_OK && status != GL_FRAMEBUFFER_COMPLETE)
    st = satf_error_set(err, SATF_ERR_GL,
                        "render target %dx%d with %d colour attachments: %s",
                        width, height, ncolor, fbo_status_name(status));
  if (st != SATF_OK) {
    satf_gl_target_destroy(t);
    return st;
  }
  *out = t;
  return SATF_OK;
}

void satf_gl_target_destroy(satf_gl_target *t) {
  if (!t)
    return;
  glDeleteFramebuffers(1, &t->fbo);
  glDeleteTextures(t->ncolor, t->color);
  glDeleteTextures(1, &t->depth);
  free(t);
}

void satf_gl_target_bind(const satf_gl_target *t) {
  GLenum bufs[SATF_GL_MAX_TARGET_COLORS];
  for (int i = 0; i < t->ncolor; i++)
    bufs[i] = GL_COLOR_ATTACHMENT0 + (GLenum)i;
  glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
  glDrawBuffers(t->ncolor, bufs);
  glViewport(0, 0, t->width, t->height);
}

GLuint satf_gl_target_fbo(const satf_gl_target *t) { return t->fbo; }

GLuint satf_gl_target_color_texture(const satf_gl_target *t, int index) {
  return index >= 0 && index < t->ncolor ? t->color[index] : 0;
}

GLuint satf_gl_target_depth_texture(const satf_gl_target *t) {
  return t->depth;
}

int satf_gl_target_width(const satf_gl_target *t) { return t->width; }
int satf_gl_target_height(const satf_gl_target *t) { return t->height; }
int satf_gl_target_color_count(const satf_gl_target *t) { return t->ncolor; }

satf_status satf_gl_read_rgba_bottom_up(GLuint fbo, GLenum read_buffer,
                                        int width, int height, float *dst,
                                        size_t dst_floats, satf_error *err) {
  if (width <= 0 || height <= 0 ||
      dst_floats / 4 / (size_t)width < (size_t)height)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "read-back: %dx%d RGBA does not fit %zu floats",
                          width, height, dst_floats);
  GLint prev_read = 0, prev_pack = 0, prev_align = 0;
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &prev_read);
  /* A bound pack buffer would turn dst into an offset into it. */
  glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &prev_pack);
  glGetIntegerv(GL_PACK_ALIGNMENT, &prev_align);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  glReadBuffer(read_buffer);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, dst);
  glPixelStorei(GL_PACK_ALIGNMENT, prev_align);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)prev_read);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, (GLuint)prev_pack);
  return satf_gl_check("read-back", err);
}

satf_status satf_gl_target_read_bottom_up(const satf_gl_target *t, int index,
                                          float *dst, size_t dst_floats,
                                          satf_error *err) {
  if (index < 0 || index >= t->ncolor)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "render target read-back: attachment %d of %d", index,
                          t->ncolor);
  return satf_gl_read_rgba_bottom_up(t->fbo,
                                     GL_COLOR_ATTACHMENT0 + (GLenum)index,
                                     t->width, t->height, dst, dst_floats, err);
}

/* ---- debug output ------------------------------------------------------ */

static const char *severity_name(GLenum s) {
  switch (s) {
  case GL_DEBUG_SEVERITY_HIGH: return "high";
  case GL_DEBUG_SEVERITY_MEDIUM: return "medium";
  case GL_DEBUG_SEVERITY_LOW: return "low";
  }
  return "note";
}

static void APIENTRY print_debug(GLenum source, GLenum type, GLuint id,
                                 GLenum severity, GLsizei length,
                                 const GLchar *message, const void *user) {
  (void)source, (void)type, (void)length, (void)user;
  if (severity != GL_DEBUG_SEVERITY_NOTIFICATION)
    fprintf(stderr, "GL debug [%s] %u: %s\n", severity_name(severity), id,
            message);
}

static int has_gl_extension(const char *name) {
  GLint n = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &n);
  for (GLint i = 0; i < n; i++) {
    const GLubyte *e = glGetStringi(GL_EXTENSIONS, (GLuint)i);
    if (e && strcmp((const char *)e, name) == 0)
      return 1;
  }
  return 0;
}

satf_status satf_gl_debug_enable(GLDEBUGPROC fn, const void *user,
                                 satf_error *err) {
  GLint maj = 0, min = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &maj);
  glGetIntegerv(GL_MINOR_VERSION, &min);
  if (maj * 10 + min < 43 && !has_gl_extension("GL_KHR_debug"))
    return satf_error_set(err, SATF_ERR_GL,
                          "GL debug output: context %d.%d has no KHR_debug",
                          maj, min);
  glEnable(GL_DEBUG_OUTPUT);
  /* Synchronous so the callback runs inside the offending call, on this
   * thread, where a breakpoint shows the culprit. */
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(fn ? fn : print_debug, user);
  return satf_gl_check("GL debug output", err);
}
