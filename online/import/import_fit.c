/* import_fit.c - fitting one cluster's generalized cylinder (SATF eq. 1-2)
 * to its strands: the trajectory T(t) is the least-squares cubic B-spline
 * through the strands' mean, A(t) and B(t) come from the spread of the
 * strand points in the normal plane along the frame axes n1 and n2 (the
 * geometry's ellipse lies on those axes: satf/cluster.h), and the twist
 * theta(t) is how the strands wind about the trajectory, since eq. 1 makes
 * theta the phase every strand's angle u is measured from. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/geometry.h"
#include "satf/import.h"
#include "satf/math.h"

#define TABLE 257 /* trajectory samples for the coarse closest-point search */
#define TWIST_BINS 32

satf_import_fit_params satf_import_fit_params_default(void) {
  satf_import_fit_params p = {8, 8, 32, 0.95f, 0.0f};
  return p;
}

void satf_import_fit_free(satf_import_fit *fit) {
  if (fit) {
    free(fit->traj);
    free(fit->a);
    free(fit->b);
    free(fit->twist);
    free(fit->spread);
    memset(fit, 0, sizeof *fit);
  }
}

void satf_import_projection_free(satf_import_projection *p) {
  if (p) {
    free(p->offset);
    free(p->txy);
    memset(p, 0, sizeof *p);
  }
}

satf_status satf_import_fit_cluster_create(const satf_import_fit *fit,
                                           satf_cluster **out,
                                           satf_error *err) {
  satf_cluster_desc d = {fit->n_ctrl, fit->traj, fit->n_radius,
                         fit->a,      fit->b,    fit->twist};
  return satf_cluster_create(&d, out, err);
}

/* ---- Closest point on the trajectory ----------------------------------- */

static void trajectory_table(const satf_cluster *c, float *tab) {
  for (int k = 0; k < TABLE; k++)
    satf_cluster_trajectory(c, (float)k / (TABLE - 1), tab + 3 * k, NULL);
}

/* Coarse search over the table, then Gauss-Newton on |p - T(t)|^2. */
static float closest_t(const satf_cluster *c, const float *tab,
                       const float p[3]) {
  int best = 0;
  float bd = FLT_MAX;
  for (int k = 0; k < TABLE; k++) {
    float dx = p[0] - tab[3 * k], dy = p[1] - tab[3 * k + 1],
          dz = p[2] - tab[3 * k + 2];
    float d = dx * dx + dy * dy + dz * dz;
    if (d < bd) {
      bd = d;
      best = k;
    }
  }
  float t = (float)best / (TABLE - 1), h = 1.0f / (TABLE - 1);
  for (int it = 0; it < 4; it++) {
    float q[3], d1[3];
    satf_cluster_trajectory(c, t, q, d1);
    float num = 0.0f, den = 0.0f;
    for (int e = 0; e < 3; e++) {
      num += (p[e] - q[e]) * d1[e];
      den += d1[e] * d1[e];
    }
    if (!(den > 0.0f))
      break;
    float step = num / den;
    step = step > h ? h : step < -h ? -h : step;
    t += step;
    t = t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
  }
  return t;
}

/* The offset of p in the normal-plane frame at t, and its distance. */
static void offset_at(const satf_cluster_section *s, const float p[3],
                      float xy[2], float *distance) {
  float d[3] = {p[0] - s->center[0], p[1] - s->center[1], p[2] - s->center[2]};
  xy[0] = d[0] * s->n1[0] + d[1] * s->n1[1] + d[2] * s->n1[2];
  xy[1] = d[0] * s->n2[0] + d[1] * s->n2[1] + d[2] * s->n2[2];
  if (distance)
    *distance = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

void satf_import_project_point(const satf_cluster *cluster, const float p[3],
                               float *t, float *distance, float xy[2]) {
  float tab[3 * TABLE];
  trajectory_table(cluster, tab);
  *t = closest_t(cluster, tab, p);
  satf_cluster_section s;
  satf_cluster_section_at(cluster, *t, &s);
  offset_at(&s, p, xy, distance);
}

/* Raw projection of every member point: (t, x, y) with x, y along n1, n2,
 * and the distance to T(t); or normalised cross-section coordinates (SATF
 * eq. 1 inverted: x / A = v cos(theta + u), y / B = v sin(theta + u)). */
typedef struct project_job {
  const satf_strand_set *s;
  const int *members;
  const satf_cluster *cluster;
  const float *tab;
  const size_t *offset;
  float *txy;
  float *dist; /* may be NULL */
  int normalise;
} project_job;

static int project_strand(void *vctx, size_t i, int thread) {
  (void)thread;
  const project_job *j = vctx;
  int n;
  const float *p = satf_strand_set_strand(j->s, j->members[i], &n);
  for (int k = 0; k < n; k++) {
    size_t o = j->offset[i] + (size_t)k;
    float t = closest_t(j->cluster, j->tab, p + 3 * k), xy[2], d;
    satf_cluster_section sec;
    satf_cluster_section_at(j->cluster, t, &sec);
    offset_at(&sec, p + 3 * k, xy, &d);
    if (j->normalise) {
      float x = xy[0] / sec.a, y = xy[1] / sec.b;
      float c = cosf(sec.theta), s = sinf(sec.theta);
      xy[0] = c * x + s * y;
      xy[1] = -s * x + c * y;
    }
    j->txy[3 * o] = t;
    j->txy[3 * o + 1] = xy[0];
    j->txy[3 * o + 2] = xy[1];
    if (j->dist)
      j->dist[o] = d;
  }
  return 0;
}

static satf_status project_all(const satf_strand_set *s, const int *members,
                               int n_members, const satf_cluster *cluster,
                               int normalise, satf_import_projection *out,
                               float **dist, satf_error *err) {
  memset(out, 0, sizeof *out);
  out->n_strands = n_members;
  out->offset = malloc(((size_t)n_members + 1) * sizeof(size_t));
  if (!out->offset)
    return satf_error_set(err, SATF_ERR_NOMEM, "projection: out of memory");
  out->offset[0] = 0;
  for (int i = 0; i < n_members; i++)
    out->offset[i + 1] =
        out->offset[i] + (size_t)satf_strand_set_points(s, members[i]);
  size_t np = out->offset[n_members];
  out->txy = malloc((np ? np : 1) * 3 * sizeof(float));
  if (dist)
    *dist = malloc((np ? np : 1) * sizeof(float));
  float *tab = malloc(3 * TABLE * sizeof(float));
  if (!out->txy || (dist && !*dist) || !tab) {
    free(tab);
    if (dist) {
      free(*dist);
      *dist = NULL;
    }
    satf_import_projection_free(out);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "projection: cannot hold %zu points", np);
  }
  trajectory_table(cluster, tab);
  project_job job = {s,
                     members,
                     cluster,
                     tab,
                     out->offset,
                     out->txy,
                     dist ? *dist : NULL,
                     normalise};
  /* Clusters are fitted in parallel already; one thread here. */
  for (int i = 0; i < n_members; i++)
    project_strand(&job, (size_t)i, 0);
  free(tab);
  return SATF_OK;
}

satf_status satf_import_project(const satf_strand_set *s, const int *members,
                                int n_members, const satf_cluster *cluster,
                                satf_import_projection *out, satf_error *err) {
  return project_all(s, members, n_members, cluster, 1, out, NULL, err);
}

int satf_import_projection_at(const satf_import_projection *p, int i, float t,
                              float xy[2]) {
  const float *q = p->txy + 3 * p->offset[i];
  int n = (int)(p->offset[i + 1] - p->offset[i]);
  for (int k = 0; k + 1 < n; k++) {
    float t0 = q[3 * k], t1 = q[3 * k + 3];
    float lo = t0 < t1 ? t0 : t1, hi = t0 < t1 ? t1 : t0;
    if (t < lo || t > hi)
      continue;
    float f = hi > lo ? (t - t0) / (t1 - t0) : 0.0f;
    xy[0] = q[3 * k + 1] + f * (q[3 * k + 4] - q[3 * k + 1]);
    xy[1] = q[3 * k + 2] + f * (q[3 * k + 5] - q[3 * k + 2]);
    return 1;
  }
  return 0;
}

/* ---- Least squares ----------------------------------------------------- */

/* Solves the n x n system m x = rhs (rhs has k columns, overwritten with x)
 * by Gaussian elimination with partial pivoting. Returns -1 if singular. */
static int solve(double *m, double *rhs, int n, int k) {
  for (int c = 0; c < n; c++) {
    int piv = c;
    for (int r = c + 1; r < n; r++)
      if (fabs(m[r * n + c]) > fabs(m[piv * n + c]))
        piv = r;
    if (fabs(m[piv * n + c]) < 1e-300)
      return -1;
    if (piv != c) {
      for (int e = 0; e < n; e++) {
        double t = m[c * n + e];
        m[c * n + e] = m[piv * n + e];
        m[piv * n + e] = t;
      }
      for (int e = 0; e < k; e++) {
        double t = rhs[c * k + e];
        rhs[c * k + e] = rhs[piv * k + e];
        rhs[piv * k + e] = t;
      }
    }
    for (int r = c + 1; r < n; r++) {
      double f = m[r * n + c] / m[c * n + c];
      for (int e = c; e < n; e++)
        m[r * n + e] -= f * m[c * n + e];
      for (int e = 0; e < k; e++)
        rhs[r * k + e] -= f * rhs[c * k + e];
    }
  }
  for (int c = n - 1; c >= 0; c--)
    for (int e = 0; e < k; e++) {
      double v = rhs[c * k + e];
      for (int r = c + 1; r < n; r++)
        v -= m[c * n + r] * rhs[r * k + e];
      rhs[c * k + e] = v / m[c * n + c];
    }
  return 0;
}

/* The n basis functions of the clamped uniform B-spline at t. */
static void basis(int n, double t, double *w) {
  float unit[64];
  memset(unit, 0, sizeof unit);
  for (int j = 0; j < n; j++) {
    unit[j] = 1.0f;
    satf_bspline_eval(unit, n, 1, t, w + j, NULL, NULL);
    unit[j] = 0.0f;
  }
}

/* Greville abscissa of control value j: where a clamped B-spline whose
 * control values sample a linear function reproduces it exactly. */
static double greville(int j, int n) {
  int p = satf_bspline_degree(n);
  if (p == 0)
    return 0.5;
  double s = 0.0;
  for (int i = j + 1; i <= j + p; i++)
    s += i <= p ? 0.0 : i >= n ? 1.0 : (double)(i - p) / (double)(n - p);
  return s / p;
}

/* The least-squares B-spline with n control points through m points
 * parameterised by their chord length. */
static int fit_trajectory(const double *pts, int m, int n, float *ctrl) {
  double *u = malloc((size_t)m * sizeof(double));
  double *ata = calloc((size_t)n * n, sizeof(double));
  double *atb = calloc((size_t)n * 3, sizeof(double));
  double w[64];
  int bad = !u || !ata || !atb;
  if (!bad) {
    u[0] = 0.0;
    for (int k = 1; k < m; k++) {
      double dx = pts[3 * k] - pts[3 * k - 3],
             dy = pts[3 * k + 1] - pts[3 * k - 2],
             dz = pts[3 * k + 2] - pts[3 * k - 1];
      u[k] = u[k - 1] + sqrt(dx * dx + dy * dy + dz * dz);
    }
    for (int k = 0; k < m; k++)
      u[k] = u[m - 1] > 0.0 ? u[k] / u[m - 1] : (double)k / (m - 1);
    for (int k = 0; k < m; k++) {
      basis(n, u[k], w);
      for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++)
          ata[i * n + j] += w[i] * w[j];
        for (int c = 0; c < 3; c++)
          atb[i * 3 + c] += w[i] * pts[3 * k + c];
      }
    }
    bad = solve(ata, atb, n, 3) != 0;
    for (int i = 0; !bad && i < 3 * n; i++)
      ctrl[i] = (float)atb[i];
  }
  free(u);
  free(ata);
  free(atb);
  return bad ? -1 : 0;
}

/* ---- Cross-section ----------------------------------------------------- */

static int cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

/* A(t) and B(t) at the Greville points: the RMS offsets along n1 and n2,
 * each point weighted by the control value's basis function (a B-spline
 * with those control values then follows the spread smoothly). */
static void fit_axes(const float *txy, size_t np, int n, float floor_radius,
                     float *a, float *b, float *spread) {
  double sw[64] = {0}, sxx[64] = {0}, sxy[64] = {0}, syy[64] = {0}, w[64];
  for (size_t k = 0; k < np; k++) {
    basis(n, txy[3 * k], w);
    double x = txy[3 * k + 1], y = txy[3 * k + 2];
    for (int j = 0; j < n; j++) {
      sw[j] += w[j];
      sxx[j] += w[j] * x * x;
      sxy[j] += w[j] * x * y;
      syy[j] += w[j] * y * y;
    }
  }
  for (int j = 0; j < n; j++) {
    double k = sw[j] > 1e-9 ? 1.0 / sw[j] : 0.0;
    spread[3 * j] = (float)(sxx[j] * k);
    spread[3 * j + 1] = (float)(sxy[j] * k);
    spread[3 * j + 2] = (float)(syy[j] * k);
    /* 2 sigma: the edge of a uniformly filled disk is at 2 RMS */
    double ra = sw[j] > 1e-9 ? 2.0 * sqrt(sxx[j] / sw[j]) : -1.0;
    double rb = sw[j] > 1e-9 ? 2.0 * sqrt(syy[j] / sw[j]) : -1.0;
    a[j] = (float)ra;
    b[j] = (float)rb;
  }
  /* control values no point informs copy their nearest informed one */
  for (int j = 0; j < n; j++)
    if (a[j] < 0.0f) {
      for (int d = 1; d < n; d++) {
        if (j - d >= 0 && a[j - d] >= 0.0f) {
          a[j] = a[j - d];
          b[j] = b[j - d];
          break;
        }
        if (j + d < n && a[j + d] >= 0.0f && sw[j + d] > 1e-9) {
          a[j] = a[j + d];
          b[j] = b[j + d];
          break;
        }
      }
    }
  for (int j = 0; j < n; j++) {
    float big = a[j] > b[j] ? a[j] : b[j];
    float lo = floor_radius > 0.05f * big ? floor_radius : 0.05f * big;
    a[j] = a[j] > lo ? a[j] : lo;
    b[j] = b[j] > lo ? b[j] : lo;
  }
}

static double spline1(const float *ctrl, int n, double t) {
  double v;
  satf_bspline_eval(ctrl, n, 1, t, &v, NULL, NULL);
  return v;
}

/* Adds a segment's winding (dphi over dt, both weighted) to every bin its
 * t interval overlaps, in proportion to the overlap. */
static void spread_over_bins(double t0, double t1, double dphi, double dt,
                             double *num, double *den) {
  double lo = t0 < t1 ? t0 : t1, hi = t0 < t1 ? t1 : t0;
  int b0 = (int)(lo * TWIST_BINS), b1 = (int)(hi * TWIST_BINS);
  b0 = b0 < 0 ? 0 : b0 >= TWIST_BINS ? TWIST_BINS - 1 : b0;
  b1 = b1 < 0 ? 0 : b1 >= TWIST_BINS ? TWIST_BINS - 1 : b1;
  for (int k = b0; k <= b1; k++) {
    double a = fmax(lo, (double)k / TWIST_BINS);
    double b = fmin(hi, (double)(k + 1) / TWIST_BINS);
    double f = hi > lo ? (b - a) / (hi - lo) : 1.0;
    if (f <= 0.0)
      continue;
    num[k] += f * dphi;
    den[k] += f * dt;
  }
}

/* theta(t): the strands' mean winding rate about the trajectory, measured
 * on their normalised phase and weighted by v^2 (a phase near the core is
 * noise), integrated from theta(0) = 0 and sampled at the Greville points. */
static void fit_twist(const satf_import_projection *raw, const float *a,
                      const float *b, int n, float *twist) {
  double num[TWIST_BINS] = {0}, den[TWIST_BINS] = {0};
  for (int i = 0; i < raw->n_strands; i++) {
    const float *q = raw->txy + 3 * raw->offset[i];
    int m = (int)(raw->offset[i + 1] - raw->offset[i]);
    double prev_phase = 0.0, prev_v = 0.0, prev_t = 0.0;
    for (int k = 0; k < m; k++) {
      double t = q[3 * k];
      double x = q[3 * k + 1] / spline1(a, n, t),
             y = q[3 * k + 2] / spline1(b, n, t);
      double phase = atan2(y, x), v = sqrt(x * x + y * y);
      if (k > 0) {
        double dphi = phase - prev_phase, dt = t - prev_t;
        dphi -= 2.0 * SATF_PI * floor((dphi + SATF_PI) / (2.0 * SATF_PI));
        double wv = v < prev_v ? v : prev_v;
        if (fabs(dt) > 1e-6 && wv > 0.1)
          spread_over_bins(prev_t, t, wv * wv * dphi, wv * wv * dt, num, den);
      }
      prev_phase = phase;
      prev_v = v;
      prev_t = t;
    }
  }
  double rate[TWIST_BINS];
  int have[TWIST_BINS], any = 0;
  for (int k = 0; k < TWIST_BINS; k++) {
    have[k] = fabs(den[k]) > 1e-12;
    rate[k] = have[k] ? num[k] / den[k] : 0.0;
    any |= have[k];
  }
  /* bins no strand segment spans take the rate of the nearest that one
   * does */
  for (int k = 0; any && k < TWIST_BINS; k++)
    for (int d = 1; !have[k] && d < TWIST_BINS; d++) {
      if (k - d >= 0 && have[k - d]) {
        rate[k] = rate[k - d];
        break;
      }
      if (k + d < TWIST_BINS && have[k + d]) {
        rate[k] = rate[k + d];
        break;
      }
    }
  for (int j = 0; j < n; j++) {
    double g = n > 1 ? greville(j, n) : 1.0, acc = 0.0;
    for (int k = 0; k < TWIST_BINS; k++) {
      double lo = (double)k / TWIST_BINS, hi = (double)(k + 1) / TWIST_BINS;
      if (g <= lo)
        break;
      acc += rate[k] * ((g < hi ? g : hi) - lo);
    }
    twist[j] = n > 1 ? (float)acc : 0.0f;
  }
}

satf_status satf_import_fit_cluster(const satf_strand_set *s,
                                    const int *members, int n_members,
                                    const satf_import_fit_params *p,
                                    satf_import_fit *out, satf_error *err) {
  memset(out, 0, sizeof *out);
  if (n_members < 1 || p->n_ctrl < 2 || p->n_ctrl > 64 || p->n_radius < 1 ||
      p->n_radius > 64 || p->samples < p->n_ctrl || p->samples > 4096 ||
      !(p->coverage > 0.0f && p->coverage <= 1.0f) ||
      !(p->min_radius >= 0.0f) || !isfinite(p->min_radius))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "fit: %d strands (>= 1), %d trajectory control "
                          "points (2..64), %d radius values (1..64), %d "
                          "samples (n_ctrl..4096), coverage %g in (0, 1]",
                          n_members, p->n_ctrl, p->n_radius, p->samples,
                          (double)p->coverage);
  int m = p->samples;
  double *mean = calloc(3 * (size_t)m, sizeof(double));
  float *buf = malloc(3 * (size_t)m * sizeof(float));
  out->traj = malloc(3 * (size_t)p->n_ctrl * sizeof(float));
  out->a = malloc((size_t)p->n_radius * sizeof(float));
  out->b = malloc((size_t)p->n_radius * sizeof(float));
  out->twist = calloc((size_t)p->n_radius, sizeof(float));
  out->spread = calloc(3 * (size_t)p->n_radius, sizeof(float));
  if (!mean || !buf || !out->traj || !out->a || !out->b || !out->twist ||
      !out->spread) {
    free(mean);
    free(buf);
    satf_import_fit_free(out);
    return satf_error_set(err, SATF_ERR_NOMEM, "fit: out of memory");
  }
  for (int i = 0; i < n_members; i++) {
    satf_import_resample(s, members[i], m, buf);
    for (int k = 0; k < 3 * m; k++)
      mean[k] += buf[k];
  }
  for (int k = 0; k < 3 * m; k++)
    mean[k] /= n_members;
  free(buf);
  out->n_ctrl = p->n_ctrl;
  out->n_radius = p->n_radius;
  int bad = fit_trajectory(mean, m, p->n_ctrl, out->traj);
  free(mean);
  if (bad) {
    satf_import_fit_free(out);
    return satf_error_set(err, SATF_ERR_INTERNAL,
                          "fit: the trajectory's least-squares system is "
                          "singular");
  }
  /* A provisional cylinder of unit radius gives the frames. */
  float one = 1.0f, zero = 0.0f;
  satf_cluster_desc d = {p->n_ctrl, out->traj, 1, &one, &one, &zero};
  satf_cluster *cl;
  satf_status st = satf_cluster_create(&d, &cl, err);
  if (st != SATF_OK) {
    satf_import_fit_free(out);
    return st;
  }
  out->length = satf_cluster_length(cl);
  satf_import_projection raw;
  float *dist = NULL;
  st = project_all(s, members, n_members, cl, 0, &raw, &dist, err);
  satf_cluster_destroy(cl);
  if (st != SATF_OK) {
    satf_import_fit_free(out);
    return st;
  }
  size_t np = raw.offset[n_members];
  fit_axes(raw.txy, np, p->n_radius, 1e-3f * out->length, out->a, out->b,
           out->spread);
  fit_twist(&raw, out->a, out->b, p->n_radius, out->twist);
  /* One common scale makes the envelope enclose `coverage` of the points. */
  float *v = malloc((np ? np : 1) * sizeof(float));
  if (!v) {
    free(dist);
    satf_import_projection_free(&raw);
    satf_import_fit_free(out);
    return satf_error_set(err, SATF_ERR_NOMEM, "fit: out of memory");
  }
  double dsum = 0.0;
  for (size_t k = 0; k < np; k++) {
    double t = raw.txy[3 * k];
    double x = raw.txy[3 * k + 1] / spline1(out->a, p->n_radius, t);
    double y = raw.txy[3 * k + 2] / spline1(out->b, p->n_radius, t);
    v[k] = (float)sqrt(x * x + y * y);
    dsum += dist[k];
  }
  float *sorted = malloc((np ? np : 1) * sizeof(float));
  float scale = 1.0f;
  if (sorted && np > 0) {
    memcpy(sorted, v, np * sizeof(float));
    qsort(sorted, np, sizeof(float), cmp_float);
    size_t q = (size_t)ceil((double)p->coverage * (double)np);
    q = q < 1 ? 1 : q > np ? np : q;
    scale = sorted[q - 1] * 1.0001f;
    if (!(scale > 0.0f))
      scale = 1.0f;
  }
  free(sorted);
  for (int j = 0; j < p->n_radius; j++) {
    out->a[j] = fmaxf(out->a[j] * scale, p->min_radius);
    out->b[j] = fmaxf(out->b[j] * scale, p->min_radius);
  }
  size_t inside = 0;
  if (p->min_radius > 0.0f) { /* the floor may have grown the envelope */
    for (size_t k = 0; k < np; k++) {
      double t = raw.txy[3 * k];
      double x = raw.txy[3 * k + 1] / spline1(out->a, p->n_radius, t);
      double y = raw.txy[3 * k + 2] / spline1(out->b, p->n_radius, t);
      inside += x * x + y * y <= 1.0;
    }
  } else {
    for (size_t k = 0; k < np; k++)
      inside += v[k] <= scale;
  }
  free(v);
  free(dist);
  satf_import_projection_free(&raw);
  out->strands = n_members;
  out->points = np;
  out->inside = inside;
  out->distance_sum = dsum;
  out->strand_width = 0.05f;
  double ma = 0.0, mb = 0.0;
  for (int j = 0; j < p->n_radius; j++) {
    ma += out->a[j];
    mb += out->b[j];
  }
  out->radius = (float)sqrt(ma * mb) / (float)p->n_radius;
  out->layout = SATF_SCENE_LAYOUT_UNIFORM;
  return SATF_OK;
}
