/* test_baseline.c - the --no-satf path (effects.satf off, online/render/
 * baseline.c): Scheuermann 2004 (paper 002), SATF's Fig. 4(a) baseline.
 * Its image owes nothing to the HRIR database (another database gives the
 * same bits, while SATF's image changes); its ambient occlusion darkens
 * inner layers only; its diffuse term is the paper's
 * max(0, 0.75 N.L + 0.25), evaluated from the production GLSL; its
 * depth-sorted passes make the image independent of the clusters' order
 * in the scene. */
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

#include "render_fixture.h"
#include "renderer_internal.h"
#include "satf/gl.h"
#include "satf/render.h"
#include "shaders.h"
#include "test_util.h"

#define W 96
#define H 72

typedef struct fixture {
  fixture_gl *gl;
  satf_db *other; /* another database: other seed, fewer samples */
} fixture;

static int setup(void **state) {
  fixture *f = calloc(1, sizeof *f);
  if (!f || !(f->gl = fixture_gl_create(W, H)))
    return -1;
  satf_build_params p = fixture_db_params();
  p.seed += 1234567;
  p.samples = 24;
  satf_error err;
  if (satf_build(&p, 0, NULL, NULL, &f->other, &err) != SATF_OK) {
    fprintf(stderr, "second database: %s\n", err.message);
    return -1;
  }
  *state = f;
  return 0;
}

static int teardown(void **state) {
  fixture *f = *state;
  satf_db_destroy(f->other);
  fixture_gl_free(f->gl);
  free(f);
  return 0;
}

/* Two clusters crossing on screen: a vertical one in front of a
 * horizontal one, listed in either order; `layers` shells each. */
static satf_scene *two_clusters(int satf, int layers, int swapped,
                                int shadows) {
  char cl[2][512], json[2048];
  snprintf(cl[0], sizeof cl[0],
           "{\"name\": \"vertical\", \"prototype\": {"
           "  \"trajectory\": [[0, -3, 0], [0, 3, 0]], \"a\": 0.9,"
           "  \"shell\": {\"layers\": %d, \"st\": 8, \"su\": 16},"
           "  \"density\": {\"strands\": 600, \"seed\": 1}}}",
           layers);
  snprintf(cl[1], sizeof cl[1],
           "{\"name\": \"horizontal\", \"prototype\": {"
           "  \"trajectory\": [[-3, 0.3, -1.5], [0, 0.1, -1.2], [3, 0.3, "
           "-1.5]], \"a\": 0.8, \"twist\": [0, 2, 4],"
           "  \"shell\": {\"layers\": %d, \"st\": 10, \"su\": 16},"
           "  \"density\": {\"strands\": 700, \"seed\": 3}}}",
           layers);
  snprintf(json, sizeof json,
           "{\"macro_clusters\": [%s, %s],"
           " \"camera\": {\"position\": [1, 2, 12], \"target\": [0, 0, 0],"
           "              \"fov_y\": 40},"
           " \"lights\": [{\"direction\": [-0.5, -0.3, -0.8]},"
           "             {\"type\": \"point\", \"position\": [4, 4, 6],"
           "              \"intensity\": 6, \"color\": [0.8, 0.9, 1]}],"
           " \"effects\": {\"satf\": %s, \"cluster_shadows\": %s},"
           " \"background\": [0, 0, 0]}",
           cl[swapped], cl[!swapped], satf ? "true" : "false",
           shadows ? "true" : "false");
  return fixture_scene(json);
}

/* One frame of `scene` with `db` (all AOVs when aovs). */
static satf_image *render(const satf_scene *scene, const satf_db *db,
                          int aovs) {
  satf_renderer *r = NULL;
  satf_image *img = NULL;
  satf_error err;
  if (satf_renderer_create(scene, db, W, H, 2, &r, &err) != SATF_OK ||
      satf_renderer_render_image(r, aovs, &img, NULL, &err) != SATF_OK)
    fprintf(stderr, "render: %s\n", err.message);
  satf_renderer_destroy(r);
  return img;
}

static double mean_of(const satf_image *img, const char *name) {
  const float *p = fixture_plane(img, name);
  double s = 0.0;
  for (size_t i = 0; p && i < (size_t)W * H; i++)
    s += p[i];
  return s / ((double)W * H);
}

static double luminance_sum(const satf_image *img) {
  return 0.2126 * mean_of(img, "R") + 0.7152 * mean_of(img, "G") +
         0.0722 * mean_of(img, "B");
}

/* The baseline renders the same bits from another database (no records,
 * no database alpha, no s-map from it), in every AOV, deep opacity map on;
 * the SATF frame changes with the database. */
static void test_no_database(void **state) {
  fixture *f = *state;
  satf_scene *base = two_clusters(0, 3, 0, 1), *satf = two_clusters(1, 3, 0, 1);
  assert_non_null(base);
  assert_non_null(satf);
  satf_image *b1 = render(base, f->gl->db, 1), *b2 = render(base, f->other, 1);
  satf_image *s1 = render(satf, f->gl->db, 0), *s2 = render(satf, f->other, 0);
  assert_non_null(b1);
  assert_non_null(b2);
  assert_non_null(s1);
  assert_non_null(s2);
  const char *names[] = {"R",        "G",         "B",
                         "A",        "diffuse.R", "specI.R",
                         "specII.R", "shadow.Y",  "alpha.Y"};
  for (size_t c = 0; c < sizeof names / sizeof *names; c++)
    assert_true(fixture_same_bits(b1, b2, names[c]));
  double coverage = mean_of(b1, "A");
  double satf_diff =
      fmax(fixture_max_diff(s1, s2, "R"), fixture_max_diff(s1, s2, "A"));
  printf("baseline: coverage %.3f, same bits with either database; SATF: "
         "max |d| %.4f between the databases\n",
         coverage, satf_diff);
  assert_true(coverage > 0.05); /* the clusters are drawn */
  assert_true(satf_diff > 0.02);
  satf_image_destroy(b1);
  satf_image_destroy(b2);
  satf_image_destroy(s1);
  satf_image_destroy(s2);
  satf_scene_destroy(base);
  satf_scene_destroy(satf);
}

/* The ambient occlusion term (paper 002, per vertex): (1 - a)^(L-1-k) for
 * layer k, 1 for the outermost; in a frame it darkens a cluster of several
 * layers and leaves a one-layer cluster (outermost only) unchanged. */
static void test_occlusion(void **state) {
  fixture *f = *state;
  for (int k = 0; k < 4; k++)
    assert_near(baseline_layer_occlusion(0.3f, k, 4), powf(0.7f, 3 - k), 1e-6);
  assert_near(baseline_layer_occlusion(0.3f, 3, 4), 1.0, 0.0);
  assert_true(baseline_layer_occlusion(0.3f, 0, 4) <
              baseline_layer_occlusion(0.3f, 1, 4));
  double ratio[2];
  int layers[2] = {1, 4};
  for (int i = 0; i < 2; i++) {
    satf_scene *s = two_clusters(0, layers[i], 0, 0);
    assert_non_null(s);
    satf_image *on = render(s, f->gl->db, 0);
    s->effects.self_shadow = 0; /* --no-self-shadow: no AO */
    satf_image *off = render(s, f->gl->db, 0);
    assert_non_null(on);
    assert_non_null(off);
    ratio[i] = luminance_sum(on) / luminance_sum(off);
    if (i == 0) /* a lone layer is the outermost: AO 1 */
      assert_true(fixture_same_bits(on, off, "R"));
    assert_true(fixture_same_bits(on, off, "A")); /* AO leaves alpha */
    satf_image_destroy(on);
    satf_image_destroy(off);
    satf_scene_destroy(s);
  }
  printf("luminance with AO / without: %.4f (1 layer), %.4f (4 layers)\n",
         ratio[0], ratio[1]);
  assert_near(ratio[0], 1.0, 1e-9);
  assert_true(ratio[1] < 0.95);
}

/* Paper 002's diffuse term from the production GLSL
 * (satf_glsl_baseline_lighting) on the driver, N.L from -1 to 1: the unlit
 * side keeps light down to N.L = -1/3. */
static void test_wrapped_diffuse(void **state) {
  (void)state;
  static const char *head = "#version 430 core\n"
                            "layout(local_size_x = 1) in;\n"
                            "layout(std430, binding = 0) buffer io {\n"
                            "  float v[];\n"
                            "};\n";
  static const char *body =
      "void main() {\n"
      "  uint i = gl_GlobalInvocationID.x;\n"
      "  float c = v[i];\n"
      "  vec3 n = vec3(0.0, 0.0, 1.0);\n"
      "  vec3 l = vec3(sqrt(max(1.0 - c * c, 0.0)), 0.0, c);\n"
      "  v[i] = scheuermann_diffuse(n, l);\n"
      "}\n";
  size_t len =
      strlen(head) + strlen(satf_glsl_baseline_lighting) + strlen(body) + 1;
  char *src = malloc(len);
  assert_non_null(src);
  snprintf(src, len, "%s%s%s", head, satf_glsl_baseline_lighting, body);
  GLuint prog = 0;
  satf_error err;
  satf_status st =
      satf_gl_program_build_compute("wrapped diffuse", src, &prog, &err);
  free(src);
  if (st != SATF_OK)
    fprintf(stderr, "%s\n", err.message);
  assert_int_equal(st, SATF_OK);
  enum { N = 9 };
  const float nl[N] = {-1.0f, -0.5f, -0.34f, -1.0f / 3.0f, -0.3f,
                       -0.2f, 0.0f,  0.5f,   1.0f};
  float out[N];
  GLuint buf;
  glGenBuffers(1, &buf);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buf);
  glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof nl, nl, GL_DYNAMIC_COPY);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf);
  glUseProgram(prog);
  glDispatchCompute(N, 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof out, out);
  glDeleteBuffers(1, &buf);
  glDeleteProgram(prog);
  for (int i = 0; i < N; i++) {
    double want = fmax(0.0, 0.75 * nl[i] + 0.25);
    printf("N.L %+.4f: diffuse %.6f (paper 002: %.6f)\n", nl[i], out[i], want);
    assert_near(out[i], want, 2e-6);
  }
  assert_true(out[5] > 0.09f); /* N.L = -0.2: 0.1, lit from behind */
  assert_true(out[4] > 0.0f);  /* N.L = -0.3 */
  assert_true(out[2] == 0.0f); /* beyond -1/3: dark */
  assert_near(out[6], 0.25, 1e-6);
}

/* The passes sort clusters by a coarse key (their centres' distance from
 * the eye), not by the scene's list: swapping the two clusters' order
 * gives the same image. */
static void test_cluster_order(void **state) {
  fixture *f = *state;
  satf_scene *a = two_clusters(0, 3, 0, 1), *b = two_clusters(0, 3, 1, 1);
  assert_non_null(a);
  assert_non_null(b);
  satf_image *ia = render(a, f->gl->db, 0), *ib = render(b, f->gl->db, 0);
  assert_non_null(ia);
  assert_non_null(ib);
  double d = 0.0;
  const char *names[] = {"R", "G", "B", "A"};
  for (int c = 0; c < 4; c++)
    d = fmax(d, fixture_max_diff(ia, ib, names[c]));
  printf("cluster order swapped: max |d| %.2g\n", d);
  assert_true(d <= 1e-3);
  assert_true(mean_of(ia, "A") > 0.05);
  satf_image_destroy(ia);
  satf_image_destroy(ib);
  satf_scene_destroy(a);
  satf_scene_destroy(b);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_no_database),
      cmocka_unit_test(test_occlusion),
      cmocka_unit_test(test_wrapped_diffuse),
      cmocka_unit_test(test_cluster_order),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
