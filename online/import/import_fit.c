/* import_fit.c - fitting one cluster's generalized cylinder (SATF eq. 1-2)
 * to its strands: the trajectory T(t) is the least-squares cubic B-spline
 * through the strands' mean; the twist theta(t) turns the cross-section
 * (satf/geometry.h), so it is the orientation of the principal axes of the
 * strands' spread in the normal plane, unwrapped along t; and A(t), B(t)
 * come from the spread along those turned axes. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "import_internal.h"
#include "satf/common.h"
#include "satf/geometry.h"
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
    free(fit->track_first);
    free(fit->track_count);
    free(fit->track_xy);
    free(fit->track_member);
    free(fit->track_width);
    free(fit->track_ends);
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
 * eq. 1 inverted, in the ellipse's twisted axes n1, n2 of the section:
 * x / A = v cos u, y / B = v sin u). */
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
    if (j->normalise) { /* the section's axes are already twisted */
      xy[0] /= sec.a;
      xy[1] /= sec.b;
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
  /* one evaluation of n control points of dimension n whose control point
   * j is the j-th unit vector: component j of the value is basis j */
  float unit[64 * 64];
  memset(unit, 0, (size_t)n * n * sizeof(float));
  for (int j = 0; j < n; j++)
    unit[j * n + j] = 1.0f;
  satf_bspline_eval(unit, n, n, t, w, NULL, NULL);
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

/* The least-squares B-spline with n control points through m points at
 * the parameters u (in [0, 1]). */
static int fit_bspline_at(const double *pts, const double *u, int m, int n,
                          float *ctrl) {
  double *ata = calloc((size_t)n * n, sizeof(double));
  double *atb = calloc((size_t)n * 3, sizeof(double));
  double w[64];
  int bad = !ata || !atb;
  for (int k = 0; !bad && k < m; k++) {
    basis(n, u[k], w);
    for (int i = 0; i < n; i++) {
      for (int j = 0; j < n; j++)
        ata[i * n + j] += w[i] * w[j];
      for (int c = 0; c < 3; c++)
        atb[i * 3 + c] += w[i] * pts[3 * k + c];
    }
  }
  bad = bad || solve(ata, atb, n, 3) != 0;
  for (int i = 0; !bad && i < 3 * n; i++)
    ctrl[i] = (float)atb[i];
  free(ata);
  free(atb);
  return bad ? -1 : 0;
}

/* The least-squares B-spline with n control points through m points
 * parameterised by their chord length (or evenly). */
static int fit_trajectory_u(const double *pts, int m, int n, int uniform,
                            float *ctrl) {
  double *u = malloc((size_t)m * sizeof(double));
  if (!u)
    return -1;
  u[0] = 0.0;
  for (int k = 1; k < m; k++) {
    double dx = pts[3 * k] - pts[3 * k - 3],
           dy = pts[3 * k + 1] - pts[3 * k - 2],
           dz = pts[3 * k + 2] - pts[3 * k - 1];
    u[k] = u[k - 1] + sqrt(dx * dx + dy * dy + dz * dz);
  }
  for (int k = 0; k < m; k++)
    u[k] = u[m - 1] > 0.0 && !uniform ? u[k] / u[m - 1] : (double)k / (m - 1);
  int bad = fit_bspline_at(pts, u, m, n, ctrl);
  free(u);
  return bad;
}

static int fit_trajectory(const double *pts, int m, int n, float *ctrl) {
  return fit_trajectory_u(pts, m, n, 0, ctrl);
}

/* ---- Cross-section ----------------------------------------------------- */

static int cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

static double spline1(const float *ctrl, int n, double t) {
  double v;
  satf_bspline_eval(ctrl, n, 1, t, &v, NULL, NULL);
  return v;
}

/* Second moments of the points' offsets (x, y) at each control value,
 * every point weighted by that control value's basis function at its t (a
 * B-spline with values taken from them follows the spread smoothly). */
typedef struct basis_moments {
  double w[64], xx[64], xy[64], yy[64];
} basis_moments;

static void moments_gather(const float *txy, size_t np, int n,
                           basis_moments *m) {
  double w[64];
  memset(m, 0, sizeof *m);
  for (size_t k = 0; k < np; k++) {
    basis(n, txy[3 * k], w);
    double x = txy[3 * k + 1], y = txy[3 * k + 2];
    for (int j = 0; j < n; j++) {
      m->w[j] += w[j];
      m->xx[j] += w[j] * x * x;
      m->xy[j] += w[j] * x * y;
      m->yy[j] += w[j] * y * y;
    }
  }
}

/* The mean moments xx, xy, yy per control value (satf_import_fit.spread). */
static void moments_spread(const basis_moments *m, int n, float *spread) {
  for (int j = 0; j < n; j++) {
    double k = m->w[j] > 1e-9 ? 1.0 / m->w[j] : 0.0;
    spread[3 * j] = (float)(m->xx[j] * k);
    spread[3 * j + 1] = (float)(m->xy[j] * k);
    spread[3 * j + 2] = (float)(m->yy[j] * k);
  }
}

/* A(t) and B(t) at the Greville points from moments taken in the
 * ellipse's own (twisted) axes: twice the RMS offset along each. */
static void fit_axes(const basis_moments *m, int n, float floor_radius,
                     float *a, float *b) {
  for (int j = 0; j < n; j++) {
    /* 2 sigma: the edge of a uniformly filled disk is at 2 RMS */
    double ra = m->w[j] > 1e-9 ? 2.0 * sqrt(m->xx[j] / m->w[j]) : -1.0;
    double rb = m->w[j] > 1e-9 ? 2.0 * sqrt(m->yy[j] / m->w[j]) : -1.0;
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
        if (j + d < n && a[j + d] >= 0.0f && m->w[j + d] > 1e-9) {
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

/* ---- Twist ------------------------------------------------------------- */

/* What the points say about theta in each of TWIST_BINS slices of t: the
 * second moments of their offsets in the untwisted frame (the orientation
 * of the cross-section) and how fast the strands wind about the trajectory
 * (numerator and denominator of an r^2-weighted d phase / dt). */
typedef struct twist_bins {
  double w[TWIST_BINS], xx[TWIST_BINS], xy[TWIST_BINS], yy[TWIST_BINS];
  double num[TWIST_BINS], den[TWIST_BINS];
} twist_bins;

static int bin_of(double t) {
  int k = (int)(t * TWIST_BINS);
  return k < 0 ? 0 : k >= TWIST_BINS ? TWIST_BINS - 1 : k;
}

/* Adds a segment's winding (dphi over dt, both weighted) to every bin its
 * t interval overlaps, in proportion to the overlap. */
static void spread_over_bins(double t0, double t1, double dphi, double dt,
                             double *num, double *den) {
  double lo = t0 < t1 ? t0 : t1, hi = t0 < t1 ? t1 : t0;
  for (int k = bin_of(lo); k <= bin_of(hi); k++) {
    double a = fmax(lo, (double)k / TWIST_BINS);
    double b = fmin(hi, (double)(k + 1) / TWIST_BINS);
    double f = hi > lo ? (b - a) / (hi - lo) : 1.0;
    if (f <= 0.0)
      continue;
    num[k] += f * dphi;
    den[k] += f * dt;
  }
}

/* Fills the bins from the raw projection (offsets along the untwisted
 * rotation-minimising normals). A rigid turn of the cross-section turns
 * every point's angle by the same amount, so weighting by r^2 only mutes
 * the points near the trajectory, whose angle is noise. */
static void twist_gather(const satf_import_projection *raw, twist_bins *b) {
  memset(b, 0, sizeof *b);
  for (int i = 0; i < raw->n_strands; i++) {
    const float *q = raw->txy + 3 * raw->offset[i];
    int m = (int)(raw->offset[i + 1] - raw->offset[i]);
    double prev_phase = 0.0, prev_r2 = 0.0, prev_t = 0.0;
    for (int k = 0; k < m; k++) {
      double t = q[3 * k], x = q[3 * k + 1], y = q[3 * k + 2];
      int bin = bin_of(t);
      b->w[bin] += 1.0;
      b->xx[bin] += x * x;
      b->xy[bin] += x * y;
      b->yy[bin] += y * y;
      double phase = atan2(y, x), r2 = x * x + y * y;
      if (k > 0 && fabs(t - prev_t) > 1e-6) {
        double dphi = phase - prev_phase;
        dphi -= SATF_TWO_PI * floor((dphi + SATF_PI) / SATF_TWO_PI);
        double wr = r2 < prev_r2 ? r2 : prev_r2;
        spread_over_bins(prev_t, t, wr * dphi, wr * (t - prev_t), b->num,
                         b->den);
      }
      prev_phase = phase;
      prev_r2 = r2;
      prev_t = t;
    }
  }
}

/* Winding rate per bin; bins no strand segment spans take the rate of the
 * nearest that one does (0 everywhere when none does). */
static void winding_rates(const twist_bins *b, double *rate) {
  int have[TWIST_BINS], any = 0;
  for (int k = 0; k < TWIST_BINS; k++) {
    have[k] = fabs(b->den[k]) > 1e-12;
    rate[k] = have[k] ? b->num[k] / b->den[k] : 0.0;
    any |= have[k];
  }
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
}

/* The principal axis of bin k's spread, in (-pi/2, pi/2], and how far it
 * can be trusted, in [0, 1]. The anisotropy (A^2 - B^2) / (A^2 + B^2) of
 * the spread is 0 for a round cross-section, whose axis means nothing, but
 * w points drawn from a round one show about sqrt(2 / w) by chance; the
 * angle counts not at all below twice that (and below 0.1, axes within
 * 11%) and fully 0.2 above. */
static double bin_axis(const twist_bins *b, int k, double *trust) {
  double xx = b->xx[k], xy = b->xy[k], yy = b->yy[k], tr = xx + yy;
  double aniso = tr > 0.0 ? hypot(xx - yy, 2.0 * xy) / tr : 0.0;
  double noise = b->w[k] > 0.0 ? 2.0 * sqrt(2.0 / b->w[k]) : 1.0;
  double s = (aniso - fmax(0.1, noise)) / 0.2;
  s = s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
  *trust = s * s * (3.0 - 2.0 * s);
  return 0.5 * atan2(2.0 * xy, xx - yy);
}

/* theta at the bin centres, unwrapped along t: each bin starts from the
 * previous one carried forward by the strands' winding, then moves to its
 * own principal axis as far as that can be trusted. An ellipse turned by a
 * quarter turn is the same ellipse with A and B swapped, and A and B are
 * measured afterwards, so the axis is taken modulo pi/2: the branch
 * nearest the prediction, the least turn that explains the points. */
static void twist_at_bins(const twist_bins *b, double *theta) {
  double rate[TWIST_BINS], prev = 0.0;
  winding_rates(b, rate);
  for (int k = 0; k < TWIST_BINS; k++) {
    double pred =
        k == 0 ? 0.0 : prev + 0.5 * (rate[k - 1] + rate[k]) / TWIST_BINS;
    double trust, axis = bin_axis(b, k, &trust);
    double quarter = 0.5 * SATF_PI;
    axis += quarter * floor((pred - axis) / quarter + 0.5);
    theta[k] = pred + trust * (axis - pred);
    prev = theta[k];
  }
}

/* The B-spline with n control values closest in least squares to theta at
 * the bin centres, each bin weighted by its share of the points, plus a
 * penalty on the control values' second divided differences: it keeps the
 * system regular when n exceeds the bins, stops the control values from
 * swinging to chase a few noisy bins (a strand or two per bin in small
 * clusters), and does not bias a linear twist, which it reproduces
 * exactly. */
static void fit_twist_spline(const twist_bins *b, const double *theta, int n,
                             float *twist) {
  double ata[64 * 64] = {0}, atb[64] = {0}, w[64], total = 0.0;
  for (int k = 0; k < TWIST_BINS; k++)
    total += b->w[k];
  for (int k = 0; k < TWIST_BINS; k++) {
    /* empty bins keep a small say, so the curve stays defined there */
    double wk = total > 0.0 ? 0.1 + b->w[k] * TWIST_BINS / total : 1.0;
    basis(n, ((double)k + 0.5) / TWIST_BINS, w);
    for (int i = 0; i < n; i++) {
      for (int j = 0; j < n; j++)
        ata[i * n + j] += wk * w[i] * w[j];
      atb[i] += wk * w[i] * theta[k];
    }
  }
  /* second divided differences over the Greville abscissae: zero for the
   * control values of a linear function, whatever their spacing */
  const double lambda = 1e-3;
  for (int j = 1; j + 1 < n; j++) {
    double h0 = greville(j, n) - greville(j - 1, n);
    double h1 = greville(j + 1, n) - greville(j, n);
    const int idx[3] = {j - 1, j, j + 1};
    const double c[3] = {1.0 / h0, -1.0 / h0 - 1.0 / h1, 1.0 / h1};
    for (int p = 0; p < 3; p++)
      for (int q = 0; q < 3; q++)
        ata[idx[p] * n + idx[q]] += lambda * c[p] * c[q];
  }
  if (solve(ata, atb, n, 1) != 0) /* cannot happen: every bin has weight */
    memset(atb, 0, sizeof atb);
  for (int j = 0; j < n; j++)
    twist[j] = (float)atb[j];
}

/* theta(t) (SATF eq. 1-2, theta turning the cross-section as
 * satf/geometry.h reads it): the orientation of the principal axes of the
 * strands' spread, unwrapped along t, carried by the strands' winding
 * where the cross-section is round. */
static int fit_twist(const satf_import_projection *raw, int n, float *twist) {
  twist_bins *b = malloc(sizeof *b);
  double theta[TWIST_BINS];
  if (!b)
    return -1;
  twist_gather(raw, b);
  twist_at_bins(b, theta);
  fit_twist_spline(b, theta, n, twist);
  free(b);
  return 0;
}

/* The raw offsets turned into the fitted ellipse's axes at each point's t:
 * (x, y) rotated by -theta(t). */
static void to_twisted_axes(const float *raw, size_t np, const float *twist,
                            int n, float *out) {
  for (size_t k = 0; k < np; k++) {
    double t = raw[3 * k], th = spline1(twist, n, t);
    double c = cos(th), s = sin(th), x = raw[3 * k + 1], y = raw[3 * k + 2];
    out[3 * k] = (float)t;
    out[3 * k + 1] = (float)(c * x + s * y);
    out[3 * k + 2] = (float)(-s * x + c * y);
  }
}

/* ---- The whole fit ----------------------------------------------------- */

/* v of every point in the fitted envelope (offsets in the ellipse's axes). */
static void envelope_v(const float *txy, size_t np, const satf_import_fit *f,
                       float *v) {
  for (size_t k = 0; k < np; k++) {
    double t = txy[3 * k];
    double x = txy[3 * k + 1] / spline1(f->a, f->n_radius, t);
    double y = txy[3 * k + 2] / spline1(f->b, f->n_radius, t);
    v[k] = (float)sqrt(x * x + y * y);
  }
}

/* One common scale makes the envelope enclose `coverage` of the points;
 * then the floor min_radius. Sets out->inside. */
static satf_status scale_envelope(const float *txy, size_t np,
                                  const satf_import_fit_params *p,
                                  satf_import_fit *out, satf_error *err) {
  float *v = malloc((np ? np : 1) * sizeof(float));
  float *sorted = malloc((np ? np : 1) * sizeof(float));
  if (!v || !sorted) {
    free(v);
    free(sorted);
    return satf_error_set(err, SATF_ERR_NOMEM, "fit: out of memory");
  }
  envelope_v(txy, np, out, v);
  float scale = 1.0f;
  if (np > 0) {
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
  if (p->min_radius > 0.0f) /* the floor may have grown the envelope */
    envelope_v(txy, np, out, v);
  else
    for (size_t k = 0; k < np; k++)
      v[k] /= scale;
  size_t inside = 0;
  for (size_t k = 0; k < np; k++)
    inside += v[k] <= 1.0f;
  out->inside = inside;
  free(v);
  return SATF_OK;
}

void satf_import_percentiles(float *v, size_t n, float out[3]) {
  if (n == 0) {
    out[0] = out[1] = out[2] = 0.0f;
    return;
  }
  qsort(v, n, sizeof(float), cmp_float);
  out[0] = v[(n - 1) / 2];
  out[1] = v[(size_t)floor(0.9 * (double)(n - 1) + 0.5)];
  out[2] = v[n - 1];
}

/* The fit measures (satf_import_fit_measures) of the finished envelope:
 * offsets rot in the ellipse's axes, dist the points' distances to T(t). */
static satf_status fit_measures(const float *rot, const float *dist, size_t np,
                                int n_strands, satf_import_fit *f,
                                satf_error *err) {
  satf_import_fit_measures *m = &f->measures;
  float *surf = malloc((np ? np : 1) * sizeof(float));
  float *out = malloc((np ? np : 1) * sizeof(float));
  float *tr = malloc((np ? np : 1) * sizeof(float));
  if (!surf || !out || !tr) {
    free(surf);
    free(out);
    free(tr);
    return satf_error_set(err, SATF_ERR_NOMEM, "fit: out of memory");
  }
  for (size_t k = 0; k < np; k++) {
    double t = rot[3 * k];
    double x = rot[3 * k + 1], y = rot[3 * k + 2];
    double a = spline1(f->a, f->n_radius, t), b = spline1(f->b, f->n_radius, t);
    double r = sqrt(x * x + y * y);
    double v = sqrt((x / a) * (x / a) + (y / b) * (y / b));
    /* the envelope along the point's ray lies at r / v; at the trajectory
     * itself (r = 0) the nearest envelope point is the minor half-axis */
    double edge = v > 1e-12 ? r / v : fmin(a, b);
    surf[k] = (float)fabs(r - edge);
    out[k] = (float)(r > edge ? r - edge : 0.0);
    tr[k] = dist[k];
  }
  satf_import_percentiles(surf, np, m->surface);
  satf_import_percentiles(out, np, m->outside);
  satf_import_percentiles(tr, np, m->trajectory);
  free(surf);
  free(out);
  free(tr);
  /* area and diameter over 32 evenly spaced t */
  double area = 0.0, big = 0.0;
  for (int k = 0; k < 32; k++) {
    double t = (k + 0.5) / 32.0;
    double a = spline1(f->a, f->n_radius, t), b = spline1(f->b, f->n_radius, t);
    area += SATF_PI * a * b;
    big += a > b ? a : b;
  }
  m->area_per_strand = (float)(area / 32.0 / (n_strands > 0 ? n_strands : 1));
  m->diameter = (float)(2.0 * big / 32.0);
  m->aspect = m->diameter > 0.0f ? f->length / m->diameter : 0.0f;
  return SATF_OK;
}

/* The angle of each strand segment to the trajectory, in degrees (p50,
 * p90, max into out), from the untwisted offsets (t, x, y) of its two
 * points: the rotation-minimising frame turns with the trajectory, so
 * (dx, dy) is the segment's run across it and dt times the length its run
 * along it (a segment running back along t is over 90 degrees). */
static satf_status fit_direction(const satf_import_projection *raw,
                                 double length, float out[3], satf_error *err) {
  size_t np = raw->offset[raw->n_strands], n = 0;
  float *angle = malloc((np ? np : 1) * sizeof(float));
  if (!angle)
    return satf_error_set(err, SATF_ERR_NOMEM, "fit: out of memory");
  for (int i = 0; i < raw->n_strands; i++)
    for (size_t k = raw->offset[i]; k + 1 < raw->offset[i + 1]; k++) {
      const float *a = raw->txy + 3 * k, *b = a + 3;
      double along = (double)(b[0] - a[0]) * length;
      double across = hypot((double)(b[1] - a[1]), (double)(b[2] - a[2]));
      if (along != 0.0 || across > 0.0)
        angle[n++] = (float)(atan2(across, along) * (180.0 / SATF_PI));
    }
  out[0] = out[1] = out[2] = 0.0f;
  if (n > 0)
    satf_import_percentiles(angle, n, out);
  free(angle);
  return SATF_OK;
}

/* A fur sheet's strands lie side by side, flat on the surface, and do not
 * wind about its axis: one theta for the whole sheet, the principal axis
 * of all its points' offsets. Per bin (fit_twist) a tuft of 50 strands has
 * 6 points, too few to trust an axis, and the winding of strands that
 * cross the axis sideways turned the sheet by 98 degrees on average over
 * its length (generated fur), a twisted ribbon whose hair directions
 * (dP/dt, SATF eq. 1) curve into arcs. */
static void sheet_twist(const float *txy, size_t np, int n, float *twist) {
  double xx = 0.0, xy = 0.0, yy = 0.0;
  for (size_t k = 0; k < np; k++) {
    double x = txy[3 * k + 1], y = txy[3 * k + 2];
    xx += x * x;
    xy += x * y;
    yy += y * y;
  }
  float theta = (float)(0.5 * atan2(2.0 * xy, xx - yy));
  for (int j = 0; j < n; j++)
    twist[j] = theta;
}

/* How fast a fur sheet's A and B may change along it, per unit length:
 * the renderer draws the hair along dP/dt (SATF eq. 1), which tilts by
 * atan(dA/ds) at the envelope's edge, so a sheet tapering as its strands
 * thin out (up to 42 degrees on generated fur, 57 at a tuft's tip) was
 * drawn with strands converging into arcs where its real strands lie side
 * by side. The envelope stays as wide as its strands' density needs (the
 * tracks leave it empty where they end). */
#define SHEET_SLOPE 0.15

/* v[j] raised to max over i of v[i] - step |g_j - g_i| (g the Greville
 * abscissae): the least raise that keeps every value and changes by at
 * most step per unit t between control values. */
static void limit_slope(float *v, int n, double step) {
  float tmp[64];
  for (int j = 0; j < n; j++) {
    double best = v[j];
    for (int i = 0; i < n; i++)
      best = fmax(best, v[i] - step * fabs(greville(j, n) - greville(i, n)));
    tmp[j] = (float)best;
  }
  memcpy(v, tmp, (size_t)n * sizeof(float));
}

/* The cross-section of a fit whose trajectory is known: theta(t) from the
 * raw offsets, then A(t), B(t) in the ellipse's axes, scaled for
 * coverage. The spread stays in the untwisted frame (satf/import.h). */
static satf_status fit_section(const satf_import_projection *raw,
                               const float *dist,
                               const satf_import_fit_params *p, int sheet,
                               satf_import_fit *out, satf_error *err) {
  size_t np = raw->offset[raw->n_strands];
  float *rot = calloc((np ? np : 1) * 3, sizeof(float));
  basis_moments *m = malloc(sizeof *m);
  if (!rot || !m) {
    free(rot);
    free(m);
    return satf_error_set(err, SATF_ERR_NOMEM, "fit: out of memory");
  }
  moments_gather(raw->txy, np, p->n_radius, m);
  moments_spread(m, p->n_radius, out->spread);
  if (sheet)
    sheet_twist(raw->txy, np, p->n_radius, out->twist);
  else if (fit_twist(raw, p->n_radius, out->twist) != 0) {
    free(rot);
    free(m);
    return satf_error_set(err, SATF_ERR_NOMEM, "fit: out of memory");
  }
  to_twisted_axes(raw->txy, np, out->twist, p->n_radius, rot);
  moments_gather(rot, np, p->n_radius, m);
  fit_axes(m, p->n_radius, 1e-3f * out->length, out->a, out->b);
  free(m);
  if (sheet) {
    limit_slope(out->a, p->n_radius, SHEET_SLOPE * out->length);
    limit_slope(out->b, p->n_radius, SHEET_SLOPE * out->length);
  }
  satf_status st = scale_envelope(rot, np, p, out, err);
  if (st == SATF_OK)
    st = fit_measures(rot, dist, np, raw->n_strands, out, err);
  /* a tuft is drawn as its strands, each along itself */
  if (st == SATF_OK && !sheet)
    st = fit_direction(raw, out->length, out->measures.direction, err);
  free(rot);
  return st;
}

/* How wide a patch the roots cover across the direction dir (unit): twice
 * the largest distance of a root from the roots' mean, across dir. */
static double root_width(const satf_strand_set *s, const int *members, int n,
                         const double *dir) {
  double mid[3] = {0.0, 0.0, 0.0}, far2 = 0.0;
  for (int i = 0; i < n; i++) {
    int np;
    const float *q = satf_strand_set_strand(s, members[i], &np);
    for (int c = 0; c < 3; c++)
      mid[c] += q[c] / n;
  }
  for (int i = 0; i < n; i++) {
    int np;
    const float *q = satf_strand_set_strand(s, members[i], &np);
    double d[3], u = 0.0, d2 = 0.0;
    for (int c = 0; c < 3; c++) {
      d[c] = q[c] - mid[c];
      u += d[c] * dir[c];
    }
    for (int c = 0; c < 3; c++)
      d2 += (d[c] - u * dir[c]) * (d[c] - u * dir[c]);
    far2 = d2 > far2 ? d2 : far2;
  }
  return 2.0 * sqrt(far2);
}

/* How well the members run along dir (unit): the mean over them of the
 * cosine between their chord (root to tip) and dir. */
static double alignment(const satf_strand_set *s, const int *members, int n,
                        const double *dir) {
  double sum = 0.0;
  for (int i = 0; i < n; i++) {
    int np;
    const float *q = satf_strand_set_strand(s, members[i], &np);
    double d[3], l2 = 0.0, dot = 0.0;
    for (int c = 0; c < 3; c++) {
      d[c] = q[3 * (np - 1) + c] - q[c];
      l2 += d[c] * d[c];
      dot += d[c] * dir[c];
    }
    sum += l2 > 0.0 ? dot / sqrt(l2) : 0.0;
  }
  return n > 0 ? sum / n : 0.0;
}

/* A tuft's axis: the least-squares parabola (3 control points) through
 * all its member points at their places along the flow, or the line when
 * the parabola turns by more than TUFT_TURN degrees from end to end. A
 * cubic hooked at the ends, where few points pin it down; a generalized
 * cylinder bent tighter than its half-width folds over itself there
 * (dP/dt reversed at the envelope's inner side), and the tracks rebuilt
 * about such an axis turned by more than 30 degrees between slices: 1.7%
 * of generated fur's (cubic) against 0.2% (parabola). A fur patch's
 * strands turn by about 20 degrees across it (gen-strands.py's swirls). */
#define TUFT_CTRL 3
#define TUFT_TURN 30.0

/* The angle, in degrees, between the first and last legs of a control
 * polygon of n points (the end tangents of its B-spline). */
static double end_turn(const float *ctrl, int n) {
  double d0[3], d1[3], dot = 0.0, l0 = 0.0, l1 = 0.0;
  for (int c = 0; c < 3; c++) {
    d0[c] = ctrl[3 + c] - ctrl[c];
    d1[c] = ctrl[3 * (n - 1) + c] - ctrl[3 * (n - 2) + c];
    dot += d0[c] * d1[c];
    l0 += d0[c] * d0[c];
    l1 += d1[c] * d1[c];
  }
  double cs = l0 > 0.0 && l1 > 0.0 ? dot / sqrt(l0 * l1) : 1.0;
  return acos(cs > 1.0 ? 1.0 : cs < -1.0 ? -1.0 : cs) * 180.0 / SATF_PI;
}

/* Fur: short, nearly straight strands lying side by side (a patch of a
 * pelt), a sheet. Returns 1 when the members are one: their mean strand is
 * straight (chord over length > 0.8), their roots cover a patch wider
 * across its direction than it is long, and they run along it (the mean
 * cosine of their chords to it > SHEET_ALIGN). Without the width test the
 * long strands of a ponytail's crown, whose roots spread along their flow
 * towards the tie (across it 0.06 to 3.5 times a strand's length, median
 * 0.5), became tufts (86 of its clusters had axes turning back on
 * themselves); without the alignment, early clusters of Bangs_100's
 * strands, swept different ways over the scalp, became sheets, which
 * changed how they were split and left its single strands with fewer
 * control points (trajectory p90 0.10 -> 0.13). Generated fur's 4-point
 * strands have roots across 1.7 to 14 times their length (median 3.5).
 *
 * The mean strand of a sheet is one strand long while the patch may be
 * longer than that along the flow: when the points reach at least 1.25
 * times as far along the direction as the mean strand is long, the m
 * points of `mean` are replaced by samples of the axis through all the
 * points from the first roots to the last tips (a tuft lying along the
 * surface). It was the means of the points binned along the direction,
 * but bins hold different strands side by side: the 16 means zigzagged
 * sideways by a third of the tuft's width, and the tracks about that axis
 * turned by 145 degrees between slices (median, generated fur). */
#define SHEET_ALIGN 0.95

static int tuft_axis(const satf_strand_set *s, const int *members, int n, int m,
                     double *mean) {
  double dir[3], len = 0.0, chord = 0.0;
  for (int c = 0; c < 3; c++)
    dir[c] = mean[3 * (m - 1) + c] - mean[c];
  for (int k = 1; k < m; k++) {
    double d2 = 0.0;
    for (int c = 0; c < 3; c++)
      d2 += (mean[3 * k + c] - mean[3 * k - 3 + c]) *
            (mean[3 * k + c] - mean[3 * k - 3 + c]);
    len += sqrt(d2);
  }
  chord = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  if (n < 2 || !(chord > 0.8 * len) || !(chord > 0.0))
    return 0;
  for (int c = 0; c < 3; c++)
    dir[c] /= chord;
  if (!(root_width(s, members, n, dir) > len) ||
      !(alignment(s, members, n, dir) > SHEET_ALIGN))
    return 0;
  double lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < n; i++) {
    int np;
    const float *q = satf_strand_set_strand(s, members[i], &np);
    for (int k = 0; k < np; k++) {
      double u =
          q[3 * k] * dir[0] + q[3 * k + 1] * dir[1] + q[3 * k + 2] * dir[2];
      lo = u < lo ? u : lo;
      hi = u > hi ? u : hi;
    }
  }
  if (!(hi - lo >= 1.25 * len))
    return 1;
  /* every member point at its place along the direction, in [0, 1] */
  size_t np_all = 0;
  for (int i = 0; i < n; i++) {
    int np;
    satf_strand_set_strand(s, members[i], &np);
    np_all += (size_t)np;
  }
  double *pts = malloc(3 * np_all * sizeof(double));
  double *u = malloc(np_all * sizeof(double));
  float ctrl[3 * TUFT_CTRL];
  if (pts && u) {
    size_t k = 0;
    for (int i = 0; i < n; i++) {
      int np;
      const float *q = satf_strand_set_strand(s, members[i], &np);
      for (int j = 0; j < np; j++, k++) {
        for (int c = 0; c < 3; c++)
          pts[3 * k + c] = q[3 * j + c];
        u[k] = (q[3 * j] * dir[0] + q[3 * j + 1] * dir[1] +
                q[3 * j + 2] * dir[2] - lo) /
               (hi - lo);
      }
    }
    int nc = TUFT_CTRL, bad = fit_bspline_at(pts, u, (int)np_all, nc, ctrl);
    if (!bad && end_turn(ctrl, nc) > TUFT_TURN)
      bad = fit_bspline_at(pts, u, (int)np_all, nc = 2, ctrl);
    if (!bad)
      for (int k2 = 0; k2 < m; k2++) {
        double v[3];
        satf_bspline_eval(ctrl, nc, 3, (double)k2 / (m - 1), v, NULL, NULL);
        for (int c = 0; c < 3; c++)
          mean[3 * k2 + c] = v[c];
      }
  }
  free(pts);
  free(u);
  return 1;
}

/* How far before the mean root the mean strand may reach back, as a share
 * of its length: where the strands of a cluster begin at about one place,
 * its roots' spread along the flow (a curtain's: 1.5%); where they begin
 * along a surface they lie on (fur, a crown), the cluster starts near
 * where most of them do, not under the skin behind the first (unbounded,
 * 12 of the generated fur's 230 shell clusters turned their hair at the
 * envelope more than 15 degrees off the axis, over the 5% that
 * test_fur_runs_along_strands allows; 5 at this bound). */
#define ROOT_REACH 0.05

/* Reverses the order of m points. */
static void reverse_points(double *pts, int m) {
  for (int a = 0, b = m - 1; a < b; a++, b--)
    for (int c = 0; c < 3; c++) {
      double t = pts[3 * a + c];
      pts[3 * a + c] = pts[3 * b + c];
      pts[3 * b + c] = t;
    }
}

/* The mean strand ends where the members' tips do on average, so the
 * longer half of them ran past t = 1, where the shells stop: their ends
 * were cut square at the mean length and the last slice of the tracks
 * counted them all (SATF sec. 3.3 wants the density where the strands
 * are). So the mean strand (m points, evenly spaced in arc length) is
 * continued along its end direction to the farthest member tip (at most
 * half its length further: a stray strand stays outside), then spaced
 * evenly again; t = 1 is then the last tip, and the tracks thin out to
 * it as the members end. The same at the roots (from_root): the mean
 * root lies among the members' roots, and the half of them that begin
 * before it were cut square at t = 0 (a curtain's top rows, 5 pixels of
 * its 20K strands at 640 x 480, missing against Cycles); continued back
 * to the first root, t = 0 is where the first strand begins. */
static void reach_farthest(const satf_strand_set *s, const int *members,
                           int n_members, int m, double *mean, int roots) {
  const double *end = mean + 3 * (m - 1);
  const double *back = mean + 3 * (m - 1 - (m - 1) / 8);
  double dir[3] = {end[0] - back[0], end[1] - back[1], end[2] - back[2]};
  double dl = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  double length = 0.0;
  for (int k = 1; k < m; k++) {
    const double *a = mean + 3 * (k - 1), *b = mean + 3 * k;
    length +=
        sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
             (b[2] - a[2]) * (b[2] - a[2]));
  }
  if (!(dl > 1e-9 * length) || !(length > 0.0))
    return;
  double reach = 0.0;
  for (int i = 0; i < n_members; i++) {
    int n;
    const float *p = satf_strand_set_strand(s, members[i], &n);
    const float *tip = roots ? p : p + 3 * (n - 1);
    double d = ((tip[0] - end[0]) * dir[0] + (tip[1] - end[1]) * dir[1] +
                (tip[2] - end[2]) * dir[2]) /
               dl;
    reach = d > reach ? d : reach;
  }
  reach = fmin(reach, (roots ? ROOT_REACH : 0.5) * length);
  if (!(reach > 1e-3 * length))
    return;
  double *old = malloc(3 * (size_t)m * sizeof(double));
  if (!old) /* the mean strand as it is: square ends, nothing worse */
    return;
  memcpy(old, mean, 3 * (size_t)m * sizeof(double));
  double total = length + reach, seg_start = 0.0;
  int seg = 0;
  for (int k = 0; k < m; k++) {
    double a = total * (double)k / (double)(m - 1);
    double *o = mean + 3 * k;
    if (a >= length) { /* along the end direction, past the old end */
      for (int c = 0; c < 3; c++)
        o[c] = old[3 * (m - 1) + c] + (a - length) * dir[c] / dl;
      continue;
    }
    for (;;) {
      const double *p0 = old + 3 * seg, *p1 = p0 + 3;
      double len = sqrt((p1[0] - p0[0]) * (p1[0] - p0[0]) +
                        (p1[1] - p0[1]) * (p1[1] - p0[1]) +
                        (p1[2] - p0[2]) * (p1[2] - p0[2]));
      if (seg_start + len >= a || seg == m - 2) {
        double f = len > 0.0 ? (a - seg_start) / len : 0.0;
        f = f < 0.0 ? 0.0 : f > 1.0 ? 1.0 : f;
        for (int c = 0; c < 3; c++)
          o[c] = p0[c] + f * (p1[c] - p0[c]);
        break;
      }
      seg_start += len;
      seg++;
    }
  }
  free(old);
}

/* reach_farthest at the tips, or (from_root) at the roots: the mean
 * strand reversed, reached back, and turned round again. */
static void reach_end(const satf_strand_set *s, const int *members,
                      int n_members, int m, double *mean, int from_root) {
  if (m < 4)
    return;
  if (from_root)
    reverse_points(mean, m);
  reach_farthest(s, members, n_members, m, mean, from_root);
  if (from_root)
    reverse_points(mean, m);
}

/* The least-squares cubic B-spline through the members' mean strand, each
 * strand resampled to p->samples points. */
static satf_status fit_mean_trajectory(const satf_strand_set *s,
                                       const int *members, int n_members,
                                       const satf_import_fit_params *p,
                                       float *traj, int *sheet,
                                       satf_error *err) {
  int m = p->samples;
  double *mean = calloc(3 * (size_t)m, sizeof(double));
  float *buf = malloc(3 * (size_t)m * sizeof(float));
  if (!mean || !buf) {
    free(mean);
    free(buf);
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
  *sheet = tuft_axis(s, members, n_members, m, mean);
  if (!*sheet) {
    reach_end(s, members, n_members, m, mean, 0);
    reach_end(s, members, n_members, m, mean, 1);
  }
  /* the control points stay near the points they fit: a B-spline with
   * more control points than the data pins down swings far out (and the
   * scene's camera frames it); then half as many, down to 4 */
  double lo[3] = {INFINITY, INFINITY, INFINITY},
         hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int k = 0; k < m; k++)
    for (int c = 0; c < 3; c++) {
      lo[c] = fmin(lo[c], mean[3 * k + c]);
      hi[c] = fmax(hi[c], mean[3 * k + c]);
    }
  double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                     (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (hi[2] - lo[2]) * (hi[2] - lo[2]));
  int bad = 1, want = p->n_ctrl;
  for (int n = want; n >= 2; n = n > 4 ? n / 2 : n - 1) {
    bad = fit_trajectory(mean, m, n, traj);
    int wild = 0;
    for (int k = 0; !bad && k < 3 * n; k++) {
      double g = 0.5 * diag + 1e-6;
      wild |= traj[k] < lo[k % 3] - g || traj[k] > hi[k % 3] + g;
    }
    if (bad || (wild && n > 4))
      continue;
    if (n < want) {
      /* the calm curve of n control points, sampled evenly and fitted
       * again with the count asked for (keyframes of a sequence and the
       * scene need every fit of a cluster to keep its count): smooth dense
       * samples pin every control point down */
      for (int k = 0; k < m; k++) {
        double v[3];
        satf_bspline_eval(traj, n, 3, (double)k / (m - 1), v, NULL, NULL);
        for (int c = 0; c < 3; c++)
          mean[3 * k + c] = v[c];
      }
      bad = fit_trajectory_u(mean, m, want, 1, traj);
    }
    break;
  }
  free(mean);
  if (bad)
    return satf_error_set(err, SATF_ERR_INTERNAL,
                          "fit: the trajectory's least-squares system is "
                          "singular");
  return SATF_OK;
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
  out->core = 0.4f; /* until satf_import_estimate_density measures it */
  out->traj = malloc(3 * (size_t)p->n_ctrl * sizeof(float));
  out->a = malloc((size_t)p->n_radius * sizeof(float));
  out->b = malloc((size_t)p->n_radius * sizeof(float));
  out->twist = calloc((size_t)p->n_radius, sizeof(float));
  out->spread = calloc(3 * (size_t)p->n_radius, sizeof(float));
  if (!out->traj || !out->a || !out->b || !out->twist || !out->spread) {
    satf_import_fit_free(out);
    return satf_error_set(err, SATF_ERR_NOMEM, "fit: out of memory");
  }
  out->n_ctrl = p->n_ctrl;
  out->n_radius = p->n_radius;
  int sheet = 0;
  satf_status st =
      fit_mean_trajectory(s, members, n_members, p, out->traj, &sheet, err);
  /* A provisional cylinder of unit radius and no twist gives the untwisted
   * rotation-minimising frames the raw offsets are measured in. */
  float one = 1.0f, zero = 0.0f;
  satf_cluster_desc d = {out->n_ctrl, out->traj, 1, &one, &one, &zero};
  satf_cluster *cl = NULL;
  if (st == SATF_OK)
    st = satf_cluster_create(&d, &cl, err);
  satf_import_projection raw;
  memset(&raw, 0, sizeof raw);
  float *dist = NULL;
  if (st == SATF_OK) {
    out->length = satf_cluster_length(cl);
    st = project_all(s, members, n_members, cl, 0, &raw, &dist, err);
  }
  satf_cluster_destroy(cl);
  if (st == SATF_OK)
    st = fit_section(&raw, dist, p, sheet, out, err);
  if (st == SATF_OK) {
    size_t np = raw.offset[n_members];
    double dsum = 0.0, ma = 0.0, mb = 0.0;
    for (size_t k = 0; k < np; k++)
      dsum += dist[k];
    for (int j = 0; j < p->n_radius; j++) {
      ma += out->a[j];
      mb += out->b[j];
    }
    out->strands = n_members;
    out->points = np;
    out->distance_sum = dsum;
    out->strand_width = 0.05f;
    out->radius = (float)sqrt(ma * mb) / (float)p->n_radius;
    out->layout = SATF_SCENE_LAYOUT_UNIFORM;
  }
  free(dist);
  satf_import_projection_free(&raw);
  if (st != SATF_OK)
    satf_import_fit_free(out);
  return st;
}
