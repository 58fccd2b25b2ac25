/* test_shell_mesh.c - shell parameters, HSVs and boundary sectors (SATF eq.
 * 3), layer meshes (SATF sec. 6.1) and the OpenMesh shim: creation,
 * normals, OBJ/PLY round trips, bad input. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "satf/geometry.h"
#include "satf/math.h"

#include "test_util.h"

#define HEAD_PLY "/work/shared/data/heads/woman_head.ply"

static void expect_message(const satf_error *err, const char *needle) {
  if (!strstr(err->message, needle)) {
    print_error("message '%s' lacks '%s'\n", err->message, needle);
    fail();
  }
}

/* A curved, twisting, tapering cluster like a lock of hair. */
static satf_cluster *make_lock(float x0) {
  const float traj[6 * 3] = {x0,        0.0f,  0.0f, x0 + 0.2f, -0.5f, 0.3f,
                             x0 + 0.1f, -1.2f, 0.8f, x0 - 0.3f, -1.8f, 1.0f,
                             x0 - 0.6f, -2.6f, 0.7f, x0 - 0.5f, -3.2f, 0.2f};
  const float a[3] = {0.25f, 0.2f, 0.06f}, b[3] = {0.12f, 0.1f, 0.05f};
  const float tw[3] = {0.0f, 1.2f, 2.0f};
  satf_cluster_desc d = {6, traj, 3, a, b, tw};
  satf_cluster *cl = NULL;
  satf_error err;
  assert_int_equal(satf_cluster_create(&d, &cl, &err), SATF_OK);
  return cl;
}

static void test_params_validation(void **state) {
  (void)state;
  satf_shell_params ok = {15, 33, 32, 0.3f};
  satf_error err;
  assert_int_equal(satf_shell_params_check(&ok, &err), SATF_OK);
  struct {
    satf_shell_params p;
    const char *key;
  } bad[] = {
      {{0, 33, 32, 0.3f}, "shell/layers"},
      {{257, 33, 32, 0.3f}, "shell/layers"},
      {{15, 0, 32, 0.3f}, "shell/st"},
      {{15, 4097, 32, 0.3f}, "shell/st"},
      {{15, 33, 2, 0.3f}, "shell/su"},
      {{15, 33, 4097, 0.3f}, "shell/su"},
      {{15, 33, 32, -0.01f}, "shell/core"},
      {{15, 33, 32, 0.96f}, "shell/core"},
      {{15, 33, 32, NAN}, "shell/core"},
      {{256, 4096, 4096, 0.3f}, "HSVs exceeds"},
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    assert_int_equal(satf_shell_params_check(&bad[i].p, &err),
                     SATF_ERR_ARGUMENT);
    assert_int_equal(err.status, SATF_ERR_ARGUMENT);
    expect_message(&err, bad[i].key);
    assert_int_equal(satf_shell_hsv_count(&bad[i].p), 0);
  }
  assert_int_equal(satf_shell_params_check(NULL, &err), SATF_ERR_ARGUMENT);
}

/* SATF Table 1, Fig. 6(a): 15 layers, st = 33, su = 32 -> ~16K HSVs. */
static void test_hsv_count_table1(void **state) {
  (void)state;
  satf_shell_params p = {15, 33, 32, 0.3f};
  assert_int_equal(satf_shell_hsv_count(&p), 15840);
  assert_int_equal(satf_shell_hsv_index(&p, 0, 0, 0), 0);
  assert_int_equal(satf_shell_hsv_index(&p, 32, 14, 31), 15839);
  assert_int_equal(satf_shell_hsv_index(&p, 1, 2, 3), (1 * 15 + 2) * 32 + 3);
}

static void test_layer_radii(void **state) {
  (void)state;
  satf_shell_params p = {3, 4, 8, 0.4f};
  assert_near(satf_shell_layer_v(&p, 0), 0.4, 1e-7);
  assert_near(satf_shell_layer_v(&p, 1), 0.6, 1e-7);
  assert_near(satf_shell_layer_v(&p, 2), 0.8, 1e-7);
  assert_near(satf_shell_layer_v(&p, 3), 1.0, 0.0);
}

/* On a straight circular cylinder along +z the sector corners are known in
 * closed form: radius v r at phase theta + u (for a circle, turning the
 * cross-section by theta and shifting the phase by theta agree). */
static void test_sector_on_cylinder(void **state) {
  (void)state;
  const float traj[2 * 3] = {0, 0, 0, 0, 0, 4};
  const float r[1] = {0.5f}, tw[1] = {0.3f};
  satf_cluster_desc d = {2, traj, 1, r, r, tw};
  satf_cluster *cl = NULL;
  assert_int_equal(satf_cluster_create(&d, &cl, NULL), SATF_OK);
  satf_shell_params p = {4, 8, 16, 0.2f};
  satf_shell_sector s[2];
  satf_error err;
  assert_int_equal(satf_shell_hsv_sectors(cl, &p, 3, 2, 5, s, &err), SATF_OK);
  for (int e = 0; e < 2; e++) {
    double t = (3 + e) / 8.0;
    assert_near(s[e].t, t, 1e-7);
    assert_near(s[e].origin[2], 4.0 * t, 1e-6);
    assert_near(s[e].normal[2], 1.0, 1e-6);
    assert_near(s[e].v_inner, 0.2 + 0.8 * 2 / 4, 1e-6);
    assert_near(s[e].v_outer, 0.2 + 0.8 * 3 / 4, 1e-6);
    assert_near(s[e].u_begin, 2 * SATF_PI * 5 / 16, 1e-6);
    assert_near(s[e].u_end, 2 * SATF_PI * 6 / 16, 1e-6);
    assert_near(s[e].a, 0.5, 1e-7);
    const float vs[4] = {s[e].v_inner, s[e].v_outer, s[e].v_outer,
                         s[e].v_inner};
    const float us[4] = {s[e].u_begin, s[e].u_begin, s[e].u_end, s[e].u_end};
    for (int c = 0; c < 4; c++) {
      float dlt[3];
      test_sub3(s[e].corners[c], s[e].origin, dlt);
      assert_near(test_dot3(dlt, s[e].normal), 0.0, 1e-6); /* in the plane */
      assert_near(test_len3(dlt), 0.5 * vs[c], 1e-6);
      /* measured from the twisted axis: phase u */
      assert_near(test_dot3(dlt, s[e].axis_x), 0.5 * vs[c] * cos(us[c]), 1e-6);
      assert_near(test_dot3(dlt, s[e].axis_y), 0.5 * vs[c] * sin(us[c]), 1e-6);
      /* and from n1: phase theta + u */
      assert_near(test_dot3(dlt, s[e].n1), 0.5 * vs[c] * cos(0.3 + us[c]),
                  1e-6);
      float q[3];
      satf_cluster_point(cl, s[e].t, vs[c], us[c], q);
      for (int k = 0; k < 3; k++)
        assert_near(s[e].corners[c][k], q[k], 1e-6);
    }
  }
  /* the second boundary of HSV i is the first of HSV i + 1 */
  satf_shell_sector next[2];
  assert_int_equal(satf_shell_hsv_sectors(cl, &p, 4, 2, 5, next, NULL),
                   SATF_OK);
  assert_memory_equal(next[0].corners, s[1].corners, sizeof s[1].corners);
  /* out-of-range indices */
  assert_int_equal(satf_shell_hsv_sectors(cl, &p, 8, 0, 0, s, &err),
                   SATF_ERR_ARGUMENT);
  expect_message(&err, "i = 8");
  assert_int_equal(satf_shell_sector_at(cl, &p, 8, 4, 0, s, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_shell_sector_at(cl, &p, 0, 0, 16, s, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_shell_sector_at(cl, &p, 8, 3, 15, s, &err), SATF_OK);
  satf_cluster_destroy(cl);
}

/* A flat cluster (A = 0.5, B = 0.1) along +z twisted half a turn: every
 * boundary sector's axes are the untwisted frame turned by theta(t) = pi t,
 * its corners lie at (A v cos u, B v sin u) on those axes (SATF eq. 1 with
 * theta turning the cross-section), and the layer mesh's vertices of ring i
 * are the same points, so shells and HSVs turn with the ribbon. */
static void test_sectors_turn_with_twist(void **state) {
  (void)state;
  const float traj[2 * 3] = {0, 0, 0, 0, 0, 4};
  const float a[2] = {0.5f, 0.5f}, b[2] = {0.1f, 0.1f};
  const float tw[2] = {0.0f, (float)SATF_PI};
  satf_cluster_desc d = {2, traj, 2, a, b, tw};
  satf_cluster *cl = NULL;
  assert_int_equal(satf_cluster_create(&d, &cl, NULL), SATF_OK);
  satf_shell_params p = {2, 4, 8, 0.2f};
  satf_mesh *mesh = NULL;
  assert_int_equal(satf_cluster_build_layer_mesh(cl, &p, 1, &mesh, NULL),
                   SATF_OK);
  const satf_mesh_vertex *mv = satf_mesh_vertices(mesh);
  for (int i = 0; i <= p.st; i++)
    for (int j = 0; j < p.su; j++) {
      satf_shell_sector s;
      assert_int_equal(satf_shell_sector_at(cl, &p, i, 1, j, &s, NULL),
                       SATF_OK);
      double th = SATF_PI * i / p.st, c = cos(th), n = sin(th);
      assert_near(s.theta, th, 1e-6);
      for (int k = 0; k < 3; k++) {
        assert_near(s.axis_x[k], c * s.n1[k] + n * s.n2[k], 1e-6);
        assert_near(s.axis_y[k], -n * s.n1[k] + c * s.n2[k], 1e-6);
      }
      float dlt[3];
      test_sub3(s.corners[1], s.origin, dlt); /* (v_outer, u_begin) */
      assert_near(test_dot3(dlt, s.axis_x), 0.5 * cos(s.u_begin), 1e-6);
      assert_near(test_dot3(dlt, s.axis_y), 0.1 * sin(s.u_begin), 1e-6);
      /* the outer layer's mesh vertex (i, j) is that corner */
      const float *q = mv[(size_t)i * (size_t)(p.su + 1) + (size_t)j].pos;
      for (int k = 0; k < 3; k++)
        assert_near(q[k], s.corners[1][k], 1e-6);
    }
  satf_mesh_destroy(mesh);
  satf_cluster_destroy(cl);
}

static void test_layer_mesh_structure(void **state) {
  (void)state;
  satf_cluster *cl = make_lock(0.0f);
  satf_shell_params p = {3, 33, 32, 0.3f};
  satf_mesh *grid = NULL;
  /* layer 0 from scratch, the others copying its connectivity */
  for (int k = 0; k < 3; k++) {
    satf_mesh *m = NULL;
    satf_error err;
    assert_int_equal(
        satf_cluster_build_layer_mesh_from(cl, &p, k, grid, &m, &err), SATF_OK);
    size_t nv = satf_mesh_vertex_count(m), nf = satf_mesh_triangle_count(m);
    assert_int_equal(nv, 34 * 33);
    assert_int_equal(nf, 2 * 33 * 32);
    float v = satf_shell_layer_v(&p, k + 1);
    assert_near(satf_mesh_layer_v(m), v, 0.0);
    const satf_mesh_vertex *vx = satf_mesh_vertices(m);
    const uint32_t *idx = satf_mesh_indices(m);
    for (int i = 0; i <= 33; i++)
      for (int j = 0; j <= 32; j++) {
        const satf_mesh_vertex *q = &vx[i * 33 + j];
        float t = i / 33.0f, u = (float)(2 * SATF_PI * (j % 32) / 32);
        float want[3], T[3], r[3], dir[3], an[3];
        satf_cluster_point(cl, t, v, u, want);
        for (int c = 0; c < 3; c++)
          assert_near(q->pos[c], want[c], 1e-6);
        assert_near(q->uv[0], j / 32.0, 1e-7);
        assert_near(q->uv[1], t, 1e-7);
        assert_near(test_len3(q->normal), 1.0, 1e-5);
        satf_cluster_trajectory(cl, t, T, NULL);
        test_sub3(q->pos, T, r);
        assert_true(test_dot3(q->normal, r) > 0.0); /* outward */
        /* the discrete normal follows the analytic surface normal */
        satf_cluster_surface_normal(cl, t, v, u, an);
        assert_true(test_dot3(q->normal, an) > 0.97);
        satf_cluster_hair_tangent(cl, t, v, u, dir);
        assert_near(test_dot3(q->tangent, dir), 1.0, 1e-5);
      }
    /* the seam shares one normal on both copies */
    for (int i = 0; i <= 33; i++)
      for (int c = 0; c < 3; c++)
        assert_near(vx[i * 33].normal[c], vx[i * 33 + 32].normal[c], 1e-6);
    /* faces: valid, not degenerate, front side outward */
    for (size_t f = 0; f < nf; f++) {
      const float *a = vx[idx[3 * f]].pos, *b = vx[idx[3 * f + 1]].pos,
                  *c = vx[idx[3 * f + 2]].pos;
      for (int e = 0; e < 3; e++)
        assert_true(idx[3 * f + e] < nv);
      float e1[3], e2[3], fn[3], cen[3], T[3], r[3];
      test_sub3(b, a, e1);
      test_sub3(c, a, e2);
      satf_cross3f(e1, e2, fn);
      assert_true(0.5 * test_len3(fn) > 1e-8);
      for (int q = 0; q < 3; q++)
        cen[q] = (a[q] + b[q] + c[q]) / 3.0f;
      float tc = (vx[idx[3 * f]].uv[1] + vx[idx[3 * f + 1]].uv[1] +
                  vx[idx[3 * f + 2]].uv[1]) /
                 3.0f;
      satf_cluster_trajectory(cl, tc, T, NULL);
      test_sub3(cen, T, r);
      assert_true(test_dot3(fn, r) > 0.0);
    }
    if (grid)
      satf_mesh_destroy(m);
    else
      grid = m;
  }
  satf_mesh *m = NULL;
  satf_error err;
  assert_int_equal(satf_cluster_build_layer_mesh(cl, &p, 3, &m, &err),
                   SATF_ERR_ARGUMENT);
  assert_null(m);
  expect_message(&err, "layer 3");
  /* st and su swapped: same counts, other triangles */
  satf_shell_params swapped = {3, 32, 33, 0.3f};
  assert_int_equal(
      satf_cluster_build_layer_mesh_from(cl, &swapped, 0, grid, &m, &err),
      SATF_ERR_ARGUMENT);
  assert_null(m);
  expect_message(&err, "differ");
  satf_shell_params other = {3, 10, 32, 0.3f};
  assert_int_equal(
      satf_cluster_build_layer_mesh_from(cl, &other, 0, grid, &m, &err),
      SATF_ERR_ARGUMENT);
  expect_message(&err, "topology mesh has");
  satf_mesh_destroy(grid);
  satf_cluster_destroy(cl);
}

/* One triangle counter-clockwise in the xy plane: every vertex normal is
 * +z; reversed, -z. */
static void test_mesh_normals_by_hand(void **state) {
  (void)state;
  const float pos[4 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const uint32_t ccw[6] = {0, 1, 2, 1, 3, 2}, cw[3] = {0, 2, 1};
  satf_mesh_desc d = {4, pos, NULL, NULL, NULL, 2, ccw, -1.0f};
  satf_mesh *m = NULL;
  assert_int_equal(satf_mesh_create(&d, &m, NULL), SATF_OK);
  const satf_mesh_vertex *v = satf_mesh_vertices(m);
  for (int i = 0; i < 4; i++) {
    assert_near(v[i].normal[0], 0.0, 1e-7);
    assert_near(v[i].normal[1], 0.0, 1e-7);
    assert_near(v[i].normal[2], 1.0, 1e-7);
    assert_near(v[i].tangent[0], 0.0, 0.0);
  }
  assert_int_equal(satf_mesh_update_normals(m, NULL), SATF_OK);
  assert_near(satf_mesh_vertices(m)[3].normal[2], 1.0, 1e-7);
  float lo[3], hi[3];
  satf_mesh_bounds(m, lo, hi);
  assert_near(lo[0], 0.0, 0.0);
  assert_near(hi[1], 1.0, 0.0);
  satf_mesh_destroy(m);
  d.n_triangles = 1;
  d.indices = cw;
  assert_int_equal(satf_mesh_create(&d, &m, NULL), SATF_OK);
  assert_near(satf_mesh_vertices(m)[0].normal[2], -1.0, 1e-7);
  assert_near(satf_mesh_vertices(m)[3].normal[2], 0.0, 0.0); /* isolated */
  satf_mesh_destroy(m);
}

static void test_mesh_create_rejects(void **state) {
  (void)state;
  float pos[4 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  uint32_t idx[6] = {0, 1, 2, 0, 1, 3};
  satf_mesh_desc d = {4, pos, NULL, NULL, NULL, 1, idx, -1.0f};
  satf_mesh *m = (satf_mesh *)(uintptr_t)1;
  satf_error err;
  idx[2] = 4;
  assert_int_equal(satf_mesh_create(&d, &m, &err), SATF_ERR_ARGUMENT);
  assert_null(m);
  expect_message(&err, "vertex 4 of 4");
  idx[2] = 1;
  assert_int_equal(satf_mesh_create(&d, &m, &err), SATF_ERR_ARGUMENT);
  expect_message(&err, "repeats a vertex");
  idx[2] = 2;
  pos[4] = NAN;
  assert_int_equal(satf_mesh_create(&d, &m, &err), SATF_ERR_ARGUMENT);
  expect_message(&err, "not finite");
  pos[4] = 0;
  /* the edge 0 -> 1 used twice in the same direction: non-manifold */
  d.n_triangles = 2;
  assert_int_equal(satf_mesh_create(&d, &m, &err), SATF_ERR_ARGUMENT);
  expect_message(&err, "triangle 1");
  assert_null(m);
  assert_int_equal(satf_mesh_create(NULL, &m, &err), SATF_ERR_ARGUMENT);
}

/* Scratch files go to SATF_TEST_TMP (set by ctest), never into the
 * source tree when the binary is run by hand. */
static void tmp_path(char *out, size_t size, const char *name) {
  const char *dir = getenv("SATF_TEST_TMP");
  snprintf(out, size, "%s/satf-geometry-%s", dir && *dir ? dir : "/tmp", name);
}

static void round_trip(const char *name) {
  satf_cluster *cl = make_lock(1.0f);
  satf_shell_params p = {2, 12, 10, 0.5f};
  satf_mesh *m = NULL, *r = NULL;
  satf_error err;
  assert_int_equal(satf_cluster_build_layer_mesh(cl, &p, 1, &m, &err), SATF_OK);
  char path[1024];
  tmp_path(path, sizeof path, name);
  remove(path);
  if (satf_mesh_write(m, path, &err)) {
    print_error("write: %s\n", err.message);
    fail();
  }
  if (satf_mesh_read(path, &r, &err)) {
    print_error("read: %s\n", err.message);
    fail();
  }
  assert_int_equal(satf_mesh_vertex_count(r), satf_mesh_vertex_count(m));
  assert_int_equal(satf_mesh_triangle_count(r), satf_mesh_triangle_count(m));
  assert_near(satf_mesh_layer_v(r), -1.0, 0.0);
  const satf_mesh_vertex *a = satf_mesh_vertices(m), *b = satf_mesh_vertices(r);
  for (size_t i = 0; i < satf_mesh_vertex_count(m); i++) {
    for (int c = 0; c < 3; c++) {
      assert_near(b[i].pos[c], a[i].pos[c], 1e-6);
      assert_near(b[i].normal[c], a[i].normal[c], 1e-6);
    }
    for (int c = 0; c < 2; c++)
      assert_near(b[i].uv[c], a[i].uv[c], 1e-6);
  }
  /* same triangles, possibly starting at another corner */
  const uint32_t *ia = satf_mesh_indices(m), *ib = satf_mesh_indices(r);
  for (size_t f = 0; f < satf_mesh_triangle_count(m); f++) {
    int found = 0;
    for (int s = 0; s < 3; s++)
      found |= ib[3 * f] == ia[3 * f + s] &&
               ib[3 * f + 1] == ia[3 * f + (s + 1) % 3] &&
               ib[3 * f + 2] == ia[3 * f + (s + 2) % 3];
    assert_true(found);
  }
  satf_mesh_destroy(r);
  satf_mesh_destroy(m);
  satf_cluster_destroy(cl);
}

static void test_round_trip_obj(void **state) {
  (void)state;
  round_trip("layer.obj");
}

static void test_round_trip_ply(void **state) {
  (void)state;
  round_trip("layer.PLY");
}

/* Normals given at creation are kept (not recomputed) and travel through
 * both file formats, as do the texture coordinates. */
static void test_round_trip_given_normals(void **state) {
  (void)state;
  const float pos[4 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0.5f};
  const float nrm[4 * 3] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0.6f, 0, 0.8f};
  const float uv[4 * 2] = {0, 0, 1, 0, 0, 1, 0.25f, 0.75f};
  const uint32_t idx[6] = {0, 1, 2, 1, 3, 2};
  satf_mesh_desc d = {4, pos, nrm, NULL, uv, 2, idx, 0.5f};
  satf_mesh *m = NULL;
  assert_int_equal(satf_mesh_create(&d, &m, NULL), SATF_OK);
  assert_memory_equal(satf_mesh_vertices(m)[3].normal, nrm + 9,
                      3 * sizeof(float));
  const char *names[2] = {"given.obj", "given.ply"};
  for (int f = 0; f < 2; f++) {
    char path[1024];
    satf_error err;
    satf_mesh *r = NULL;
    tmp_path(path, sizeof path, names[f]);
    assert_int_equal(satf_mesh_write(m, path, &err), SATF_OK);
    assert_int_equal(satf_mesh_read(path, &r, &err), SATF_OK);
    assert_int_equal(satf_mesh_vertex_count(r), 4);
    assert_int_equal(satf_mesh_triangle_count(r), 2);
    const satf_mesh_vertex *v = satf_mesh_vertices(r);
    for (int i = 0; i < 4; i++) {
      for (int c = 0; c < 3; c++) {
        assert_near(v[i].pos[c], pos[3 * i + c], 1e-7);
        assert_near(v[i].normal[c], nrm[3 * i + c], 1e-7);
      }
      assert_near(v[i].uv[0], uv[2 * i], 1e-7);
      assert_near(v[i].uv[1], uv[2 * i + 1], 1e-7);
    }
    satf_mesh_destroy(r);
  }
  satf_mesh_destroy(m);
}

static void test_io_errors(void **state) {
  (void)state;
  const float pos[3 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint32_t idx[3] = {0, 1, 2};
  satf_mesh_desc d = {3, pos, NULL, NULL, NULL, 1, idx, -1.0f};
  satf_mesh *m = NULL, *r = (satf_mesh *)(uintptr_t)1;
  satf_error err;
  assert_int_equal(satf_mesh_create(&d, &m, NULL), SATF_OK);
  char path[1024];
  tmp_path(path, sizeof path, "tri.stl");
  assert_int_equal(satf_mesh_write(m, path, &err), SATF_ERR_ARGUMENT);
  expect_message(&err, ".stl");
  assert_int_equal(satf_mesh_write(m, "/nonexistent-dir/x.obj", &err),
                   SATF_ERR_IO);
  tmp_path(path, sizeof path, "missing.ply");
  remove(path);
  assert_int_equal(satf_mesh_read(path, &r, &err), SATF_ERR_IO);
  assert_null(r);
  expect_message(&err, "missing.ply");
  tmp_path(path, sizeof path, "garbage.ply");
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  fputs("this is not a ply file\n\x01\x02\x03", f);
  fclose(f);
  assert_int_equal(satf_mesh_read(path, &r, &err), SATF_ERR_FORMAT);
  expect_message(&err, "garbage.ply");
  satf_mesh_destroy(m);
}

/* The opaque head used by the demo scenes, when this machine has it. */
static void test_read_head_ply(void **state) {
  (void)state;
  FILE *f = fopen(HEAD_PLY, "rb");
  if (!f) {
    print_message("skipping: %s not present\n", HEAD_PLY);
    skip();
  }
  fclose(f);
  satf_mesh *m = NULL;
  satf_error err;
  if (satf_mesh_read(HEAD_PLY, &m, &err)) {
    print_error("%s\n", err.message);
    fail();
  }
  assert_int_equal(satf_mesh_vertex_count(m), 43662);
  size_t nf = satf_mesh_triangle_count(m);
  print_message("head: %zu vertices, %zu triangles\n",
                satf_mesh_vertex_count(m), nf);
  /* the header declares 78520 faces; OpenMesh drops non-manifold ones */
  assert_true(nf <= 78520 && nf >= 78000);
  const satf_mesh_vertex *v = satf_mesh_vertices(m);
  for (size_t i = 0; i < satf_mesh_vertex_count(m); i++) {
    double n = test_len3(v[i].normal);
    assert_true(fabs(n - 1.0) < 1e-4 || n == 0.0); /* 0: isolated vertex */
  }
  satf_mesh_destroy(m);
}

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Fig. 7(a) scale: 17 clusters x 3 layers of 33 x 32 cells, built from
 * scratch and sharing one grid's connectivity. Reports the times; the
 * assertions are on the totals and on both ways agreeing. */
static void test_build_scene_layers(void **state) {
  (void)state;
  satf_cluster *cl[17];
  for (int c = 0; c < 17; c++)
    cl[c] = make_lock(0.3f * c);
  satf_shell_params p = {3, 33, 32, 0.3f};
  satf_mesh *grid = NULL;
  double ms[2];
  for (int pass = 0; pass < 2; pass++) {
    size_t nv = 0, nf = 0;
    double t0 = now_s();
    for (int c = 0; c < 17; c++)
      for (int k = 0; k < 3; k++) {
        satf_mesh *m = NULL;
        assert_int_equal(
            satf_cluster_build_layer_mesh_from(cl[c], &p, k, grid, &m, NULL),
            SATF_OK);
        nv += satf_mesh_vertex_count(m);
        nf += satf_mesh_triangle_count(m);
        if (pass == 0 && c == 16 && k == 2)
          grid = m; /* the last scratch mesh is the next pass's grid */
        else
          satf_mesh_destroy(m);
      }
    ms[pass] = (now_s() - t0) * 1e3;
    assert_int_equal(nv, 51 * 34 * 33);
    assert_int_equal(nf, 51 * 2 * 33 * 32);
  }
  print_message("17 clusters x 3 layers (33x32, 57222 vertices, 107712 "
                "triangles): %.2f ms from scratch, %.2f ms sharing a grid\n",
                ms[0], ms[1]);
  /* a mesh built on the shared grid equals the one built from scratch */
  satf_mesh *a = NULL, *b = NULL;
  assert_int_equal(satf_cluster_build_layer_mesh(cl[3], &p, 1, &a, NULL),
                   SATF_OK);
  assert_int_equal(
      satf_cluster_build_layer_mesh_from(cl[3], &p, 1, grid, &b, NULL),
      SATF_OK);
  assert_memory_equal(satf_mesh_vertices(a), satf_mesh_vertices(b),
                      satf_mesh_vertex_count(a) * sizeof(satf_mesh_vertex));
  assert_memory_equal(satf_mesh_indices(a), satf_mesh_indices(b),
                      3 * satf_mesh_triangle_count(a) * sizeof(uint32_t));
  satf_mesh_destroy(a);
  satf_mesh_destroy(b);
  satf_mesh_destroy(grid);
  for (int c = 0; c < 17; c++)
    satf_cluster_destroy(cl[c]);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_params_validation),
      cmocka_unit_test(test_hsv_count_table1),
      cmocka_unit_test(test_layer_radii),
      cmocka_unit_test(test_sector_on_cylinder),
      cmocka_unit_test(test_sectors_turn_with_twist),
      cmocka_unit_test(test_layer_mesh_structure),
      cmocka_unit_test(test_mesh_normals_by_hand),
      cmocka_unit_test(test_mesh_create_rejects),
      cmocka_unit_test(test_round_trip_obj),
      cmocka_unit_test(test_round_trip_ply),
      cmocka_unit_test(test_round_trip_given_normals),
      cmocka_unit_test(test_io_errors),
      cmocka_unit_test(test_read_head_ply),
      cmocka_unit_test(test_build_scene_layers),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
