/* glsl_harness.h - what the tests that evaluate a GLSL library alone share
 * (test_lighting: lighting.glsl, test_fiber_glsl: fiber.glsl): a headless
 * context w x 1 and a program whose fragment shader is head + library +
 * main. Header-only; each test includes it once. */
#ifndef SATF_TESTS_GLSL_HARNESS_H
#define SATF_TESTS_GLSL_HARNESS_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/gl.h"

/* 0, or -1 after printing why (nothing left to free then). */
static inline int glsl_harness_create(int w, const char *label, const char *vs,
                                      const char *head, const char *library,
                                      const char *main, satf_gl_context **ctx,
                                      GLuint *prog) {
  satf_error err;
  if (satf_gl_context_create_headless(w, 1, ctx, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  size_t len = strlen(head) + strlen(library) + strlen(main);
  char *fs = malloc(len + 1);
  if (!fs) {
    satf_gl_context_destroy(*ctx);
    return -1;
  }
  snprintf(fs, len + 1, "%s%s%s", head, library, main);
  satf_status st = satf_gl_program_build(label, vs, fs, prog, &err);
  free(fs);
  if (st != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    satf_gl_context_destroy(*ctx);
    return -1;
  }
  return 0;
}

#endif
