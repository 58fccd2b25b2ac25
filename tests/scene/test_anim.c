/* test_anim.c - keyframe animation of scene files (satf/anim.h): every kind
 * of track hits its keys exactly, is continuous between them and C1 where
 * it is cubic, holds its end keys outside them; keys equal to the static
 * values change nothing; slerp halves a rotation; each malformed case has
 * its own message; the Fig. 8 sample matches SATF Table 1. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "satf/math.h"
#include "satf/scene.h"
#include "scene_cases.h"

static satf_scene *parse_anim(const char *json) {
  return parse_ok(json, "anim.json");
}

static satf_scene *at(const satf_scene *scene, double frame) {
  satf_scene *snap = NULL;
  satf_error err;
  satf_status s = satf_scene_at_frame(scene, frame, &snap, &err);
  if (s != SATF_OK)
    fprintf(stderr, "frame %g: %s\n", frame, err.message);
  assert_int_equal(s, SATF_OK);
  assert_non_null(snap);
  assert_false(satf_scene_is_animated(snap));
  return snap;
}

static void assert_vec(const float *got, const double *want, int n,
                       double tol) {
  for (int i = 0; i < n; i++)
    assert_near(got[i], want[i], tol);
}

/* Row-major 3x4 part of an instance matrix against a hand-worked one. */
static void assert_matrix(const float m[16], const double want[12],
                          double tol) {
  assert_vec(m, want, 12, tol);
  assert_true(m[12] == 0.0f && m[13] == 0.0f && m[14] == 0.0f && m[15] == 1.0f);
}

/* ---- every kind of track hits its keys ---- */

/* A key's missing values come from the static object: the expected values
 * below are the static object with each key's values put over it. */
static const char *const KEYED =
    "{\"animation\": {\"fps\": 30, \"frames\": [0, 20]},"
    " \"macro_clusters\": [{\"prototype\": {"
    "   \"trajectory\": [[0,0,0],[0,1,0],[0,2,0]], \"a\": [0.5,0.6,0.7],"
    "   \"b\": 0.3, \"twist\": [0,0.5,1],"
    "   \"keys\": ["
    "    {\"frame\": 2, \"trajectory\": [[0,0,0],[1,1,0],[2,2,0]],"
    "     \"a\": [0.4,0.5,0.6], \"b\": 0.2, \"twist\": [0,1,2]},"
    "    {\"frame\": 5, \"trajectory\": [[0,0,0],[-1,1,0],[-2,1.5,0.5]]},"
    "    {\"frame\": 11, \"a\": [1,1,1], \"twist\": [3,2,1]},"
    "    {\"frame\": 12.5, \"trajectory\": [[0,0,1],[0.5,1,0],[1,3,0]],"
    "     \"b\": 0.9}]},"
    "  \"instances\": ["
    "   {\"translate\": [1,0,0], \"keys\": ["
    "    {\"frame\": 0, \"translate\": [1,2,3],"
    "     \"rotate\": {\"axis\": [0,0,1], \"angle\": 90}, \"scale\": 2},"
    "    {\"frame\": 4, \"rotate\": {\"axis\": [1,0,0], \"angle\": -90}},"
    "    {\"frame\": 9, \"scale\": [1,2,3], \"translate\": [0,0,0]},"
    "    {\"frame\": 20}]},"
    "   {\"matrix\": [1,0,0,5, 0,1,0,6, 0,0,1,7, 0,0,0,1], \"keys\": ["
    "    {\"frame\": 3, \"matrix\": [0,-1,0,5, 1,0,0,6, 0,0,2,7, 0,0,0,1]},"
    "    {\"frame\": 6},"
    "    {\"frame\": 8, \"matrix\": [1,0,0,0, 0,0,-3,1, 0,3,0,2, 0,0,0,1]}]}"
    "  ]}],"
    " \"camera\": {\"position\": [0,0,10], \"target\": [0,0,0], \"keys\": ["
    "   {\"frame\": 1, \"fov_y\": 30},"
    "   {\"frame\": 6, \"position\": [5,1,8], \"target\": [0,1,0],"
    "    \"up\": [0.1,1,0], \"fov_y\": 50},"
    "   {\"frame\": 15, \"position\": [10,0,0]}]},"
    " \"lights\": ["
    "  {\"direction\": [0,0,-1], \"keys\": ["
    "   {\"frame\": 2, \"direction\": [1,0,-1], \"color\": [1,0.5,0.25],"
    "    \"intensity\": 2},"
    "   {\"frame\": 7, \"intensity\": 0.5}]},"
    "  {\"type\": \"point\", \"position\": [0,5,0], \"keys\": ["
    "   {\"frame\": 3, \"position\": [1,5,0]},"
    "   {\"frame\": 4, \"position\": [2,6,0], \"intensity\": 3}]}]}";

static void test_keys_hit_exactly(void **state) {
  (void)state;
  satf_scene *scene = parse_anim(KEYED);
  assert_int_equal(satf_scene_warning_count(scene), 0);
  assert_true(satf_scene_is_animated(scene));
  int first, last;
  assert_int_equal(satf_scene_frame_range(scene, &first, &last), 1);
  assert_int_equal(first, 0);
  assert_int_equal(last, 20);
  assert_near(satf_scene_fps(scene), 30.0, 0);
  assert_true(satf_scene_prototype_is_animated(scene, 0));
  assert_false(satf_scene_prototype_is_animated(scene, 1));
  assert_true(satf_scene_instance_is_animated(scene, 0, 1));
  assert_false(satf_scene_instance_is_animated(scene, 0, 2));
  const double tol = 1e-6;

  /* prototype: trajectory, a, b, twist */
  static const struct {
    double frame;
    double trajectory[9], a[3], b, twist[3];
  } proto[] = {
      {2, {0, 0, 0, 1, 1, 0, 2, 2, 0}, {0.4, 0.5, 0.6}, 0.2, {0, 1, 2}},
      {5, {0, 0, 0, -1, 1, 0, -2, 1.5, 0.5}, {0.5, 0.6, 0.7}, 0.3, {0, 0.5, 1}},
      {11, {0, 0, 0, 0, 1, 0, 0, 2, 0}, {1, 1, 1}, 0.3, {3, 2, 1}},
      {12.5, {0, 0, 1, 0.5, 1, 0, 1, 3, 0}, {0.5, 0.6, 0.7}, 0.9, {0, 0.5, 1}},
  };
  for (size_t k = 0; k < sizeof proto / sizeof proto[0]; k++) {
    satf_scene *snap = at(scene, proto[k].frame);
    const satf_scene_cluster *c = &snap->macro_clusters[0].prototype;
    assert_vec(c->trajectory, proto[k].trajectory, 9, tol);
    assert_vec(c->a.values, proto[k].a, 3, tol);
    assert_near(c->b.values[0], proto[k].b, tol);
    assert_vec(c->twist.values, proto[k].twist, 3, tol);
    satf_scene_destroy(snap);
  }

  /* instances: T R S keys and matrix keys */
  static const struct {
    int instance;
    double frame, m[12];
  } inst[] = {
      /* scale 2, +90 about z, then (1,2,3) */
      {0, 0, {0, -2, 0, 1, 2, 0, 0, 2, 0, 0, 2, 3}},
      /* static translate (1,0,0); -90 about x maps (x,y,z) to (x,z,-y) */
      {0, 4, {1, 0, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0}},
      {0, 9, {1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 3, 0}},
      {0, 20, {1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0}},
      {1, 3, {0, -1, 0, 5, 1, 0, 0, 6, 0, 0, 2, 7}},
      {1, 6, {1, 0, 0, 5, 0, 1, 0, 6, 0, 0, 1, 7}},
      {1, 8, {1, 0, 0, 0, 0, 0, -3, 1, 0, 3, 0, 2}},
  };
  for (size_t k = 0; k < sizeof inst / sizeof inst[0]; k++) {
    satf_scene *snap = at(scene, inst[k].frame);
    assert_matrix(snap->macro_clusters[0].instances[inst[k].instance].m,
                  inst[k].m, tol);
    satf_scene_destroy(snap);
  }

  /* camera: position, target, up (normalized), fov_y */
  double n01 = sqrt(0.01 + 1.0);
  const struct {
    double frame, position[3], target[3], up[3], fov;
  } cam[] = {
      {1, {0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 30},
      {6, {5, 1, 8}, {0, 1, 0}, {0.1 / n01, 1 / n01, 0}, 50},
      {15, {10, 0, 0}, {0, 0, 0}, {0, 1, 0}, 40},
  };
  for (size_t k = 0; k < sizeof cam / sizeof cam[0]; k++) {
    satf_scene *snap = at(scene, cam[k].frame);
    assert_vec(snap->camera.position, cam[k].position, 3, tol);
    assert_vec(snap->camera.target, cam[k].target, 3, tol);
    assert_vec(snap->camera.up, cam[k].up, 3, tol);
    assert_near(snap->camera.fov_y, cam[k].fov, tol);
    assert_int_equal(snap->camera.automatic, 0);
    satf_scene_destroy(snap);
  }

  /* lights: direction (normalized), color, intensity; point position */
  double r2 = sqrt(0.5);
  const struct {
    double frame, direction[3], color[3], intensity;
  } dir[] = {{2, {r2, 0, -r2}, {1, 0.5, 0.25}, 2},
             {7, {0, 0, -1}, {1, 1, 1}, 0.5}};
  for (size_t k = 0; k < 2; k++) {
    satf_scene *snap = at(scene, dir[k].frame);
    assert_vec(snap->lights[0].direction, dir[k].direction, 3, tol);
    assert_vec(snap->lights[0].color, dir[k].color, 3, tol);
    assert_near(snap->lights[0].intensity, dir[k].intensity, tol);
    satf_scene_destroy(snap);
  }
  const struct {
    double frame, position[3], intensity;
  } point[] = {{3, {1, 5, 0}, 1}, {4, {2, 6, 0}, 3}};
  for (size_t k = 0; k < 2; k++) {
    satf_scene *snap = at(scene, point[k].frame);
    assert_int_equal(snap->lights[1].type, SATF_SCENE_LIGHT_POINT);
    assert_vec(snap->lights[1].position, point[k].position, 3, tol);
    assert_near(snap->lights[1].intensity, point[k].intensity, tol);
    satf_scene_destroy(snap);
  }
  satf_scene_destroy(scene);
}

/* ---- continuity ---- */

/* Every float a renderer reads from a snapshot, in one list. */
static int snapshot_values(const satf_scene *s, float *out, int cap) {
  int n = 0;
#define PUT(ptr, count)                                                        \
  do {                                                                         \
    assert_true(n + (count) <= cap);                                           \
    memcpy(out + n, (ptr), (size_t)(count) * sizeof *out);                     \
    n += (count);                                                              \
  } while (0)
  for (int i = 0; i < s->n_macro_clusters; i++) {
    const satf_scene_macro_cluster *mc = &s->macro_clusters[i];
    const satf_scene_cluster *c = &mc->prototype;
    PUT(c->trajectory, 3 * c->n_points);
    PUT(c->a.values, c->a.count);
    PUT(c->b.values, c->b.count);
    PUT(c->twist.values, c->twist.count);
    for (int j = 0; j < mc->n_instances; j++)
      PUT(mc->instances[j].m, 16);
  }
  PUT(s->camera.position, 3);
  PUT(s->camera.target, 3);
  PUT(s->camera.up, 3);
  PUT(&s->camera.fov_y, 1);
  for (int l = 0; l < s->n_lights; l++) {
    PUT(s->lights[l].direction, 3);
    PUT(s->lights[l].position, 3);
    PUT(s->lights[l].color, 3);
    PUT(&s->lights[l].intensity, 1);
  }
#undef PUT
  return n;
}

static void test_continuous_between_keys(void **state) {
  (void)state;
  satf_scene *scene = parse_anim(KEYED);
  static const double keys[] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12.5, 15};
  float v0[256], vm[256], vp[256];
  for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++) {
    satf_scene *s0 = at(scene, keys[k]), *sm = at(scene, keys[k] - 1e-4),
               *sp = at(scene, keys[k] + 1e-4);
    int n = snapshot_values(s0, v0, 256);
    assert_int_equal(snapshot_values(sm, vm, 256), n);
    assert_int_equal(snapshot_values(sp, vp, 256), n);
    /* Slopes here are at most a few units per frame. */
    for (int i = 0; i < n; i++) {
      if (fabs(vm[i] - v0[i]) > 1e-2 || fabs(vp[i] - v0[i]) > 1e-2) {
        fprintf(stderr, "frame %g value %d: %g | %g | %g\n", keys[k], i, vm[i],
                v0[i], vp[i]);
        fail();
      }
    }
    satf_scene_destroy(s0);
    satf_scene_destroy(sm);
    satf_scene_destroy(sp);
  }
  /* And nowhere else a jump: a fine sweep changes by small steps. */
  satf_scene *prev = at(scene, -1.0);
  int n = snapshot_values(prev, vm, 256);
  for (double f = -1.0 + 1.0 / 64; f <= 21.0; f += 1.0 / 64) {
    satf_scene *cur = at(scene, f);
    assert_int_equal(snapshot_values(cur, vp, 256), n);
    for (int i = 0; i < n; i++)
      assert_true(fabs(vp[i] - vm[i]) < 0.5);
    memcpy(vm, vp, sizeof vm);
    satf_scene_destroy(prev);
    prev = cur;
  }
  satf_scene_destroy(prev);
  satf_scene_destroy(scene);
}

/* Keys at frames 0, 2, 7, 10 holding 0, 4, -1, 3: chord slopes 2, -1,
 * 4/3 jump at each interior key, so only a C1 cubic passes. Catmull-Rom
 * tangents: at 2, (-1 - 0) / 7; at 7, (3 - 4) / 8. */
static const char *const CUBIC =
    "{\"animation\": {\"frames\": [0, 10]},"
    " \"macro_clusters\": [{\"prototype\": {"
    "   \"trajectory\": [[0,0,0],[0,1,0]], \"a\": 0.5, \"keys\": ["
    "    {\"frame\": 0, \"trajectory\": [[0,0,0],[0,1,0]]},"
    "    {\"frame\": 2, \"trajectory\": [[0,0,0],[4,1,0]]},"
    "    {\"frame\": 7, \"trajectory\": [[0,0,0],[-1,1,0]]},"
    "    {\"frame\": 10, \"trajectory\": [[0,0,0],[3,1,0]]}]},"
    "  \"instances\": [{\"keys\": ["
    "    {\"frame\": 0, \"translate\": [0,0,0]},"
    "    {\"frame\": 2, \"translate\": [4,0,0]},"
    "    {\"frame\": 7, \"translate\": [-1,0,0]},"
    "    {\"frame\": 10, \"translate\": [3,0,0]}]}]}],"
    " \"camera\": {\"position\": [0,0,20], \"target\": [0,0,0], \"keys\": ["
    "    {\"frame\": 0, \"position\": [0,0,20]},"
    "    {\"frame\": 2, \"position\": [4,0,20]},"
    "    {\"frame\": 7, \"position\": [-1,0,20]},"
    "    {\"frame\": 10, \"position\": [3,0,20]}]}}";

static double cubic_x(const satf_scene *scene, int track, double frame) {
  satf_scene *s = at(scene, frame);
  double x = track == 0   ? s->macro_clusters[0].prototype.trajectory[3]
             : track == 1 ? s->macro_clusters[0].instances[0].m[3]
                          : s->camera.position[0];
  satf_scene_destroy(s);
  return x;
}

static void test_cubic_is_c1(void **state) {
  (void)state;
  satf_scene *scene = parse_anim(CUBIC);
  static const double key_frames[2] = {2, 7}, tangent[2] = {-1.0 / 7, -1.0 / 8};
  const double h = 1e-3;
  for (int track = 0; track < 3; track++) {
    for (int k = 0; k < 2; k++) {
      double f = key_frames[k], v = cubic_x(scene, track, f);
      double left = (v - cubic_x(scene, track, f - h)) / h;
      double right = (cubic_x(scene, track, f + h) - v) / h;
      assert_near(left, right, 0.02);
      assert_near(left, tangent[k], 0.02);
      assert_near(right, tangent[k], 0.02);
    }
    /* The interpolant is a Hermite cubic: at the middle of [2, 7] it is
     * (4 + -1) / 2 + 5 (m2 - m7) / 8 with m2 = -1/7 and m7 = -1/8. */
    assert_near(cubic_x(scene, track, 4.5),
                1.5 + 5.0 * (-1.0 / 7 + 1.0 / 8) / 8, 1e-5);
  }
  satf_scene_destroy(scene);

  /* Two keys: the cubic reduces to a straight line. */
  satf_scene *two = parse_anim(
      "{\"animation\": {\"frames\": [1, 5]},"
      " \"macro_clusters\": [{\"prototype\": {"
      "   \"trajectory\": [[0,0,0],[0,1,0]], \"a\": 0.5, \"keys\": ["
      "    {\"frame\": 1, \"a\": 0.5}, {\"frame\": 5, \"a\": 1.5}]}}]}");
  for (int i = 0; i <= 8; i++) {
    satf_scene *s = at(two, 1.0 + 0.5 * i);
    assert_near(s->macro_clusters[0].prototype.a.values[0], 0.5 + i / 8.0,
                1e-6);
    satf_scene_destroy(s);
  }
  satf_scene_destroy(two);
}

/* ---- keys equal to the static values change nothing ---- */

static void test_static_keys_change_nothing(void **state) {
  (void)state;
  satf_scene *scene = parse_anim(
      "{\"animation\": {\"frames\": [1, 10]},"
      " \"macro_clusters\": [{\"prototype\": {"
      "   \"trajectory\": [[0,0,0],[0.3,1,0.1],[0.2,2,0.7]],"
      "   \"a\": [0.5,0.6,0.7], \"b\": 0.3, \"twist\": [0,0.5,1.3], \"keys\": ["
      "    {\"frame\": 1, \"trajectory\": [[0,0,0],[0.3,1,0.1],[0.2,2,0.7]],"
      "     \"a\": [0.5,0.6,0.7], \"b\": 0.3, \"twist\": [0,0.5,1.3]},"
      "    {\"frame\": 4},"
      "    {\"frame\": 7.5, \"a\": [0.5,0.6,0.7]},"
      "    {\"frame\": 10, \"trajectory\": [[0,0,0],[0.3,1,0.1],[0.2,2,0.7]]}"
      "  ]},"
      "  \"instances\": ["
      "   {\"translate\": [1,2,3], \"rotate\": {\"axis\": [1,1,0], \"angle\": "
      "33}, \"scale\": [1,2,0.5], \"keys\": ["
      "    {\"frame\": 2, \"translate\": [1,2,3],"
      "     \"rotate\": {\"axis\": [1,1,0], \"angle\": 33}},"
      "    {\"frame\": 5}, {\"frame\": 9, \"scale\": [1,2,0.5]}]},"
      "   {\"matrix\": [0.8,-0.6,0,1, 0.6,0.8,0,2, 0.1,0,1.5,3, 0,0,0,1],"
      "    \"keys\": [{\"frame\": 1, \"matrix\": [0.8,-0.6,0,1, 0.6,0.8,0,2,"
      "     0.1,0,1.5,3, 0,0,0,1]}, {\"frame\": 3}]},"
      "   {}]}],"
      " \"camera\": {\"position\": [3,4,20], \"target\": [0,1,0],"
      "   \"up\": [0.2,1,0], \"fov_y\": 35, \"keys\": ["
      "    {\"frame\": 1, \"position\": [3,4,20], \"up\": [0.2,1,0]},"
      "    {\"frame\": 6, \"fov_y\": 35}, {\"frame\": 10}]},"
      " \"lights\": ["
      "  {\"direction\": [1,-2,-3], \"color\": [0.9,0.8,0.7], \"keys\": ["
      "    {\"frame\": 2, \"direction\": [1,-2,-3]},"
      "    {\"frame\": 8, \"color\": [0.9,0.8,0.7], \"intensity\": 1}]},"
      "  {\"type\": \"point\", \"position\": [1,2,3], \"intensity\": 50,"
      "   \"keys\": [{\"frame\": 1, \"position\": [1,2,3]},"
      "    {\"frame\": 3, \"intensity\": 50}]}]}");
  assert_int_equal(satf_scene_warning_count(scene), 0);
  for (double f = -3.0; f <= 14.0; f += 0.125) {
    satf_scene *snap = at(scene, f);
    assert_int_equal(snap->n_macro_clusters, 1);
    assert_true(
        satf_scene_prototype_equal(&snap->macro_clusters[0].prototype,
                                   &scene->macro_clusters[0].prototype));
    assert_true(satf_scene_instances_equal(&snap->macro_clusters[0],
                                           &scene->macro_clusters[0]));
    assert_true(satf_scene_camera_equal(&snap->camera, &scene->camera));
    assert_int_equal(snap->n_lights, 2);
    assert_true(satf_scene_light_equal(&snap->lights[0], &scene->lights[0]));
    assert_true(satf_scene_light_equal(&snap->lights[1], &scene->lights[1]));
    assert_int_equal(satf_scene_hsv_count(snap), satf_scene_hsv_count(scene));
    assert_int_equal(satf_scene_warning_count(snap), 0);
    assert_string_equal(snap->name, scene->name);
    satf_scene_destroy(snap);
  }
  satf_scene_destroy(scene);
}

/* ---- outside the keys the end keys hold ---- */

static void test_end_keys_hold(void **state) {
  (void)state;
  satf_scene *scene = parse_anim(KEYED);
  /* Each track's first key at or after frame 0 and last at or before 20:
   * before frame 0 and after frame 20 every value holds; the prototype's
   * keys run 2..12.5, so it holds from frames 0 and 20 too. */
  satf_scene *first = at(scene, 0.0), *last = at(scene, 20.0);
  static const double before[] = {-1e6, -100, -0.5, -1e-9};
  static const double after[] = {20.25, 21, 1e3, 1e9};
  for (int i = 0; i < 4; i++) {
    satf_scene *a = at(scene, before[i]), *b = at(scene, after[i]);
    for (int m = 0; m < 2; m++) {
      satf_scene *snap = m ? b : a, *end = m ? last : first;
      assert_true(
          satf_scene_prototype_equal(&snap->macro_clusters[0].prototype,
                                     &end->macro_clusters[0].prototype));
      assert_true(satf_scene_instances_equal(&snap->macro_clusters[0],
                                             &end->macro_clusters[0]));
      assert_true(satf_scene_camera_equal(&snap->camera, &end->camera));
      assert_true(satf_scene_light_equal(&snap->lights[0], &end->lights[0]));
      assert_true(satf_scene_light_equal(&snap->lights[1], &end->lights[1]));
    }
    satf_scene_destroy(a);
    satf_scene_destroy(b);
  }
  /* The prototype holds its first key (frame 2) from frame 0 up to 2, and
   * its last key (frame 12.5) from there to 20. */
  satf_scene *k2 = at(scene, 2.0), *k12 = at(scene, 12.5);
  assert_true(satf_scene_prototype_equal(&first->macro_clusters[0].prototype,
                                         &k2->macro_clusters[0].prototype));
  assert_true(satf_scene_prototype_equal(&last->macro_clusters[0].prototype,
                                         &k12->macro_clusters[0].prototype));
  assert_near(first->macro_clusters[0].prototype.trajectory[3], 1.0, 0);
  /* The point light's keys are 3 and 4: frame 0 holds (1,5,0), frame 20
   * holds (2,6,0) with intensity 3. */
  assert_near(first->lights[1].position[0], 1.0, 0);
  assert_near(last->lights[1].position[1], 6.0, 0);
  assert_near(last->lights[1].intensity, 3.0, 0);
  satf_scene_destroy(k2);
  satf_scene_destroy(k12);
  satf_scene_destroy(first);
  satf_scene_destroy(last);
  satf_scene_destroy(scene);
}

/* ---- rotations: slerp ---- */

static void test_slerp_halves_rotations(void **state) {
  (void)state;
  satf_scene *scene = parse_anim(
      "{\"animation\": {\"frames\": [1, 5]},"
      " \"macro_clusters\": [{\"prototype\": {\"trajectory\": "
      "[[0,0,0],[0,1,0]], \"a\": 0.5}, \"instances\": ["
      "  {\"keys\": [{\"frame\": 1},"
      "   {\"frame\": 3, \"translate\": [2,4,6],"
      "    \"rotate\": {\"axis\": [0,0,1], \"angle\": 90}}]},"
      "  {\"matrix\": [2,0,0,0, 0,2,0,0, 0,0,2,0, 0,0,0,1], \"keys\": ["
      "   {\"frame\": 1},"
      "   {\"frame\": 3, \"matrix\": [2,0,0,0, 0,0,-2,0, 0,2,0,0, 0,0,0,1]}]},"
      "  {\"keys\": [{\"frame\": 1},"
      "   {\"frame\": 2, \"rotate\": {\"axis\": [0,1,0], \"angle\": 90}},"
      "   {\"frame\": 3, \"rotate\": {\"axis\": [0,1,0], \"angle\": 180}}]}"
      " ]}]}");
  satf_scene *mid = at(scene, 2.0);
  double c = cos(SATF_PI / 4), s = sin(SATF_PI / 4);
  /* 45 degrees about z; the translation halfway along the line. */
  const double r45z[12] = {c, -s, 0, 1, s, c, 0, 2, 0, 0, 1, 3};
  assert_matrix(mid->macro_clusters[0].instances[0].m, r45z, 1e-6);
  /* Matrix keys split by the polar decomposition: scale 2 is kept, the
   * rotation about x goes halfway. */
  const double r45x[12] = {2, 0, 0, 0, 0, 2 * c, -2 * s, 0, 0, 2 * s, 2 * c, 0};
  assert_matrix(mid->macro_clusters[0].instances[1].m, r45x, 1e-6);
  /* The angle between consecutive snapshots' rotations is uniform: a point
   * on x turns at constant speed (slerp). */
  for (int i = 0; i <= 8; i++) {
    satf_scene *snap = at(scene, 1.0 + 0.25 * i);
    const float *m = snap->macro_clusters[0].instances[0].m;
    double angle = atan2(m[4], m[0]);
    assert_near(angle, (SATF_PI / 2) * i / 8.0, 1e-6);
    satf_scene_destroy(snap);
  }
  satf_scene_destroy(mid);
  /* Three keys, 0, 90, 180 about y: at 2.5 it is 135 degrees. */
  satf_scene *late = at(scene, 2.5);
  double c3 = cos(3 * SATF_PI / 4), s3 = sin(3 * SATF_PI / 4);
  const double r135y[12] = {c3, 0, s3, 0, 0, 1, 0, 0, -s3, 0, c3, 0};
  assert_matrix(late->macro_clusters[0].instances[2].m, r135y, 1e-6);
  satf_scene_destroy(late);
  satf_scene_destroy(scene);
}

/* ---- malformed animations: each its own message with its key path ---- */

#define ANIM "\"animation\": {\"frames\": [1, 48]}"
#define PROTO_KEYS(keys)                                                       \
  "{" ANIM ", \"macro_clusters\": [{\"prototype\": {\"trajectory\": "          \
  "[[0,0,0],[0,1,0]], \"a\": 0.5, \"twist\": [0, 1], \"keys\": " keys "}}]}"
#define INSTANCE(inst)                                                         \
  "{" ANIM ", \"macro_clusters\": [{\"prototype\": {\"trajectory\": "          \
  "[[0,0,0],[0,1,0]], \"a\": 0.5}, \"instances\": [" inst "]}]}"
#define MINIMAL_MC                                                             \
  "\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]], "  \
  "\"a\": 0.5}}]"
#define WITH(extra) "{" ANIM ", " MINIMAL_MC ", " extra "}"

static const bad_case bad_cases[] = {
    {"{\"animation\": 5, " MINIMAL_MC "}", SATF_ERR_FORMAT,
     "anim.json: animation: expected an object, got a number"},
    {"{\"animation\": {}, " MINIMAL_MC "}", SATF_ERR_FORMAT,
     "anim.json: animation.frames: missing required key"},
    {"{\"animation\": {\"fps\": 0, \"frames\": [1, 2]}, " MINIMAL_MC "}",
     SATF_ERR_ARGUMENT, "animation.fps: 0 is out of range (0, 1000]"},
    {"{\"animation\": {\"frames\": [1]}, " MINIMAL_MC "}", SATF_ERR_FORMAT,
     "animation.frames: expected [first, last], got 1 entries"},
    {"{\"animation\": {\"frames\": 3}, " MINIMAL_MC "}", SATF_ERR_FORMAT,
     "animation.frames: expected an array, got a number"},
    {"{\"animation\": {\"frames\": [1, 2.5]}, " MINIMAL_MC "}", SATF_ERR_FORMAT,
     "animation.frames[1]: 2.5 is not an integer"},
    {"{\"animation\": {\"frames\": [1, \"x\"]}, " MINIMAL_MC "}",
     SATF_ERR_FORMAT, "animation.frames[1]: expected an integer, got a string"},
    {"{\"animation\": {\"frames\": [1e400, 2]}, " MINIMAL_MC "}",
     SATF_ERR_ARGUMENT,
     "animation.frames[0]: number is too large to represent (parsed as inf)"},
    {"{\"animation\": {\"frames\": [10, 2]}, " MINIMAL_MC "}",
     SATF_ERR_ARGUMENT,
     "animation.frames: the last frame 2 is before the first frame 10"},
    {"{\"animation\": {\"frames\": [1, 2], \"frames\": [1, 3]}, " MINIMAL_MC
     "}",
     SATF_ERR_FORMAT, "animation: key \"frames\" appears twice"},
    {"{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]],"
     " \"a\": 0.5, \"keys\": [{\"frame\": 1}]}}]}",
     SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.keys: keyframes need a top-level "
     "\"animation\" object giving the frame range"},
    {PROTO_KEYS("{}"), SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.keys: expected an array, got an object"},
    {PROTO_KEYS("[]"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.keys: has 0 entries, expected 1 to 65536"},
    {PROTO_KEYS("[5]"), SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.keys[0]: expected an object, got a number"},
    {PROTO_KEYS("[{\"a\": 1}]"), SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.keys[0].frame: missing required key"},
    {PROTO_KEYS("[{\"frame\": 60}]"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.keys[0].frame: 60 is out of range [1, 48]"},
    {PROTO_KEYS("[{\"frame\": 0.5}]"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.keys[0].frame: 0.5 is out of range [1, 48]"},
    {PROTO_KEYS("[{\"frame\": \"1\"}]"), SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.keys[0].frame: expected a number, got a "
     "string"},
    {PROTO_KEYS("[{\"frame\": 5}, {\"frame\": 5}]"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.keys[1].frame: 5 is not after the previous "
     "key's frame 5; key frames must increase"},
    {PROTO_KEYS("[{\"frame\": 5}, {\"frame\": 9}, {\"frame\": 3}]"),
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.keys[2].frame: 3 is not after the previous "
     "key's frame 9"},
    {PROTO_KEYS("[{\"frame\": 1, \"trajectory\": [[0,0,0],[0,1,0],[0,2,0]]}]"),
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.keys[0].trajectory: has 3 control points "
     "but the static trajectory has 2; keys keep the counts"},
    {PROTO_KEYS("[{\"frame\": 1}, {\"frame\": 2, \"a\": [1, 2]}]"),
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.keys[1].a: has 2 control values but the "
     "static a has 1; keys keep the counts"},
    {PROTO_KEYS("[{\"frame\": 1, \"twist\": [0, 1, 2]}]"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.keys[0].twist: has 3 control values but "
     "the static twist has 2"},
    {PROTO_KEYS("[{\"frame\": 1, \"trajectory\": [[0,0,0],[0,1e400,0]]}]"),
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.keys[0].trajectory[1][1]: number is too "
     "large to represent"},
    {PROTO_KEYS("[{\"frame\": 1, \"trajectory\": [[1,1,1],[1,1,1]]}]"),
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.keys[0].trajectory: all 2 control points "
     "coincide"},
    {PROTO_KEYS("[{\"frame\": 1, \"b\": -1}]"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].prototype.keys[0].b: -1 is out of range (0, "
     "1000000]"},
    {PROTO_KEYS("[{\"frame\": 1, \"shell\": {\"layers\": 2}}]"),
     SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.keys[0].shell: cannot be animated; a "
     "prototype key may give trajectory, a, b and twist"},
    {PROTO_KEYS("[{\"frame\": 1, \"density\": {}}]"), SATF_ERR_FORMAT,
     "macro_clusters[0].prototype.keys[0].density: cannot be animated"},
    {INSTANCE("{\"keys\": [{\"frame\": 1, \"matrix\": [1,0,0,0, 0,1,0,0, "
              "0,0,1,0, 0,0,0,1], \"scale\": 2}]}"),
     SATF_ERR_FORMAT,
     "macro_clusters[0].instances[0].keys[0]: \"matrix\" cannot be combined "
     "with \"scale\""},
    {INSTANCE("{}, {\"matrix\": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "
              "\"keys\": [{\"frame\": 1}, {\"frame\": 2, \"translate\": "
              "[1,0,0]}]}"),
     SATF_ERR_FORMAT,
     "macro_clusters[0].instances[1].keys[1].translate: the instance is "
     "given as a \"matrix\", so its keys must give a \"matrix\" too"},
    {INSTANCE("{\"keys\": [{\"frame\": 1, \"matrix\": [1,0,0,0, 0,1,0,0, "
              "0,0,0,0, 0,0,0,1]}]}"),
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].instances[0].keys[0].matrix: is singular"},
    {INSTANCE("{\"keys\": [{\"frame\": 1, \"rotate\": {\"axis\": [0,0,0], "
              "\"angle\": 10}}]}"),
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].instances[0].keys[0].rotate.axis: has zero length"},
    {INSTANCE("{\"keys\": [{\"frame\": 1}, {\"frame\": 2, \"scale\": [1, 0, "
              "1]}]}"),
     SATF_ERR_ARGUMENT,
     "macro_clusters[0].instances[0].keys[1].scale: 0 is too close to zero"},
    {INSTANCE("{\"keys\": [{\"frame\": 49}]}"), SATF_ERR_ARGUMENT,
     "macro_clusters[0].instances[0].keys[0].frame: 49 is out of range [1, "
     "48]"},
    {WITH("\"camera\": {\"keys\": 3}"), SATF_ERR_FORMAT,
     "camera.keys: expected an array, got a number"},
    {WITH("\"camera\": {\"position\": [0,0,5], \"keys\": [{\"frame\": 1, "
          "\"target\": [0,0,5]}]}"),
     SATF_ERR_ARGUMENT,
     "camera.keys[0].target: coincides with the camera position"},
    {WITH("\"camera\": {\"position\": [0,0,5], \"target\": [0,0,0], "
          "\"keys\": [{\"frame\": 1}, {\"frame\": 2, \"up\": [0,0,1]}]}"),
     SATF_ERR_ARGUMENT,
     "camera.keys[1].up: is zero or parallel to the view direction"},
    {WITH("\"camera\": {\"keys\": [{\"frame\": 1, \"fov_y\": 180}]}"),
     SATF_ERR_ARGUMENT, "camera.keys[0].fov_y: 180 is out of range [0.1, 179]"},
    {WITH("\"camera\": {\"keys\": [{\"frame\": 1, \"near\": 1}]}"),
     SATF_ERR_FORMAT,
     "camera.keys[0].near: cannot be animated; a camera key may give "
     "position, target, up and fov_y"},
    {WITH("\"lights\": [{\"direction\": [0,0,-1], \"keys\": [{\"frame\": 1, "
          "\"direction\": [0,0,0]}]}]"),
     SATF_ERR_ARGUMENT, "lights[0].keys[0].direction: has zero length"},
    {WITH("\"lights\": [{\"direction\": [0,0,-1]}, {\"direction\": [0,0,-1], "
          "\"keys\": [{\"frame\": 1, \"type\": \"point\"}]}]"),
     SATF_ERR_FORMAT,
     "lights[1].keys[0].type: cannot be animated; a light key may give its "
     "direction or position, color and intensity"},
    {WITH("\"lights\": [{\"type\": \"point\", \"position\": [0,0,1], "
          "\"keys\": [{\"frame\": 1, \"color\": [2,0,0]}]}]"),
     SATF_ERR_ARGUMENT, "lights[0].keys[0].color[0]: 2 is out of range [0, 1]"},
    {WITH("\"lights\": [{\"direction\": [0,0,-1], \"keys\": [{\"frame\": 1, "
          "\"intensity\": -2}]}]"),
     SATF_ERR_ARGUMENT,
     "lights[0].keys[0].intensity: -2 is out of range [0, 1000000]"},
    {"{" MINIMAL_MC ", \"lights\": [{\"direction\": [0,0,-1], \"keys\": "
     "[{\"frame\": 1}]}]}",
     SATF_ERR_FORMAT,
     "lights[0].keys: keyframes need a top-level \"animation\" object"},
};
#define N_BAD (sizeof bad_cases / sizeof bad_cases[0])

static void test_malformed_cases(void **state) {
  (void)state;
  check_bad_cases(bad_cases, N_BAD, "anim.json");
}

static void test_too_many_keys(void **state) {
  (void)state;
  /* One over the per-object limit, rejected before any key is read. */
  int n = SATF_SCENE_MAX_KEYS + 1;
  size_t cap = (size_t)n * 24 + 512;
  char *json = malloc(cap);
  assert_non_null(json);
  size_t o = (size_t)snprintf(
      json, cap,
      "{\"animation\": {\"frames\": [0, %d]}, \"macro_clusters\": "
      "[{\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]], \"a\": 0.5, "
      "\"keys\": [",
      n);
  for (int i = 0; i < n; i++)
    o += (size_t)snprintf(json + o, cap - o, "%s{\"frame\": %d}", i ? "," : "",
                          i);
  snprintf(json + o, cap - o, "]}}]}");
  satf_scene *scene;
  satf_error err;
  assert_int_equal(
      satf_scene_parse(json, strlen(json), "many.json", &scene, &err),
      SATF_ERR_ARGUMENT);
  assert_string_equal(err.message, "many.json: macro_clusters[0].prototype."
                                   "keys: has 65537 entries, expected 1 to "
                                   "65536");
  free(json);
}

static void test_unknown_keys_warn(void **state) {
  (void)state;
  satf_scene *scene = parse_anim(
      "{\"animation\": {\"fsp\": 24, \"frames\": [1, 4]},"
      " \"macro_clusters\": [{\"prototype\": {\"trajectory\": "
      "[[0,0,0],[0,1,0]], \"a\": 0.5, \"keys\": [{\"frame\": 1, "
      "\"trajectroy\": [[0,0,0],[0,2,0]]}]}, \"instances\": [{\"keys\": "
      "[{\"frame\": 2, \"translat\": [1,0,0]}]}]}],"
      " \"camera\": {\"keys\": [{\"frame\": 3, \"zoom\": 2}]},"
      " \"lights\": [{\"direction\": [0,0,-1], \"keys\": [{\"frame\": 4, "
      "\"position\": [0,0,1]}]}]}");
  const char *expected[] = {
      "anim.json: animation.fsp: unknown key (ignored); did you mean "
      "\"fps\"?",
      "anim.json: macro_clusters[0].prototype.keys[0].trajectroy: unknown "
      "key (ignored); did you mean \"trajectory\"?",
      "anim.json: macro_clusters[0].instances[0].keys[0].translat: unknown "
      "key (ignored); did you mean \"translate\"?",
      "anim.json: camera.keys[0].zoom: unknown key (ignored)",
      "anim.json: lights[0].keys[0].position: unknown key (ignored)"};
  assert_int_equal(satf_scene_warning_count(scene), 5);
  for (int i = 0; i < 5; i++)
    assert_string_equal(satf_scene_warning(scene, i), expected[i]);
  /* The defaults: 24 fps; the misspelt keys changed nothing. */
  assert_near(satf_scene_fps(scene), 24.0, 0);
  satf_scene *snap = at(scene, 1.0);
  assert_true(satf_scene_prototype_equal(&snap->macro_clusters[0].prototype,
                                         &scene->macro_clusters[0].prototype));
  assert_true(satf_scene_instances_equal(&snap->macro_clusters[0],
                                         &scene->macro_clusters[0]));
  satf_scene_destroy(snap);
  satf_scene_destroy(scene);
}

/* ---- snapshots that cannot be made, static scenes ---- */

static void expect_frame_error(const char *json, double frame,
                               const char *expect) {
  satf_scene *scene = parse_anim(json), *snap = (satf_scene *)&snap;
  satf_error err;
  satf_status s = satf_scene_at_frame(scene, frame, &snap, &err);
  if (s == SATF_OK || !strstr(err.message, expect)) {
    fprintf(stderr, "frame %g: status %d, %s\n  expected: %s\n", frame, (int)s,
            s == SATF_OK ? "(ok)" : err.message, expect);
    fail();
  }
  assert_int_equal(s, SATF_ERR_ARGUMENT);
  assert_null(snap);
  satf_scene_destroy(scene);
}

static void test_snapshot_errors(void **state) {
  (void)state;
  /* Keys that are fine alone but meet in something unusable halfway. */
  expect_frame_error(
      "{" ANIM ", \"macro_clusters\": [{\"prototype\": {\"trajectory\": "
      "[[0,0,0],[0,1,0]], \"a\": 0.5, \"keys\": [{\"frame\": 1}, "
      "{\"frame\": 3, \"trajectory\": [[0,0,0],[0,-1,0]]}]}}]}",
      2.0,
      "anim.json at frame 2: macro_clusters[0].prototype.trajectory: all 2 "
      "control points coincide");
  expect_frame_error(
      INSTANCE("{}, {\"keys\": [{\"frame\": 1}, {\"frame\": 3, \"scale\": "
               "[-1, 1, 1]}]}"),
      2.0,
      "anim.json at frame 2: macro_clusters[0].instances[1]: the "
      "interpolated transform is singular");
  expect_frame_error(WITH("\"camera\": {\"position\": [0,0,10], \"target\": "
                          "[0,0,0], \"keys\": [{\"frame\": 1}, {\"frame\": "
                          "3, \"position\": [0,0,-10]}]}"),
                     2.0,
                     "anim.json at frame 2: camera.target: coincides with "
                     "the camera position");
  expect_frame_error(WITH("\"lights\": [{\"direction\": [0,0,-1], \"keys\": "
                          "[{\"frame\": 1}, {\"frame\": 3, \"direction\": "
                          "[0,0,1]}]}]"),
                     2.0,
                     "anim.json at frame 2: lights[0].direction: has zero "
                     "length");
  expect_frame_error(WITH("\"lights\": [{\"direction\": [0,0,-1]}]"), NAN,
                     "anim.json: frame nan is not a finite number");
  expect_frame_error(WITH("\"lights\": [{\"direction\": [0,0,-1]}]"), INFINITY,
                     "anim.json: frame inf is not a finite number");

  /* Arguments. */
  satf_error err;
  satf_scene *snap;
  assert_int_equal(satf_scene_at_frame(NULL, 1.0, &snap, &err),
                   SATF_ERR_ARGUMENT);
  assert_null(snap);
  assert_int_equal(satf_scene_at_frame(NULL, 1.0, NULL, NULL),
                   SATF_ERR_ARGUMENT);

  /* A static scene: not animated, no range, its snapshot a plain copy. */
  satf_scene *scene = parse_anim(
      "{\"description\": \"d\", \"database\": \"x.exr\", " MINIMAL_MC "}");
  assert_false(satf_scene_is_animated(scene));
  int first = 7, last = 7;
  assert_int_equal(satf_scene_frame_range(scene, &first, &last), 0);
  assert_int_equal(first, 0);
  assert_int_equal(last, 0);
  assert_near(satf_scene_fps(scene), 0.0, 0);
  assert_false(satf_scene_prototype_is_animated(scene, 0));
  assert_false(satf_scene_instance_is_animated(scene, 0, 0));
  snap = at(scene, 12.0);
  assert_true(satf_scene_prototype_equal(&snap->macro_clusters[0].prototype,
                                         &scene->macro_clusters[0].prototype));
  assert_true(satf_scene_camera_equal(&snap->camera, &scene->camera));
  assert_int_equal(snap->camera.automatic, 1);
  assert_string_equal(snap->description, "d");
  assert_string_equal(snap->database, "x.exr");
  assert_true(snap->macro_clusters[0].prototype.trajectory !=
              scene->macro_clusters[0].prototype.trajectory);
  satf_scene_destroy(snap);
  satf_scene_destroy(scene);
}

/* ---- what changed between snapshots ---- */

static void test_change_detection(void **state) {
  (void)state;
  satf_scene *scene = parse_anim(
      "{\"animation\": {\"frames\": [1, 10]},"
      " \"macro_clusters\": ["
      "  {\"name\": \"still\", \"prototype\": {\"trajectory\": "
      "[[0,0,0],[0,1,0]], \"a\": 0.5, \"density\": {\"type\": \"vdb\", "
      "\"file\": \"v.vdb\"}}, \"instances\": [{}, {\"translate\": [1,0,0], "
      "\"keys\": [{\"frame\": 1}, {\"frame\": 10, \"translate\": [2,0,0]}]}]},"
      "  {\"prototype\": {\"trajectory\": [[0,0,0],[0,1,0]], \"a\": 0.5,"
      "   \"keys\": [{\"frame\": 1}, {\"frame\": 10, \"trajectory\": "
      "[[0,0,0],[1,1,0]]}]}}]}");
  assert_false(satf_scene_prototype_is_animated(scene, 0));
  assert_true(satf_scene_prototype_is_animated(scene, 1));
  assert_false(satf_scene_prototype_is_animated(scene, 2));
  assert_false(satf_scene_prototype_is_animated(scene, -1));
  assert_false(satf_scene_instance_is_animated(scene, 0, 0));
  assert_true(satf_scene_instance_is_animated(scene, 0, 1));
  assert_false(satf_scene_instance_is_animated(scene, 1, 0));
  satf_scene *a = at(scene, 3.0), *b = at(scene, 4.0), *c = at(scene, 4.0);
  /* The still prototype is equal in both; the moving one is not. */
  assert_true(satf_scene_prototype_equal(&a->macro_clusters[0].prototype,
                                         &b->macro_clusters[0].prototype));
  assert_false(satf_scene_prototype_equal(&a->macro_clusters[1].prototype,
                                          &b->macro_clusters[1].prototype));
  assert_true(satf_scene_prototype_equal(&b->macro_clusters[1].prototype,
                                         &c->macro_clusters[1].prototype));
  assert_false(
      satf_scene_instances_equal(&a->macro_clusters[0], &b->macro_clusters[0]));
  assert_true(
      satf_scene_instances_equal(&a->macro_clusters[1], &b->macro_clusters[1]));
  assert_string_equal(a->macro_clusters[0].name, "still");
  assert_string_equal(a->macro_clusters[0].prototype.density.vdb_file, "v.vdb");
  /* Different geometry in a field the animation never touches. */
  c->macro_clusters[1].prototype.shell.layers++;
  assert_false(satf_scene_prototype_equal(&b->macro_clusters[1].prototype,
                                          &c->macro_clusters[1].prototype));
  c->macro_clusters[1].prototype.shell.layers--;
  c->macro_clusters[1].prototype.a.values[0] = 0.25f;
  assert_false(satf_scene_prototype_equal(&b->macro_clusters[1].prototype,
                                          &c->macro_clusters[1].prototype));
  c->camera.fov_y += 1.0f;
  assert_false(satf_scene_camera_equal(&b->camera, &c->camera));
  c->lights[0].intensity = 2.0f;
  assert_false(satf_scene_light_equal(&b->lights[0], &c->lights[0]));
  assert_true(satf_scene_light_equal(&a->lights[0], &b->lights[0]));
  satf_scene_destroy(a);
  satf_scene_destroy(b);
  satf_scene_destroy(c);
  satf_scene_destroy(scene);
}

/* ---- the Fig. 8 sample: SATF Table 1, last column ---- */

static void test_anim_8_sample(void **state) {
  (void)state;
  satf_scene *scene = NULL;
  satf_error err;
  satf_status s =
      satf_scene_load(SATF_SAMPLES_DIR "/anim_8.json", &scene, &err);
  if (s != SATF_OK)
    fprintf(stderr, "%s\n", err.message);
  assert_int_equal(s, SATF_OK);
  assert_int_equal(satf_scene_warning_count(scene), 0);
  assert_true(satf_scene_is_animated(scene));
  int first, last;
  satf_scene_frame_range(scene, &first, &last);
  assert_int_equal(first, 1);
  assert_int_equal(last, 48);
  assert_near(satf_scene_fps(scene), 24.0, 0);
  /* Table 1, Fig. 8: C# 40, L# 80, S# 21K, H# 42K. */
  assert_int_equal(satf_scene_cluster_count(scene), 40);
  assert_int_equal(satf_scene_layer_count(scene), 80);
  double hsv = (double)satf_scene_hsv_count(scene);
  double strands = (double)satf_scene_strand_count(scene);
  assert_true(fabs(hsv - 42000) <= 0.05 * 42000);
  assert_true(fabs(strands - 21000) <= 0.05 * 21000);
  assert_true(scene->n_macro_clusters < 40); /* a real macro level */
  char db[600];
  snprintf(db, sizeof db, "%s/../out/satf-default.hrirdb.exr",
           SATF_SAMPLES_DIR);
  assert_string_equal(scene->database, db);

  satf_scene *f1 = at(scene, 1), *f24 = at(scene, 24);
  assert_int_equal(satf_scene_cluster_count(f24), 40);
  assert_int_equal(satf_scene_hsv_count(f24), satf_scene_hsv_count(scene));
  for (int i = 0; i < scene->n_macro_clusters; i++) {
    const satf_scene_cluster *a = &f1->macro_clusters[i].prototype;
    const satf_scene_cluster *b = &f24->macro_clusters[i].prototype;
    assert_true(satf_scene_prototype_is_animated(scene, i));
    assert_false(satf_scene_prototype_equal(a, b));
    /* The roots stay on the scalp; the tips sway. */
    for (int k = 0; k < 3; k++)
      assert_true(a->trajectory[k] == b->trajectory[k]);
    int tip = 3 * (a->n_points - 1);
    double dx = a->trajectory[tip] - b->trajectory[tip],
           dz = a->trajectory[tip + 2] - b->trajectory[tip + 2];
    assert_true(sqrt(dx * dx + dz * dz) > 0.3);
    assert_true(satf_scene_instances_equal(&f1->macro_clusters[i],
                                           &f24->macro_clusters[i]));
  }
  /* The camera turns; frame 1 is its first key, the static position. */
  assert_true(satf_scene_camera_equal(&f1->camera, &scene->camera));
  assert_false(satf_scene_camera_equal(&f1->camera, &f24->camera));
  /* Every frame of the range makes a usable snapshot whose hair stays
   * outside the head (radius 10). */
  for (int f = first; f <= last; f++) {
    satf_scene *snap = at(scene, f);
    for (int i = 0; i < snap->n_macro_clusters; i++) {
      const satf_scene_cluster *c = &snap->macro_clusters[i].prototype;
      for (int p = 0; p < c->n_points; p++) {
        const float *q = c->trajectory + 3 * p;
        assert_true(sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) > 10.5);
      }
    }
    satf_scene_destroy(snap);
  }
  satf_scene_destroy(f1);
  satf_scene_destroy(f24);
  satf_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_keys_hit_exactly),
      cmocka_unit_test(test_continuous_between_keys),
      cmocka_unit_test(test_cubic_is_c1),
      cmocka_unit_test(test_static_keys_change_nothing),
      cmocka_unit_test(test_end_keys_hold),
      cmocka_unit_test(test_slerp_halves_rotations),
      cmocka_unit_test(test_malformed_cases),
      cmocka_unit_test(test_too_many_keys),
      cmocka_unit_test(test_unknown_keys_warn),
      cmocka_unit_test(test_snapshot_errors),
      cmocka_unit_test(test_change_detection),
      cmocka_unit_test(test_anim_8_sample),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
