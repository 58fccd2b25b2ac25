/* test_fiber_glsl.c - the GLSL twin of the fibre model
 * (online/render/glsl/fiber.glsl, satf_glsl_fiber, what the strand shader
 * compiles) evaluated on the GL driver and compared with fiber/fiber.c:
 * the single-scattering BCSDF (fiber_single against satf_fiber_eval) and
 * the dual-scattering shading (fiber_dual_shade against
 * satf_fiber_dual_shade, the tables uploaded as the renderer does), over
 * a sweep of directions, offsets, materials and hair counts; and the
 * cluster path's per-vertex global term (fiber_cluster.glsl's key_global,
 * from the tables fiber_gpu_bind uploads) against satf_fiber_dual_global.
 *
 * Pixel x reads wo, h from texel (x, 0) and wi, n_hairs from (x, 1) and
 * writes fiber_single to target 0 and fiber_dual_shade to target 1
 * (RGBA32F, unrounded). */
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

#include "fiber_gpu.h"
#include "glsl_harness.h"
#include "satf/fiber.h"
#include "satf/gl.h"
#include "shaders.h"

#define N 600
#define NTAB 32

static satf_gl_context *g_ctx;
static GLuint g_prog, g_vao, g_input, g_tables;

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
    "uniform sampler2D u_tables;\n"
    "uniform float u_eta, u_s, u_alpha;\n"
    "uniform vec4 u_v;\n"
    "uniform vec3 u_sigma_a;\n"
    "layout(location = 0) out vec4 o_single;\n"
    "layout(location = 1) out vec4 o_dual;\n"
    "void main() {\n"
    "  int x = int(gl_FragCoord.x);\n"
    "  vec4 a = texelFetch(u_in, ivec2(x, 0), 0);\n"
    "  vec4 b = texelFetch(u_in, ivec2(x, 1), 0);\n"
    "  Fiber f = Fiber(u_eta, u_v, u_s, u_sigma_a, u_alpha);\n"
    "  o_single = vec4(fiber_single(f, a.xyz, b.xyz, a.w), 0.0);\n"
    "  o_dual = vec4(fiber_dual_shade(f, u_tables, a.xyz, b.xyz, a.w, b.w),\n"
    "                0.0);\n"
    "}\n";

static int setup(void **state) {
  (void)state;
  if (glsl_harness_create(N, "fiber", vs_src, fs_head, satf_glsl_fiber, fs_main,
                          &g_ctx, &g_prog) != 0)
    return -1;
  glGenVertexArrays(1, &g_vao);
  glGenTextures(1, &g_input);
  glGenTextures(1, &g_tables);
  return 0;
}

static int teardown(void **state) {
  (void)state;
  glDeleteTextures(1, &g_input);
  glDeleteTextures(1, &g_tables);
  glDeleteVertexArrays(1, &g_vao);
  glDeleteProgram(g_prog);
  satf_gl_context_destroy(g_ctx);
  return 0;
}

static void texture(GLuint tex, GLenum internal, int w, int h, GLenum format,
                    const float *data) {
  glBindTexture(GL_TEXTURE_2D, tex);
  glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, w, h, 0, format, GL_FLOAT,
               data);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

/* Runs the pass for fibre f over n inputs (wo, h, wi, n_hairs per
 * sample); 0 on success. */
static int evaluate(const satf_fiber *f, const float *tables, const float *in,
                    int n, float *single, float *dual) {
  satf_error err;
  satf_gl_target *target = NULL;
  float *tex = calloc((size_t)n * 8, sizeof(float));
  if (!tex)
    return -1;
  for (int x = 0; x < n; x++) {
    memcpy(tex + 4 * x, in + 8 * x, 4 * sizeof(float));
    memcpy(tex + 4 * (n + x), in + 8 * x + 4, 4 * sizeof(float));
  }
  glActiveTexture(GL_TEXTURE0);
  texture(g_input, GL_RGBA32F, n, 2, GL_RGBA, tex);
  glActiveTexture(GL_TEXTURE1);
  texture(g_tables, GL_RGB32F, SATF_FIBER_DUAL_FIELDS, NTAB, GL_RGB, tables);
  free(tex);
  if (satf_gl_target_create(n, 1, 2, NULL, &target, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  satf_gl_target_bind(target);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(g_prog);
  glUniform1i(glGetUniformLocation(g_prog, "u_in"), 0);
  glUniform1i(glGetUniformLocation(g_prog, "u_tables"), 1);
  glUniform1f(glGetUniformLocation(g_prog, "u_eta"), f->eta);
  glUniform1f(glGetUniformLocation(g_prog, "u_s"), f->s);
  glUniform1f(glGetUniformLocation(g_prog, "u_alpha"), f->alpha);
  glUniform4fv(glGetUniformLocation(g_prog, "u_v"), 1, f->v);
  glUniform3fv(glGetUniformLocation(g_prog, "u_sigma_a"), 1, f->sigma_a);
  glBindVertexArray(g_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  int rc = 0;
  if (satf_gl_check("fiber pass", &err) != SATF_OK ||
      satf_gl_target_read_bottom_up(target, 0, single, (size_t)n * 4, &err) !=
          SATF_OK ||
      satf_gl_target_read_bottom_up(target, 1, dual, (size_t)n * 4, &err) !=
          SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    rc = -1;
  }
  satf_gl_target_destroy(target);
  return rc;
}

static void unit_dir(double theta, double phi, float *w) {
  w[0] = (float)sin(theta);
  w[1] = (float)(cos(theta) * cos(phi));
  w[2] = (float)(cos(theta) * sin(phi));
}

/* |a - b| within rel of the larger plus an absolute floor (the GPU's
 * exp, log and atan are not the C library's). */
static int close(float a, float b, double rel, double abs_tol) {
  return fabs((double)a - (double)b) <=
         rel * fmax(fabs((double)a), fabs((double)b)) + abs_tol;
}

static void run_material(float melanin, float redness, float beta_m,
                         float beta_n, float tilt_deg) {
  satf_fiber_material m = satf_fiber_material_default();
  m.melanin = melanin;
  m.redness = redness;
  m.roughness = beta_m;
  m.radial_roughness = beta_n;
  m.cuticle_tilt = tilt_deg * 3.14159265f / 180.0f;
  satf_fiber f;
  satf_fiber_init(&f, &m);
  float *tables = malloc(sizeof(float) * NTAB * SATF_FIBER_DUAL_FIELDS * 3);
  float *in = malloc(sizeof(float) * 8 * N);
  float *single = malloc(sizeof(float) * 4 * N);
  float *dual = malloc(sizeof(float) * 4 * N);
  assert_true(tables && in && single && dual);
  satf_fiber_dual_tables(&f, NTAB, tables);
  for (int x = 0; x < N; x++) {
    float *s = in + 8 * x;
    /* a deterministic sweep: inclinations over (-1.4, 1.4), azimuths all
     * round, h over [-0.99, 0.99], hair counts 0 to 12 */
    unit_dir(-1.4 + 2.8 * ((x * 37) % N) / N, 6.28 * ((x * 13) % 97) / 97.0, s);
    s[3] = -0.99f + 1.98f * (float)((x * 71) % N) / N;
    unit_dir(-1.4 + 2.8 * ((x * 53 + 7) % N) / N,
             6.28 * ((x * 29 + 3) % 89) / 89.0, s + 4);
    s[7] = (float)(x % 13);
  }
  assert_int_equal(evaluate(&f, tables, in, N, single, dual), 0);
  int bad = 0;
  double worst = 0;
  for (int x = 0; x < N; x++) {
    const float *s = in + 8 * x;
    float c_single[3], c_dual[3];
    satf_fiber_eval(&f, s, s + 4, s[3], c_single);
    satf_fiber_dual_shade(&f, tables, NTAB, s, s + 4, s[3], s[7], c_dual);
    for (int c = 0; c < 3; c++) {
      float g1 = single[4 * x + c], g2 = dual[4 * x + c];
      assert_true(isfinite(g1) && isfinite(g2) && g1 >= 0 && g2 >= 0);
      if (c_single[c] > 1e-3)
        worst = fmax(worst, fabs(g1 - c_single[c]) / c_single[c]);
      if (c_dual[c] > 1e-3)
        worst = fmax(worst, fabs(g2 - c_dual[c]) / c_dual[c]);
      if (!close(g1, c_single[c], 2e-4, 1e-6) ||
          !close(g2, c_dual[c], 2e-4, 1e-6)) {
        if (bad++ < 8)
          fprintf(stderr, "x %d c %d: single %g (C %g), dual %g (C %g)\n", x, c,
                  g1, c_single[c], g2, c_dual[c]);
      }
    }
  }
  /* measured on llvmpipe: 1.5e-5 at worst */
  assert_true(worst < 2e-4);
  assert_int_equal(bad, 0);
  free(tables);
  free(in);
  free(single);
  free(dual);
}

/* key_global's look-up (fiber_cluster.glsl) against the term it tabulates,
 * satf_fiber_dual_global at h = 0 and one hair, in the fibre frame
 * key_global builds (y the view across the hair): within 2.5% of the
 * term's peak for directions within 66 degrees of the hair's normal
 * plane, as the table's own test (test_fiber_dual: global_table) bounds
 * its interpolation, so the GLSL reads the table as the C writes it. Pixel
 * x: v from texel (x, 0), l from (x, 1); targets global, back. */
static const char *fs_cluster =
    "uniform sampler2D u_in;\n"
    "layout(location = 0) out vec4 o_global;\n"
    "layout(location = 1) out vec4 o_back;\n"
    "void main() {\n"
    "  int x = int(gl_FragCoord.x);\n"
    "  vec3 v = texelFetch(u_in, ivec2(x, 0), 0).xyz;\n"
    "  vec3 l = texelFetch(u_in, ivec2(x, 1), 0).xyz;\n"
    "  vec3 back;\n"
    "  o_global = vec4(key_global(vec3(0.0, 0.0, 1.0), v, l, back), 0.0);\n"
    "  o_back = vec4(back, 0.0);\n"
    "}\n";

static void cluster_global_matches_c(void **state) {
  (void)state;
  GLuint prog;
  satf_error err;
  size_t len = strlen(fs_head) + strlen(satf_glsl_fiber_cluster) +
               strlen(fs_cluster) + 1;
  char *fs = malloc(len);
  assert_non_null(fs);
  snprintf(fs, len, "%s%s%s", fs_head, satf_glsl_fiber_cluster, fs_cluster);
  if (satf_gl_program_build("cluster fibre", vs_src, fs, &prog, &err) !=
      SATF_OK)
    fail_msg("%s", err.message);
  free(fs);
  satf_scene_material m;
  memset(&m, 0, sizeof m);
  m.melanin = 0.6f;
  m.redness = 0.0f;
  m.roughness = 0.3f;
  m.radial_roughness = 0.3f;
  m.cuticle_tilt = 2.0f;
  m.ior = 1.55f;
  satf_fiber f;
  fiber_from_material(&m, &f);
  float tab[FIBER_TABLE_ROWS * SATF_FIBER_DUAL_FIELDS * 3];
  satf_fiber_dual_tables(&f, FIBER_TABLE_ROWS, tab);
  /* directions about the hair z: inclinations within 66 degrees of its
   * normal plane, azimuths all round (a deterministic sweep) */
  float *tex = calloc((size_t)N * 8, sizeof(float));
  float *global = malloc((size_t)N * 4 * sizeof(float));
  float *back = malloc((size_t)N * 4 * sizeof(float));
  assert_true(tex && global && back);
  const double lim = 66.0 * 3.14159265358979 / 180.0;
  for (int x = 0; x < N; x++) {
    double tv = -lim + 2 * lim * ((x * 37) % N) / N;
    double tl = -lim + 2 * lim * ((x * 53 + 7) % N) / N;
    double pv = 6.28 * ((x * 13) % 97) / 97.0;
    double pl = 6.28 * ((x * 29 + 3) % 89) / 89.0;
    float *v = tex + 4 * x, *l = tex + 4 * (N + x);
    v[0] = (float)(cos(tv) * cos(pv));
    v[1] = (float)(cos(tv) * sin(pv));
    v[2] = (float)sin(tv);
    l[0] = (float)(cos(tl) * cos(pl));
    l[1] = (float)(cos(tl) * sin(pl));
    l[2] = (float)sin(tl);
  }
  glActiveTexture(GL_TEXTURE0);
  texture(g_input, GL_RGBA32F, N, 2, GL_RGBA, tex);
  satf_gl_target *target = NULL;
  assert_int_equal(satf_gl_target_create(N, 1, 2, NULL, &target, &err),
                   SATF_OK);
  satf_gl_target_bind(target);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(prog);
  glUniform1i(glGetUniformLocation(prog, "u_in"), 0);
  fiber_gpu gpu;
  memset(&gpu, 0, sizeof gpu);
  gpu.with_global = 1;
  fiber_gpu_bind(&gpu, &m, prog);
  glBindVertexArray(g_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  assert_int_equal(satf_gl_check("cluster fibre pass", &err), SATF_OK);
  assert_int_equal(
      satf_gl_target_read_bottom_up(target, 0, global, (size_t)N * 4, &err),
      SATF_OK);
  assert_int_equal(
      satf_gl_target_read_bottom_up(target, 1, back, (size_t)N * 4, &err),
      SATF_OK);
  double peak_g = 0, peak_b = 0, err_g = 0, err_b = 0;
  for (int x = 0; x < N; x++) {
    const float *v = tex + 4 * x, *l = tex + 4 * (N + x);
    /* key_global's frame: y the view across the hair (z), x = hair */
    float yv[3] = {v[0], v[1], 0.0f};
    float ny = sqrtf(yv[0] * yv[0] + yv[1] * yv[1]);
    yv[0] /= ny;
    yv[1] /= ny;
    float zv[3] = {-yv[1], yv[0], 0.0f}; /* hair x y */
    float wo[3] = {v[2], v[0] * yv[0] + v[1] * yv[1], 0.0f};
    float wi[3] = {l[2], l[0] * yv[0] + l[1] * yv[1],
                   l[0] * zv[0] + l[1] * zv[1]};
    float cg[3], cb[3];
    satf_fiber_dual_global(&f, tab, FIBER_TABLE_ROWS, wo, wi, 0.0f, 1.0f, cg,
                           cb);
    /* the back-scattering's step at |phi| = pi / 2 is left out within
     * 3 degrees, where the texture blends the two sides */
    float phi = fabsf(atan2f(wi[2], wi[1]));
    int near_step = fabsf(phi - 1.5707963f) < 0.05f;
    for (int c = 0; c < 3; c++) {
      assert_true(isfinite(global[4 * x + c]) && global[4 * x + c] >= 0.0f);
      assert_true(isfinite(back[4 * x + c]) && back[4 * x + c] >= 0.0f);
      peak_g = fmax(peak_g, cg[c]);
      peak_b = fmax(peak_b, cb[c]);
      err_g = fmax(err_g, fabs(global[4 * x + c] - cg[c]));
      if (!near_step)
        err_b = fmax(err_b, fabs(back[4 * x + c] - cb[c]));
    }
  }
  printf("key_global: global within %.4f of its peak %.4f, back %.4f of "
         "%.4f\n",
         err_g / peak_g, peak_g, err_b / peak_b, peak_b);
  assert_true(peak_g > 1e-3 && peak_b > 1e-3);
  assert_true(err_g <= 0.025 * peak_g);
  assert_true(err_b <= 0.025 * peak_b);
  fiber_gpu_release(&gpu);
  satf_gl_target_destroy(target);
  glDeleteProgram(prog);
  free(tex);
  free(global);
  free(back);
}

static void glsl_matches_c_brown(void **state) {
  (void)state;
  run_material(0.6f, 0.0f, 0.3f, 0.3f, 2.0f);
}

static void glsl_matches_c_blond_smooth(void **state) {
  (void)state;
  run_material(0.15f, 0.4f, 0.12f, 0.2f, 3.0f);
}

static void glsl_matches_c_dark_rough(void **state) {
  (void)state;
  run_material(0.95f, 0.1f, 0.7f, 0.8f, 0.0f);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(glsl_matches_c_brown),
      cmocka_unit_test(glsl_matches_c_blond_smooth),
      cmocka_unit_test(glsl_matches_c_dark_rough),
      cmocka_unit_test(cluster_global_matches_c),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
