/* test_lighting.c - the production GLSL lighting functions (SATF eq. 9-11,
 * satf_glsl_lighting, exactly what the shading pass compiles) evaluated on
 * the GPU driver and compared with the formulas worked out in C.
 *
 * A full-screen pass reads, for pixel x, the inputs t, n, l, v, the
 * exponent and the shift from four texels of column x, and writes
 *   target 0: (kk_diffuse(t, l), kk_specular(t, l, v, e),
 *              kk_specular(shifted(t, n, +s), l, v, e),
 *              kk_specular(shifted(t, n, -s), l, v, e))
 *   target 1: (shifted(t, n, s), 0)
 * into RGBA32F targets, so values come back unrounded. */
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

#include "glsl_harness.h"
#include "satf/gl.h"
#include "shaders.h"

#define PI 3.14159265358979323846
#define MAX_SAMPLES 1025

static satf_gl_context *g_ctx;
static GLuint g_prog, g_vao, g_input;

static const char *vs_src =
    "#version 430 core\n"
    "void main() {\n"
    "  vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0,\n"
    "                float((gl_VertexID & 2) << 1) - 1.0);\n"
    "  gl_Position = vec4(p, 0.0, 1.0);\n"
    "}\n";

static const char *fs_head = "#version 430 core\n";
static const char *fs_main =
    "uniform sampler2D u_in;\n"
    "layout(location = 0) out vec4 o_terms;\n"
    "layout(location = 1) out vec4 o_shifted;\n"
    "void main() {\n"
    "  int x = int(gl_FragCoord.x);\n"
    "  vec4 t = texelFetch(u_in, ivec2(x, 0), 0);\n"
    "  vec4 n = texelFetch(u_in, ivec2(x, 1), 0);\n"
    "  vec3 l = texelFetch(u_in, ivec2(x, 2), 0).xyz;\n"
    "  vec3 v = texelFetch(u_in, ivec2(x, 3), 0).xyz;\n"
    "  float e = t.w, s = n.w;\n"
    "  o_terms = vec4(kk_diffuse(t.xyz, l), kk_specular(t.xyz, l, v, e),\n"
    "                 kk_specular(shifted(t.xyz, n.xyz, s), l, v, e),\n"
    "                 kk_specular(shifted(t.xyz, n.xyz, -s), l, v, e));\n"
    "  o_shifted = vec4(shifted(t.xyz, n.xyz, s), 0.0);\n"
    "}\n";

/* One evaluation: the inputs of pixel x. */
typedef struct sample_in {
  float t[3], n[3], l[3], v[3];
  float exponent, shift;
} sample_in;

typedef struct sample_out {
  float diffuse, specular, spec_primary, spec_secondary;
  float shifted[3];
} sample_out;

static int setup(void **state) {
  (void)state;
  if (glsl_harness_create(MAX_SAMPLES, "lighting", vs_src, fs_head,
                          satf_glsl_lighting, fs_main, &g_ctx, &g_prog) != 0)
    return -1;
  glGenVertexArrays(1, &g_vao);
  glGenTextures(1, &g_input);
  return 0;
}

static int teardown(void **state) {
  (void)state;
  glDeleteTextures(1, &g_input);
  glDeleteVertexArrays(1, &g_vao);
  glDeleteProgram(g_prog);
  satf_gl_context_destroy(g_ctx);
  return 0;
}

/* Runs the pass over n samples; 0 on success. */
static int evaluate(const sample_in *in, int n, sample_out *out) {
  satf_error err;
  float *tex = calloc((size_t)n * 16, sizeof(float));
  float *terms = malloc((size_t)n * 4 * sizeof(float));
  float *shifted = malloc((size_t)n * 4 * sizeof(float));
  satf_gl_target *target = NULL;
  int rc = -1;
  if (!tex || !terms || !shifted)
    goto done;
  for (int x = 0; x < n; x++) {
    float *row[4] = {tex + 4 * x, tex + 4 * (n + x), tex + 4 * (2 * n + x),
                     tex + 4 * (3 * n + x)};
    memcpy(row[0], in[x].t, sizeof in[x].t);
    memcpy(row[1], in[x].n, sizeof in[x].n);
    memcpy(row[2], in[x].l, sizeof in[x].l);
    memcpy(row[3], in[x].v, sizeof in[x].v);
    row[0][3] = in[x].exponent;
    row[1][3] = in[x].shift;
  }
  glBindTexture(GL_TEXTURE_2D, g_input);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, n, 4, 0, GL_RGBA, GL_FLOAT, tex);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  if (satf_gl_target_create(n, 1, 2, NULL, &target, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    goto done;
  }
  satf_gl_target_bind(target);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(g_prog);
  glActiveTexture(GL_TEXTURE0);
  glUniform1i(glGetUniformLocation(g_prog, "u_in"), 0);
  glBindVertexArray(g_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  if (satf_gl_check("lighting pass", &err) != SATF_OK ||
      satf_gl_target_read_bottom_up(target, 0, terms, (size_t)n * 4, &err) !=
          SATF_OK ||
      satf_gl_target_read_bottom_up(target, 1, shifted, (size_t)n * 4, &err) !=
          SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    goto done;
  }
  for (int x = 0; x < n; x++) {
    out[x].diffuse = terms[4 * x];
    out[x].specular = terms[4 * x + 1];
    out[x].spec_primary = terms[4 * x + 2];
    out[x].spec_secondary = terms[4 * x + 3];
    memcpy(out[x].shifted, shifted + 4 * x, 3 * sizeof(float));
  }
  rc = 0;
done:
  satf_gl_target_destroy(target);
  free(tex);
  free(terms);
  free(shifted);
  return rc;
}

static void set3(float *d, double x, double y, double z) {
  d[0] = (float)x;
  d[1] = (float)y;
  d[2] = (float)z;
}

/* SATF eq. 9: with t along x and l at angle a from t in the xy plane, the
 * diffuse term is sin a. */
static void test_diffuse_is_sine(void **state) {
  (void)state;
  enum { N = 9 };
  const double angles[N] = {0.0,        0.3, PI / 6, PI / 4, PI / 2,
                            2 * PI / 3, 2.5, 3.0,    PI};
  sample_in in[N];
  sample_out out[N];
  memset(in, 0, sizeof in);
  for (int i = 0; i < N; i++) {
    set3(in[i].t, 1, 0, 0);
    set3(in[i].n, 0, 1, 0);
    set3(in[i].l, cos(angles[i]), sin(angles[i]), 0);
    set3(in[i].v, 0, 0, 1);
    in[i].exponent = 1.0f;
  }
  assert_int_equal(evaluate(in, N, out), 0);
  for (int i = 0; i < N; i++) {
    double want = sin(angles[i]);
    if (fabs(out[i].diffuse - want) > 1e-5)
      fail_msg("angle %g: kk_diffuse %.8f, sin %.8f", angles[i],
               (double)out[i].diffuse, want);
  }
  /* the tangent's sign does not matter (a fibre has no direction) */
  for (int i = 0; i < N; i++)
    set3(in[i].t, -1, 0, 0);
  assert_int_equal(evaluate(in, N, out), 0);
  for (int i = 0; i < N; i++)
    assert_true(fabs(out[i].diffuse - sin(angles[i])) <= 1e-5);
}

/* SATF eq. 10 in its mirror form: sin(t,l) sin(t,v) - (t.l)(t.v), raised to
 * the exponent. */
static void test_specular_configurations(void **state) {
  (void)state;
  enum { N = 8 };
  sample_in in[N];
  sample_out out[N];
  double want[N];
  memset(in, 0, sizeof in);
  for (int i = 0; i < N; i++) {
    set3(in[i].t, 1, 0, 0);
    set3(in[i].n, 0, 1, 0);
  }
  /* 0-1: mirror configuration, v = l reflected through the normal plane
   * of t: sin^2 + cos^2 = 1 for any angle and any exponent */
  set3(in[0].l, cos(0.4), sin(0.4), 0);
  set3(in[0].v, -cos(0.4), sin(0.4), 0);
  in[0].exponent = 80.0f;
  want[0] = 1.0;
  set3(in[1].l, cos(1.1), 0, sin(1.1));
  set3(in[1].v, -cos(1.1), sin(1.1) * 0.6, sin(1.1) * 0.8);
  in[1].exponent = 7.0f;
  want[1] = 1.0;
  /* 2-4: retro-reflection (v = l) at 60 degrees from t: sin^2 - cos^2 =
   * -cos(120 deg) = 1/2, then the exponent */
  for (int i = 2; i <= 4; i++) {
    set3(in[i].l, cos(PI / 3), sin(PI / 3), 0);
    set3(in[i].v, cos(PI / 3), sin(PI / 3), 0);
  }
  in[2].exponent = 1.0f;
  want[2] = 0.5;
  in[3].exponent = 4.0f;
  want[3] = 0.0625;
  in[4].exponent = 0.5f;
  want[4] = sqrt(0.5);
  /* 5: retro-reflection at 30 degrees: -cos(60 deg) < 0, clamped to 0 */
  set3(in[5].l, cos(PI / 6), sin(PI / 6), 0);
  set3(in[5].v, cos(PI / 6), sin(PI / 6), 0);
  in[5].exponent = 2.0f;
  want[5] = 0.0;
  /* 6-7: l at a1 in the xy plane, v at a2 in the xz plane: sin a1 sin a2 -
   * cos a1 cos a2 = -cos(a1 + a2) */
  set3(in[6].l, cos(1.0), sin(1.0), 0);
  set3(in[6].v, cos(2.5), 0, sin(2.5));
  in[6].exponent = 80.0f;
  want[6] = pow(-cos(3.5), 80.0);
  set3(in[7].l, cos(1.0), sin(1.0), 0);
  set3(in[7].v, cos(2.5), 0, sin(2.5));
  in[7].exponent = 1.0f;
  want[7] = -cos(3.5);
  assert_int_equal(evaluate(in, N, out), 0);
  for (int i = 0; i < N; i++) {
    double tol = 1e-5 + 1e-4 * want[i];
    if (fabs(out[i].specular - want[i]) > tol)
      fail_msg("case %d: kk_specular %.8g, expected %.8g", i,
               (double)out[i].specular, want[i]);
  }
}

/* Paper 002: t~ = normalize(t + s n). */
static void test_shifted_tangent(void **state) {
  (void)state;
  enum { N = 5 };
  const double shifts[N] = {0.0, 0.1, -0.2, 0.5, 1.0};
  sample_in in[N];
  sample_out out[N];
  memset(in, 0, sizeof in);
  for (int i = 0; i < N; i++) {
    set3(in[i].t, 0, 0.6, 0.8);
    set3(in[i].n, 1, 0, 0);
    set3(in[i].l, 0, 0, 1);
    set3(in[i].v, 0, 0, 1);
    in[i].exponent = 1.0f;
    in[i].shift = (float)shifts[i];
  }
  assert_int_equal(evaluate(in, N, out), 0);
  for (int i = 0; i < N; i++) {
    double s = shifts[i], len = sqrt(1.0 + s * s);
    double want[3] = {s / len, 0.6 / len, 0.8 / len};
    for (int a = 0; a < 3; a++)
      assert_true(fabs(out[i].shifted[a] - want[a]) <= 1e-6);
  }
}

/* The lit strip: an arc of hair point(theta) = (sin, 0, cos) for theta in
 * [-pi/3, pi/3] from the root to the tip, outward normal n = point,
 * tangent t = (cos, 0, -sin) towards the tip, light and viewer along +z.
 * The shifted tangent is perpendicular to z where tan(theta) = s, so the
 * primary highlight (shift +s) peaks at theta = atan(s), towards the tip,
 * and the secondary (shift -s) at -atan(s), towards the root. */
static void test_highlight_shift_on_arc(void **state) {
  (void)state;
  enum { N = MAX_SAMPLES, NS = 4 };
  const double shifts[NS] = {0.0, 0.05, 0.1, 0.2};
  const double step = (2.0 * PI / 3.0) / (N - 1);
  sample_in *in = calloc(N, sizeof *in);
  sample_out *out = calloc(N, sizeof *out);
  assert_non_null(in);
  assert_non_null(out);
  int prev_primary = -1, prev_secondary = N;
  for (int k = 0; k < NS; k++) {
    for (int x = 0; x < N; x++) {
      double th = -PI / 3.0 + step * x;
      set3(in[x].t, cos(th), 0, -sin(th));
      set3(in[x].n, sin(th), 0, cos(th));
      set3(in[x].l, 0, 0, 1);
      set3(in[x].v, 0, 0, 1);
      in[x].exponent = 80.0f;
      in[x].shift = (float)shifts[k];
    }
    assert_int_equal(evaluate(in, N, out), 0);
    int p = 0, q = 0;
    for (int x = 1; x < N; x++) {
      if (out[x].spec_primary > out[p].spec_primary)
        p = x;
      if (out[x].spec_secondary > out[q].spec_secondary)
        q = x;
    }
    double tp = -PI / 3.0 + step * p, tq = -PI / 3.0 + step * q;
    double want = atan(shifts[k]);
    if (fabs(tp - want) > step || fabs(tq + want) > step)
      fail_msg("shift %g: primary peak at %.5f, secondary at %.5f; expected "
               "+-%.5f (one sample = %.5f)",
               shifts[k], tp, tq, want, step);
    /* the peak is the full highlight: the shifted tangent is (nearly)
     * perpendicular to both l and v there */
    assert_true(out[p].spec_primary > 0.99f);
    assert_true(out[q].spec_secondary > 0.99f);
    if (k == 0) {
      assert_int_equal(p, (N - 1) / 2); /* theta = 0 is sample 512 */
      assert_int_equal(q, (N - 1) / 2);
    } else {
      assert_true(p > prev_primary);   /* towards the tip */
      assert_true(q < prev_secondary); /* towards the root */
    }
    prev_primary = p;
    prev_secondary = q;
  }
  free(in);
  free(out);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_diffuse_is_sine),
      cmocka_unit_test(test_specular_configurations),
      cmocka_unit_test(test_shifted_tangent),
      cmocka_unit_test(test_highlight_shift_on_arc),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
