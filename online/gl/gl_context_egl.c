/* gl_context_egl.c - headless OpenGL contexts through EGL; see
 * gl_context.h. */
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/gl.h"

struct satf_gl_context {
  EGLDisplay display;
  EGLContext context;
  int width, height;
  int major, minor;
  char renderer[256];
};

/* Newest first; Mesa refuses versions above what it implements, so the
 * first success is the best the driver offers. */
static const int gl_versions[][2] = {{4, 6}, {4, 5}, {4, 3}, {3, 3}};

static const char *egl_error_name(EGLint code) {
  switch (code) {
  case EGL_SUCCESS: return "EGL_SUCCESS";
  case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
  case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
  case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
  case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
  case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
  case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
  case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
  case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
  case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
  case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
  case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
  case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
  case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
  case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
  }
  return "unknown EGL error";
}

/* Whole-word match in a space-separated extension string. */
static int has_extension(const char *list, const char *name) {
  size_t n = strlen(name);
  for (const char *p = list; p && (p = strstr(p, name)) != NULL; p += n) {
    int starts = p == list || p[-1] == ' ';
    int ends = p[n] == '\0' || p[n] == ' ';
    if (starts && ends)
      return 1;
  }
  return 0;
}

/* Initialises the first usable display: Mesa surfaceless, else each EGL
 * device in turn. Records the last EGL error for the caller's message. */
static EGLDisplay open_display(EGLint *last_error, const char **tried) {
  *last_error = EGL_SUCCESS;
  *tried = "none: this EGL offers no platform extension (is an EGL vendor "
           "such as Debian's libegl-mesa0 installed?)";
  const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  PFNEGLGETPLATFORMDISPLAYEXTPROC get_display =
      (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress(
          "eglGetPlatformDisplayEXT");
  if (!client || !get_display ||
      !has_extension(client, "EGL_EXT_platform_base")) {
    *last_error = eglGetError();
    return EGL_NO_DISPLAY;
  }
  EGLint major = 0, minor = 0;
  if (has_extension(client, "EGL_MESA_platform_surfaceless")) {
    *tried = "Mesa surfaceless platform";
    EGLDisplay d =
        get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor))
      return d;
    *last_error = eglGetError();
  }
  PFNEGLQUERYDEVICESEXTPROC query_devices =
      (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
  if (query_devices && has_extension(client, "EGL_EXT_platform_device")) {
    *tried = "Mesa surfaceless platform and EGL devices";
    EGLDeviceEXT devices[16];
    EGLint ndevices = 0;
    if (!query_devices(16, devices, &ndevices))
      ndevices = 0;
    for (EGLint i = 0; i < ndevices; i++) {
      EGLDisplay d = get_display(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL);
      if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor))
        return d;
      *last_error = eglGetError();
    }
  }
  return EGL_NO_DISPLAY;
}

static EGLContext create_core_context(EGLDisplay d, EGLConfig config,
                                      EGLint *last_error) {
  for (size_t i = 0; i < sizeof gl_versions / sizeof gl_versions[0]; i++) {
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                              gl_versions[i][0],
                              EGL_CONTEXT_MINOR_VERSION,
                              gl_versions[i][1],
                              EGL_CONTEXT_OPENGL_PROFILE_MASK,
                              EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_NONE};
    EGLContext c = eglCreateContext(d, config, EGL_NO_CONTEXT, attribs);
    if (c != EGL_NO_CONTEXT)
      return c;
    *last_error = eglGetError();
  }
  return EGL_NO_CONTEXT;
}

/* The display is deliberately not terminated: EGL displays are per-process
 * singletons, so eglTerminate here would destroy every other satf context
 * on it. The driver releases it at process exit. */
void satf_gl_context_destroy(satf_gl_context *ctx) {
  if (!ctx)
    return;
  if (ctx->context != EGL_NO_CONTEXT) {
    if (eglGetCurrentContext() == ctx->context)
      eglMakeCurrent(ctx->display, EGL_NO_SURFACE, EGL_NO_SURFACE,
                     EGL_NO_CONTEXT);
    eglDestroyContext(ctx->display, ctx->context);
  }
  free(ctx);
}

static satf_status fail(satf_gl_context *ctx, satf_error *err,
                        satf_status status, const char *what, EGLint code) {
  satf_gl_context_destroy(ctx);
  if (code == EGL_SUCCESS)
    return satf_error_set(err, status, "EGL headless context: %s", what);
  return satf_error_set(err, status, "EGL headless context: %s (EGL error %s)",
                        what, egl_error_name(code));
}

satf_status satf_gl_context_create_headless(int width, int height,
                                            satf_gl_context **out,
                                            satf_error *err) {
  *out = NULL;
  if (width <= 0 || height <= 0)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "EGL headless context: invalid frame size %dx%d",
                          width, height);
  satf_gl_context *ctx = calloc(1, sizeof *ctx);
  if (!ctx)
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "EGL headless context: out of memory");
  ctx->context = EGL_NO_CONTEXT;
  ctx->width = width;
  ctx->height = height;

  EGLint code = EGL_SUCCESS;
  const char *tried = "";
  ctx->display = open_display(&code, &tried);
  if (ctx->display == EGL_NO_DISPLAY) {
    char what[256];
    snprintf(what, sizeof what, "no usable EGL display; tried: %s", tried);
    return fail(ctx, err, SATF_ERR_GL, what, code);
  }
  const char *exts = eglQueryString(ctx->display, EGL_EXTENSIONS);
  if (!has_extension(exts, "EGL_KHR_surfaceless_context"))
    return fail(ctx, err, SATF_ERR_GL,
                "display lacks EGL_KHR_surfaceless_context", eglGetError());
  if (!eglBindAPI(EGL_OPENGL_API))
    return fail(ctx, err, SATF_ERR_GL, "desktop OpenGL API not supported",
                eglGetError());
  /* EGL_SURFACE_TYPE 0 matches every config: none is drawn to. */
  const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                   EGL_SURFACE_TYPE, 0, EGL_NONE};
  EGLConfig config = NULL;
  EGLint nconfigs = 0;
  if (!eglChooseConfig(ctx->display, config_attribs, &config, 1, &nconfigs) ||
      nconfigs < 1)
    return fail(ctx, err, SATF_ERR_GL, "no config renders desktop OpenGL",
                eglGetError());
  ctx->context = create_core_context(ctx->display, config, &code);
  if (ctx->context == EGL_NO_CONTEXT)
    return fail(ctx, err, SATF_ERR_GL,
                "cannot create an OpenGL 3.3+ core context", code);
  if (!eglMakeCurrent(ctx->display, EGL_NO_SURFACE, EGL_NO_SURFACE,
                      ctx->context))
    return fail(ctx, err, SATF_ERR_GL, "cannot make the context current",
                eglGetError());
  satf_status st =
      satf_gl_query_context(width, height, &ctx->major, &ctx->minor,
                            ctx->renderer, sizeof ctx->renderer, err);
  if (st != SATF_OK) {
    satf_gl_context_destroy(ctx);
    return st;
  }
  *out = ctx;
  return SATF_OK;
}

satf_status satf_gl_context_make_current(const satf_gl_context *ctx,
                                         satf_error *err) {
  if (!eglMakeCurrent(ctx->display, EGL_NO_SURFACE, EGL_NO_SURFACE,
                      ctx->context))
    return satf_error_set(err, SATF_ERR_GL,
                          "EGL headless context: cannot make current (%s)",
                          egl_error_name(eglGetError()));
  return SATF_OK;
}

void satf_gl_context_version(const satf_gl_context *ctx, int *major,
                             int *minor) {
  *major = ctx->major;
  *minor = ctx->minor;
}

const char *satf_gl_context_renderer(const satf_gl_context *ctx) {
  return ctx->renderer;
}

void satf_gl_context_size(const satf_gl_context *ctx, int *width, int *height) {
  *width = ctx->width;
  *height = ctx->height;
}
