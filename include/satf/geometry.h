/* geometry.h - cluster geometry (online/geometry/): clamped B-splines
 * (SATF eq. 2), generalized cylinders with their rotation-minimising
 * frames, shell layers and HSVs (eq. 1-3), and triangle meshes through the
 * OpenMesh shim (layer meshes, head meshes). */
#ifndef SATF_GEOMETRY_H
#define SATF_GEOMETRY_H

#include <stddef.h>
#include <stdint.h>

#include "satf/satf.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- B-splines ----
 * uniform clamped (open-uniform) B-splines on t in [0,1], the
 * curve family of SATF eq. 2 (trajectory T(t) in 3-D, radii A(t), B(t) and
 * twist theta(t) in 1-D).
 *
 * The knot vector is clamped, so the curve starts at the first and ends at
 * the last control point; interior knots are evenly spaced. The degree is
 * cubic when there are at least 4 control points. With fewer, a cubic is not
 * defined, so the degree drops to n - 1: 3 points give a quadratic Bezier
 * curve, 2 a straight segment, 1 a constant. Evaluation is in double
 * precision; control points are the caller's floats, read-only. */

/* The degree used for n control points: min(3, n - 1), and 0 for n < 1. */
int satf_bspline_degree(int n);

/* Evaluates the spline with n control points of dim coordinates each
 * (ctrl[i * dim + c]) at t, clamped to [0,1]. value, d1 (dC/dt) and d2
 * (d2C/dt2) each receive dim doubles; any of them may be NULL. dim must be
 * in 1..4 and n >= 1 (callers validate). */
void satf_bspline_eval(const float *ctrl, int n, int dim, double t,
                       double *value, double *d1, double *d2);

/* ---- Clusters ----
 * the geometry of one hair cluster (SATF paper sec. 3.2): a
 * generalized cylinder swept by an ellipse along a 3-D B-spline, its layered
 * volumetric shells and the Hair Shell Volumes (HSVs) they divide into.
 *
 * Parameters. t in [0,1] runs along the trajectory T(t) (the B-spline
 * parameter; it is close to the relative arc length when the control points
 * are evenly spaced), v in [0,1] from the trajectory to the cluster's
 * envelope, u in [0, 2 pi) around it. The hair runs along t.
 *
 * Frames. The ellipse lies in the normal plane of T. Its axes are measured
 * from a rotation-minimising frame (tangent, n1, n2), n2 = tangent x n1,
 * computed by the double reflection method (Wang, Juettler, Zheng, Liu,
 * "Computation of rotation minimizing frames", ACM TOG 27(1), 2008), so the
 * frame neither flips on helices nor spins on straight stretches.
 *
 * Twist. SATF eq. 1 reads E(t) = (A cos(theta + u), B sin(theta + u)) and
 * calls theta(t) "the self-twisting phase of the ellipse E(t)". Read
 * literally, theta only moves where phase u starts on an ellipse that keeps
 * its axes on (n1, n2), so a flat cluster could never turn (paper 001's
 * Fig. 6(c), a ribbon twisted one full turn, would stay flat). satf reads
 * theta as the angle the cross-section is turned by: the ellipse's axes are
 * the rotation-minimising normals rotated by theta(t),
 *   e1 = cos theta n1 + sin theta n2,  e2 = -sin theta n1 + cos theta n2,
 * and the point at (t, v, u) is T + v (A cos u e1 + B sin u e2). Strands at
 * fixed (v, u) turn with the ellipse. For A = B the two readings are the
 * same surface with the same (v, u) coordinates.
 *
 * A satf_cluster is immutable after satf_cluster_create: every query below
 * may run on many threads at once on one handle. */

/* The modelling parameters H = Modeling(T(t), A(t), B(t), theta(t)) of
 * SATF eq. 2, as B-spline control polygons. The arrays are copied. */
typedef struct satf_cluster_desc {
  int n_ctrl;         /* trajectory control points, >= 2 */
  const float *traj;  /* n_ctrl * 3 floats (x, y, z) */
  int n_radius;       /* control points of a, b and twist, >= 1 */
  const float *a;     /* semi-axis along e1 (n1 turned by theta), > 0 */
  const float *b;     /* semi-axis along e2 (n2 turned by theta), > 0 */
  const float *twist; /* theta: the angle the cross-section is turned by,
                         radians, counter-clockwise from n1 towards n2 */
} satf_cluster_desc;

typedef struct satf_cluster satf_cluster;

/* Validates desc (counts, finite values, positive radii, a trajectory of
 * non-zero length) and builds the cluster with its frame table. */
satf_status satf_cluster_create(const satf_cluster_desc *desc,
                                satf_cluster **out, satf_error *err);
void satf_cluster_destroy(satf_cluster *cluster);

/* Arc length of the trajectory T. */
float satf_cluster_length(const satf_cluster *cluster);

/* T(t) and, if d1 is non-NULL, dT/dt. */
void satf_cluster_trajectory(const satf_cluster *cluster, float t, float pos[3],
                             float d1[3]);

/* The rotation-minimising frame at t: unit tangent of T and the two unit
 * normals spanning the normal plane (right-handed, orthonormal). */
void satf_cluster_frame(const satf_cluster *cluster, float t, float tangent[3],
                        float n1[3], float n2[3]);

/* Everything about the cross-section at one t, so per-vertex work along a
 * ring evaluates the splines and the frame once. n1 and n2 are the
 * ellipse's axes, already turned by theta (e1, e2 above), so every consumer
 * works with the phase u alone; rmf_n1, rmf_n2 are the untwisted
 * rotation-minimising normals. */
typedef struct satf_cluster_section {
  float t;
  float center[3];  /* T(t) */
  float dcenter[3]; /* dT/dt */
  float tangent[3];
  float n1[3], n2[3]; /* the ellipse's axes: (rmf_n1, rmf_n2) turned by theta */
  /* d n1/dt, d n2/dt: the frame's turn along T plus the twist's,
   * d n1/dt = cos theta rmf_n1' + sin theta rmf_n2' + theta' n2 and
   * d n2/dt = -sin theta rmf_n1' + cos theta rmf_n2' - theta' n1 */
  float dn1[3], dn2[3];
  float rmf_n1[3], rmf_n2[3]; /* the rotation-minimising normals */
  float a, b, theta;          /* A(t), B(t), theta(t) */
  float da, db, dtheta;       /* their derivatives in t */
} satf_cluster_section;

void satf_cluster_section_at(const satf_cluster *cluster, float t,
                             satf_cluster_section *section);

/* SATF eq. 1 with theta turning the cross-section (see Twist above):
 * T(t) + v (A cos u n1 + B sin u n2), n1, n2 the section's turned axes. */
void satf_cluster_section_point(const satf_cluster_section *section, float v,
                                float u, float p[3]);
/* dP/dt normalised: the direction the hair runs at (t, v, u). */
void satf_cluster_section_hair_tangent(const satf_cluster_section *section,
                                       float v, float u, float dir[3]);
/* Unit normal of the surface v = const at (t, u), pointing away from the
 * trajectory. At v <= 0 the surface collapses onto T; the normal returned
 * there is the limit direction as v -> 0+. */
void satf_cluster_section_surface_normal(const satf_cluster_section *section,
                                         float v, float u, float n[3]);

/* One-shot forms of the three functions above. */
void satf_cluster_point(const satf_cluster *cluster, float t, float v, float u,
                        float p[3]);
void satf_cluster_hair_tangent(const satf_cluster *cluster, float t, float v,
                               float u, float dir[3]);
void satf_cluster_surface_normal(const satf_cluster *cluster, float t, float v,
                                 float u, float n[3]);

/* ---- Shells and Hair Shell Volumes (SATF sec. 3.2, eq. 3) ----
 *
 * v in [0, core] is the transparent interior core. The shell v in [core, 1]
 * is split into `layers` layers; layer k (0 = innermost) spans
 * [v_k, v_{k+1}] with v_j = core + (1 - core) j / layers, and its mesh is
 * its outer surface v_{k+1} (SATF sec. 6.1). HSV (i, k, j) spans
 * t in [i/st, (i+1)/st], layer k and u in [2 pi j/su, 2 pi (j+1)/su]; its
 * two boundary generalized sectors lie in the normal planes at t = i/st and
 * t = (i+1)/st. */
typedef struct satf_shell_params {
  int layers; /* 1..256 */
  int st;     /* HSVs along t, 1..4096 */
  int su;     /* HSVs around u, 3..4096 */
  float core; /* v radius of the interior core, in [0, 0.95] */
} satf_shell_params;

satf_status satf_shell_params_check(const satf_shell_params *params,
                                    satf_error *err);
/* st * layers * su, or 0 when params are invalid. */
size_t satf_shell_hsv_count(const satf_shell_params *params);
/* Linear index of HSV (i, k, j): (i * layers + k) * su + j. */
size_t satf_shell_hsv_index(const satf_shell_params *params, int i, int k,
                            int j);
/* v_j, the boundary between layers j - 1 and j (j in 0..layers). */
float satf_shell_layer_v(const satf_shell_params *params, int j);

/* A generalized sector: the cut of layer k, phase span j, through the normal
 * plane at t = i / st (i in 0..st). */
typedef struct satf_shell_sector {
  float t;
  int layer, phase;
  float v_inner, v_outer; /* v_k, v_{k+1} */
  float u_begin, u_end;   /* 2 pi j / su, 2 pi (j+1) / su */
  float a, b;             /* ellipse semi-axes at t */
  /* (v_inner, u_begin), (v_outer, u_begin), (v_outer, u_end),
   * (v_inner, u_end) */
  float corners[4][3];
  /* The plane: origin T(t), normal the tangent of T, (n1, n2) the
   * rotation-minimising normal-plane frame and theta(t) the twist.
   * (axis_x, axis_y) is (n1, n2) rotated by theta: the ellipse's axes, so
   * the point at (v, u) is origin + v (A cos u axis_x + B sin u axis_y)
   * (SATF eq. 1, theta turning the cross-section; see Twist above). */
  float origin[3];
  float normal[3];
  float n1[3], n2[3];
  float theta;
  float axis_x[3], axis_y[3];
} satf_shell_sector;

/* The boundary sector at t = i / st of layer k, phase span j. */
satf_status satf_shell_sector_at(const satf_cluster *cluster,
                                 const satf_shell_params *params, int i, int k,
                                 int j, satf_shell_sector *out,
                                 satf_error *err);
/* Both boundary sectors of HSV (i, k, j), i in 0..st-1. */
satf_status satf_shell_hsv_sectors(const satf_cluster *cluster,
                                   const satf_shell_params *params, int i,
                                   int k, int j, satf_shell_sector out[2],
                                   satf_error *err);

/* ---- Layer meshes (SATF sec. 6.1) ---- */
typedef struct satf_mesh satf_mesh; /* below */

/* The mesh of layer k: its outer surface v_{k+1} as a grid of (st + 1) x
 * (su + 1) vertices (the u seam duplicated so texture coordinates run over
 * [0,1]), two triangles per cell, outward normals, the hair direction as
 * tangent, uv = (u / 2 pi, t) and layer_v = v_{k+1}. */
satf_status satf_cluster_build_layer_mesh(const satf_cluster *cluster,
                                          const satf_shell_params *params,
                                          int k, satf_mesh **out,
                                          satf_error *err);
/* The same, copying the triangle connectivity of `grid`, any layer mesh
 * built earlier with the same st and su (any cluster, any layer; checked),
 * instead of rebuilding it: the way to build many layers quickly. grid may
 * be NULL. */
satf_status satf_cluster_build_layer_mesh_from(const satf_cluster *cluster,
                                               const satf_shell_params *params,
                                               int k, const satf_mesh *grid,
                                               satf_mesh **out,
                                               satf_error *err);

/* ---- Meshes ----
 * triangle meshes for rasterisation: the cluster layer meshes
 * (SATF sec. 6.1) and opaque meshes such as heads. A C front end to an
 * OpenMesh TriMesh (online/mesh_openmesh.cpp); the data is also kept as
 * plain arrays ready for a GL upload.
 *
 * Per vertex: position, unit normal, tangent (the hair direction on layer
 * meshes, zero on meshes read from files) and texture coordinates. Files
 * (OBJ, PLY) carry positions, normals and texture coordinates, not
 * tangents or layer_v. */

typedef struct satf_mesh satf_mesh;

/* Interleaved vertex, 44 bytes, in the order of the GL attributes. */
typedef struct satf_mesh_vertex {
  float pos[3];
  float normal[3];
  float tangent[3];
  float uv[2];
} satf_mesh_vertex;

typedef struct satf_mesh_desc {
  size_t n_vertices;
  const float *positions; /* 3 per vertex, required */
  const float *normals;   /* 3 per vertex; NULL: computed from the faces */
  const float *tangents;  /* 3 per vertex; NULL: zero */
  const float *uvs;       /* 2 per vertex; NULL: zero */
  size_t n_triangles;
  const uint32_t *indices; /* 3 per triangle, counter-clockwise seen from
                              the side the normal points to */
  float layer_v;           /* the shell radius v of a layer mesh, or -1 */
} satf_mesh_desc;

/* Copies desc into a new mesh. Rejects out-of-range indices, non-finite
 * positions, and triangles OpenMesh cannot add (repeated vertices or
 * non-manifold edges). */
satf_status satf_mesh_create(const satf_mesh_desc *desc, satf_mesh **out,
                             satf_error *err);
/* As satf_mesh_create, for a desc whose triangles are exactly those of
 * `topology` (checked): the OpenMesh connectivity is copied instead of
 * rebuilt triangle by triangle, several times faster. Meant for the layer
 * meshes, which all share one grid. */
satf_status satf_mesh_create_with_topology(const satf_mesh *topology,
                                           const satf_mesh_desc *desc,
                                           satf_mesh **out, satf_error *err);
void satf_mesh_destroy(satf_mesh *mesh);

/* Recomputes vertex normals with OpenMesh (each the normalised sum of its
 * faces' normals). Vertices at exactly the same position, such as the
 * duplicated u seam of a layer mesh, then share their averaged normal so
 * seams do not show in the shading. */
satf_status satf_mesh_update_normals(satf_mesh *mesh, satf_error *err);

size_t satf_mesh_vertex_count(const satf_mesh *mesh);
size_t satf_mesh_triangle_count(const satf_mesh *mesh);
/* satf_mesh_vertex_count entries, valid until the mesh changes. */
const satf_mesh_vertex *satf_mesh_vertices(const satf_mesh *mesh);
/* 3 * satf_mesh_triangle_count entries. */
const uint32_t *satf_mesh_indices(const satf_mesh *mesh);
/* The layer's v (see satf_mesh_desc), -1 for meshes read from files. */
float satf_mesh_layer_v(const satf_mesh *mesh);
/* Axis-aligned bounds of the positions (zeros for an empty mesh). */
void satf_mesh_bounds(const satf_mesh *mesh, float lo[3], float hi[3]);

/* Writes an OBJ or a binary PLY chosen by the extension of path (.obj,
 * .ply, any case), with normals and texture coordinates, through a
 * temporary file renamed into place. */
satf_status satf_mesh_write(const satf_mesh *mesh, const char *path,
                            satf_error *err);
/* Reads an OBJ or PLY (ASCII or binary); polygons are triangulated. Normals
 * come from the file when present, else from satf_mesh_update_normals. */
satf_status satf_mesh_read(const char *path, satf_mesh **out, satf_error *err);

#ifdef __cplusplus
}
#endif
#endif
