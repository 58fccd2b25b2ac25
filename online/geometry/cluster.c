/* cluster.c - the generalized cylinder of SATF sec. 3.2 (eq. 1-2): spline
 * evaluation, the rotation-minimising frame table and points, normals and
 * hair directions on the swept ellipse. */
#include "satf/geometry.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "satf/math.h"

/* Samples of the frame table (1024 intervals). Between samples the frame
 * is interpolated and re-orthogonalised against the exact tangent; this
 * density keeps the angular step on a tight helix far below the flip
 * threshold. The same samples give the arc length by Simpson's rule, so
 * the interval count must be even. */
#define FRAME_SAMPLES 1025
/* Control polygons larger than this are certainly a corrupt input. */
#define MAX_CONTROL_POINTS (1 << 20)

struct satf_cluster {
  int n_ctrl, n_radius;
  float *traj;  /* n_ctrl * 3 */
  float *a;     /* n_radius */
  float *b;     /* n_radius */
  float *twist; /* n_radius */
  double length;
  double pos[FRAME_SAMPLES][3];     /* T at sample i */
  double tangent[FRAME_SAMPLES][3]; /* unit tangent of T at sample i */
  double n1[FRAME_SAMPLES][3];      /* rotation-minimising normal */
};

/* ---- small vector helpers (the common ones are in satf/math.h) ---- */

static void to_float3(const double in[3], float out[3]) {
  out[0] = (float)in[0];
  out[1] = (float)in[1];
  out[2] = (float)in[2];
}

static void to_double3(const float in[3], double out[3]) {
  out[0] = in[0];
  out[1] = in[1];
  out[2] = in[2];
}

/* Any unit vector perpendicular to unit vector t. */
static void any_perpendicular(const double t[3], double out[3]) {
  int axis = 0;
  if (fabs(t[1]) < fabs(t[axis]))
    axis = 1;
  if (fabs(t[2]) < fabs(t[axis]))
    axis = 2;
  double e[3] = {0.0, 0.0, 0.0};
  e[axis] = 1.0;
  double d = satf_dot3d(e, t);
  for (int c = 0; c < 3; c++)
    out[c] = e[c] - d * t[c];
  satf_normalize3d(out);
}

/* ---- validation ---- */

static satf_status check_finite(const float *v, int count, const char *what,
                                satf_error *err) {
  if (!v)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "cluster/%s: array is NULL",
                          what);
  for (int i = 0; i < count; i++)
    if (!isfinite(v[i]))
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "cluster/%s[%d]: value is not finite", what, i);
  return SATF_OK;
}

static satf_status check_positive(const float *v, int count, const char *what,
                                  satf_error *err) {
  for (int i = 0; i < count; i++)
    if (!(v[i] > 0.0f))
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "cluster/%s[%d]: radius %g must be > 0", what, i,
                            (double)v[i]);
  return SATF_OK;
}

static satf_status check_desc(const satf_cluster_desc *desc, satf_error *err) {
  if (!desc)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "cluster: desc is NULL");
  if (desc->n_ctrl < 2 || desc->n_ctrl > MAX_CONTROL_POINTS)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "cluster/n_ctrl: %d trajectory control points, "
                          "need 2..%d",
                          desc->n_ctrl, MAX_CONTROL_POINTS);
  if (desc->n_radius < 1 || desc->n_radius > MAX_CONTROL_POINTS)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "cluster/n_radius: %d radius control points, "
                          "need 1..%d",
                          desc->n_radius, MAX_CONTROL_POINTS);
  satf_status st;
  if ((st = check_finite(desc->traj, desc->n_ctrl * 3, "traj", err)) ||
      (st = check_finite(desc->a, desc->n_radius, "a", err)) ||
      (st = check_finite(desc->b, desc->n_radius, "b", err)) ||
      (st = check_finite(desc->twist, desc->n_radius, "twist", err)) ||
      (st = check_positive(desc->a, desc->n_radius, "a", err)) ||
      (st = check_positive(desc->b, desc->n_radius, "b", err)))
    return st;
  return SATF_OK;
}

/* ---- splines ---- */

static void eval_traj(const satf_cluster *cl, double t, double pos[3],
                      double d1[3], double d2[3]) {
  satf_bspline_eval(cl->traj, cl->n_ctrl, 3, t, pos, d1, d2);
}

static void eval_scalar(const satf_cluster *cl, const float *ctrl, double t,
                        double *value, double *d1) {
  satf_bspline_eval(ctrl, cl->n_radius, 1, t, value, d1, NULL);
}

static double sample_t(int i) { return (double)i / (FRAME_SAMPLES - 1); }

/* Evaluates T and T' at every table sample (T' left unnormalised in the
 * tangent table) and returns the arc length of T by the composite Simpson
 * rule on |T'|. */
static double sample_trajectory(satf_cluster *cl) {
  const int n = FRAME_SAMPLES - 1;
  double sum = 0.0;
  for (int i = 0; i <= n; i++) {
    eval_traj(cl, sample_t(i), cl->pos[i], cl->tangent[i], NULL);
    double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * sqrt(satf_dot3d(cl->tangent[i], cl->tangent[i]));
  }
  return sum / (3.0 * n);
}

/* Largest absolute control coordinate: the scale against which a speed or a
 * length counts as zero. */
static double trajectory_extent(const satf_cluster *cl) {
  double m = 0.0;
  for (int i = 0; i < cl->n_ctrl * 3; i++)
    m = fmax(m, fabs((double)cl->traj[i]));
  return m;
}

/* Unit tangents at the table samples. Where T' vanishes (repeated control
 * points) the chord to the neighbouring samples stands in; on a stationary
 * stretch the nearest valid tangent is copied. */
static void build_tangent_table(satf_cluster *cl, double speed_eps) {
  int valid[FRAME_SAMPLES];
  int first_valid = -1;
  for (int i = 0; i < FRAME_SAMPLES; i++) {
    double *tan = cl->tangent[i];
    valid[i] = satf_normalize3d(tan) > speed_eps;
    if (!valid[i]) {
      const double *p0 = cl->pos[i > 0 ? i - 1 : 0];
      const double *p1 = cl->pos[i < FRAME_SAMPLES - 1 ? i + 1 : i];
      for (int c = 0; c < 3; c++)
        tan[c] = p1[c] - p0[c];
      valid[i] = satf_normalize3d(tan) > speed_eps / FRAME_SAMPLES;
    }
    if (valid[i] && first_valid < 0)
      first_valid = i;
  }
  for (int i = 0; i < FRAME_SAMPLES; i++) {
    if (valid[i])
      continue;
    const double *src =
        i < first_valid ? cl->tangent[first_valid] : cl->tangent[i - 1];
    memcpy(cl->tangent[i], src, sizeof(double) * 3);
  }
}

/* One step of the double reflection method (Wang et al. 2008, Algorithm
 * "DR"): reflect (r_i, t_i) in the bisector plane of x_i x_{i+1}, then in
 * the plane that maps the reflected tangent onto t_{i+1}. */
static void double_reflection_step(const double x0[3], const double x1[3],
                                   const double t0[3], const double r0[3],
                                   const double t1[3], double r1[3]) {
  double v1[3] = {x1[0] - x0[0], x1[1] - x0[1], x1[2] - x0[2]};
  double c1 = satf_dot3d(v1, v1);
  double rl[3], tl[3];
  memcpy(rl, r0, sizeof rl);
  memcpy(tl, t0, sizeof tl);
  if (c1 > 0.0) {
    double kr = 2.0 / c1 * satf_dot3d(v1, r0),
           kt = 2.0 / c1 * satf_dot3d(v1, t0);
    for (int c = 0; c < 3; c++) {
      rl[c] = r0[c] - kr * v1[c];
      tl[c] = t0[c] - kt * v1[c];
    }
  }
  double v2[3] = {t1[0] - tl[0], t1[1] - tl[1], t1[2] - tl[2]};
  double c2 = satf_dot3d(v2, v2);
  memcpy(r1, rl, sizeof rl);
  if (c2 > 0.0) {
    double k = 2.0 / c2 * satf_dot3d(v2, rl);
    for (int c = 0; c < 3; c++)
      r1[c] = rl[c] - k * v2[c];
  }
  /* Keep exact orthonormality against t1 despite rounding. */
  double d = satf_dot3d(r1, t1);
  for (int c = 0; c < 3; c++)
    r1[c] -= d * t1[c];
  if (satf_normalize3d(r1) == 0.0)
    any_perpendicular(t1, r1);
}

static void build_frame_table(satf_cluster *cl) {
  any_perpendicular(cl->tangent[0], cl->n1[0]);
  for (int i = 0; i + 1 < FRAME_SAMPLES; i++)
    double_reflection_step(cl->pos[i], cl->pos[i + 1], cl->tangent[i],
                           cl->n1[i], cl->tangent[i + 1], cl->n1[i + 1]);
}

satf_status satf_cluster_create(const satf_cluster_desc *desc,
                                satf_cluster **out, satf_error *err) {
  if (!out)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "cluster: out is NULL");
  *out = NULL;
  satf_status st = check_desc(desc, err);
  if (st)
    return st;
  satf_cluster *cl = calloc(1, sizeof *cl);
  size_t n_floats = (size_t)desc->n_ctrl * 3 + (size_t)desc->n_radius * 3;
  float *data = calloc(n_floats, sizeof(float));
  if (!cl || !data) {
    free(cl);
    free(data);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cluster: cannot allocate %zu control values",
                          n_floats);
  }
  cl->n_ctrl = desc->n_ctrl;
  cl->n_radius = desc->n_radius;
  cl->traj = data;
  cl->a = cl->traj + (size_t)desc->n_ctrl * 3;
  cl->b = cl->a + desc->n_radius;
  cl->twist = cl->b + desc->n_radius;
  memcpy(cl->traj, desc->traj, sizeof(float) * 3 * (size_t)desc->n_ctrl);
  memcpy(cl->a, desc->a, sizeof(float) * (size_t)desc->n_radius);
  memcpy(cl->b, desc->b, sizeof(float) * (size_t)desc->n_radius);
  memcpy(cl->twist, desc->twist, sizeof(float) * (size_t)desc->n_radius);

  cl->length = sample_trajectory(cl);
  double extent = trajectory_extent(cl);
  if (!(cl->length > 1e-6 * extent) || cl->length < DBL_MIN) {
    satf_cluster_destroy(cl);
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "cluster/traj: trajectory has zero length (all "
                          "control points coincide)");
  }
  build_tangent_table(cl, 1e-9 * cl->length);
  build_frame_table(cl);
  *out = cl;
  return SATF_OK;
}

void satf_cluster_destroy(satf_cluster *cluster) {
  if (!cluster)
    return;
  free(cluster->traj);
  free(cluster);
}

float satf_cluster_length(const satf_cluster *cluster) {
  return (float)cluster->length;
}

void satf_cluster_trajectory(const satf_cluster *cluster, float t, float pos[3],
                             float d1[3]) {
  double p[3], d[3];
  eval_traj(cluster, t, p, d, NULL);
  to_float3(p, pos);
  if (d1)
    to_float3(d, d1);
}

/* Table position of t: sample index i and fraction f towards i + 1. */
static void table_locate(double t, int *i, double *f) {
  double x = t * (FRAME_SAMPLES - 1);
  if (!(x > 0.0))
    x = 0.0;
  if (x > FRAME_SAMPLES - 1)
    x = FRAME_SAMPLES - 1;
  int k = (int)x;
  if (k > FRAME_SAMPLES - 2)
    k = FRAME_SAMPLES - 2;
  *i = k;
  *f = x - k;
}

/* The frame at t in double precision, with dT/dt and d2T/dt2 for callers
 * that need derivatives. The tangent is exact where T' is not degenerate;
 * n1 is interpolated from the table and re-orthogonalised against it. */
static void frame_at(const satf_cluster *cl, double t, double d1[3],
                     double d2[3], double *speed, double tan[3], double n1[3],
                     double n2[3]) {
  int i;
  double f;
  table_locate(t, &i, &f);
  eval_traj(cl, t, NULL, d1, d2);
  memcpy(tan, d1, sizeof(double) * 3);
  *speed = satf_normalize3d(tan);
  if (!(*speed > 1e-9 * cl->length)) {
    *speed = 0.0;
    for (int c = 0; c < 3; c++)
      tan[c] = (1.0 - f) * cl->tangent[i][c] + f * cl->tangent[i + 1][c];
    satf_normalize3d(tan);
  }
  double r[3];
  for (int c = 0; c < 3; c++)
    r[c] = (1.0 - f) * cl->n1[i][c] + f * cl->n1[i + 1][c];
  double d = satf_dot3d(r, tan);
  for (int c = 0; c < 3; c++)
    r[c] -= d * tan[c];
  if (satf_normalize3d(r) < 1e-12)
    any_perpendicular(tan, r);
  memcpy(n1, r, sizeof r);
  satf_cross3d(tan, n1, n2);
  satf_normalize3d(n2);
}

void satf_cluster_frame(const satf_cluster *cluster, float t, float tangent[3],
                        float n1[3], float n2[3]) {
  double d1[3], d2[3], speed, tan[3], a[3], b[3];
  frame_at(cluster, t, d1, d2, &speed, tan, a, b);
  to_float3(tan, tangent);
  to_float3(a, n1);
  to_float3(b, n2);
}

/* Derivative in t of a rotation-minimising normal n: it has no component
 * about the tangent, so dn/dt = -(n . dtan/dt) tan, with dtan/dt the part
 * of T'' normal to the tangent divided by the speed. */
static void rmf_normal_derivative(const double d2[3], double speed,
                                  const double tan[3], const double n[3],
                                  double dn[3]) {
  if (speed <= 0.0) {
    dn[0] = dn[1] = dn[2] = 0.0;
    return;
  }
  double k = satf_dot3d(d2, n) / speed; /* n . dtan/dt, as n is normal to tan */
  for (int c = 0; c < 3; c++)
    dn[c] = -k * tan[c];
}

/* The ellipse's axes at t: the rotation-minimising normals (r1, r2) turned
 * by theta, and their t-derivatives from the frame's derivatives (dr1, dr2)
 * and the twist rate dth (SATF eq. 1 with theta turning the cross-section,
 * satf/geometry.h):
 *   e1 = c r1 + s r2,  e1' = c r1' + s r2' + theta' e2,
 *   e2 = -s r1 + c r2, e2' = -s r1' + c r2' - theta' e1. */
static void twisted_axes(const double r1[3], const double r2[3],
                         const double dr1[3], const double dr2[3], double th,
                         double dth, double e1[3], double e2[3], double de1[3],
                         double de2[3]) {
  double c = cos(th), s = sin(th);
  for (int k = 0; k < 3; k++) {
    e1[k] = c * r1[k] + s * r2[k];
    e2[k] = -s * r1[k] + c * r2[k];
  }
  for (int k = 0; k < 3; k++) {
    de1[k] = c * dr1[k] + s * dr2[k] + dth * e2[k];
    de2[k] = -s * dr1[k] + c * dr2[k] - dth * e1[k];
  }
}

void satf_cluster_section_at(const satf_cluster *cluster, float t,
                             satf_cluster_section *s) {
  double pos[3], d1[3], d2[3], speed, tan[3], n1[3], n2[3], dn1[3], dn2[3];
  double tt = t;
  eval_traj(cluster, tt, pos, NULL, NULL);
  frame_at(cluster, tt, d1, d2, &speed, tan, n1, n2);
  rmf_normal_derivative(d2, speed, tan, n1, dn1);
  rmf_normal_derivative(d2, speed, tan, n2, dn2);
  double a, da, b, db, th, dth;
  eval_scalar(cluster, cluster->a, tt, &a, &da);
  eval_scalar(cluster, cluster->b, tt, &b, &db);
  eval_scalar(cluster, cluster->twist, tt, &th, &dth);
  double e1[3], e2[3], de1[3], de2[3];
  twisted_axes(n1, n2, dn1, dn2, th, dth, e1, e2, de1, de2);
  s->t = t;
  to_float3(pos, s->center);
  to_float3(d1, s->dcenter);
  to_float3(tan, s->tangent);
  to_float3(e1, s->n1);
  to_float3(e2, s->n2);
  to_float3(de1, s->dn1);
  to_float3(de2, s->dn2);
  to_float3(n1, s->rmf_n1);
  to_float3(n2, s->rmf_n2);
  s->a = (float)a;
  s->b = (float)b;
  s->theta = (float)th;
  s->da = (float)da;
  s->db = (float)db;
  s->dtheta = (float)dth;
}

/* The ellipse of SATF eq. 1 in the normal plane at v = 1, its axes n1, n2
 * already turned by theta: E(u) = A cos(u) n1 + B sin(u) n2. */
static void ellipse_offset(const satf_cluster_section *s, double u,
                           double e[3]) {
  double x = s->a * cos(u), y = s->b * sin(u);
  for (int c = 0; c < 3; c++)
    e[c] = x * s->n1[c] + y * s->n2[c];
}

/* dE/du at v = 1. */
static void ellipse_du(const satf_cluster_section *s, double u, double e[3]) {
  double x = -s->a * sin(u), y = s->b * cos(u);
  for (int c = 0; c < 3; c++)
    e[c] = x * s->n1[c] + y * s->n2[c];
}

/* dE/dt at v = 1: the radii and the axes vary along t (the axes' derivative
 * holds both the frame's turn and the twist). */
static void ellipse_dt(const satf_cluster_section *s, double u, double e[3]) {
  double cu = cos(u), su = sin(u);
  double k1 = s->da * cu, k2 = s->db * su;
  for (int c = 0; c < 3; c++)
    e[c] = k1 * s->n1[c] + s->a * cu * s->dn1[c] + k2 * s->n2[c] +
           s->b * su * s->dn2[c];
}

void satf_cluster_section_point(const satf_cluster_section *s, float v, float u,
                                float p[3]) {
  double e[3];
  ellipse_offset(s, u, e); /* SATF eq. 1 */
  for (int c = 0; c < 3; c++)
    p[c] = (float)(s->center[c] + (double)v * e[c]);
}

/* dP/dt = T'(t) + v dE/dt. */
static void point_dt(const satf_cluster_section *s, double v, double u,
                     double out[3]) {
  double e[3];
  ellipse_dt(s, u, e);
  for (int c = 0; c < 3; c++)
    out[c] = s->dcenter[c] + v * e[c];
}

void satf_cluster_section_hair_tangent(const satf_cluster_section *s, float v,
                                       float u, float dir[3]) {
  double d[3];
  point_dt(s, v, u, d);
  if (satf_normalize3d(d) == 0.0)
    to_double3(s->tangent, d);
  to_float3(d, dir);
}

void satf_cluster_section_surface_normal(const satf_cluster_section *s, float v,
                                         float u, float n[3]) {
  double eu[3], pt[3], out[3];
  /* dP/du = v dE/du; the positive factor v does not change the direction. */
  ellipse_du(s, u, eu);
  point_dt(s, v > 0.0f ? v : 0.0f, u, pt);
  satf_cross3d(eu, pt, out);
  /* The outward normal of the ellipse within its plane, for orientation and
   * as the fallback where the surface is degenerate. */
  double in_plane[3];
  double x = s->b * cos(u), y = s->a * sin(u);
  for (int c = 0; c < 3; c++)
    in_plane[c] = x * s->n1[c] + y * s->n2[c];
  satf_normalize3d(in_plane);
  if (satf_normalize3d(out) < 1e-20)
    memcpy(out, in_plane, sizeof out);
  if (satf_dot3d(out, in_plane) < 0.0)
    for (int c = 0; c < 3; c++)
      out[c] = -out[c];
  to_float3(out, n);
}

void satf_cluster_point(const satf_cluster *cluster, float t, float v, float u,
                        float p[3]) {
  satf_cluster_section s;
  satf_cluster_section_at(cluster, t, &s);
  satf_cluster_section_point(&s, v, u, p);
}

void satf_cluster_hair_tangent(const satf_cluster *cluster, float t, float v,
                               float u, float dir[3]) {
  satf_cluster_section s;
  satf_cluster_section_at(cluster, t, &s);
  satf_cluster_section_hair_tangent(&s, v, u, dir);
}

void satf_cluster_surface_normal(const satf_cluster *cluster, float t, float v,
                                 float u, float n[3]) {
  satf_cluster_section s;
  satf_cluster_section_at(cluster, t, &s);
  satf_cluster_section_surface_normal(&s, v, u, n);
}
