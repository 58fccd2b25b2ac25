/* import_macro.c - macro-clusters (SATF sec. 3.1): clusters whose shapes
 * agree after a similarity transform (uniform scale, rotation,
 * translation) are stored once, as a prototype plus one transform per
 * instance. Shapes are compared through the trajectory (samples along t,
 * aligned by Horn's closed-form absolute orientation) and the spread of the
 * strands in the normal plane as a 3-D second-moment tensor, which does not
 * depend on the rotation-minimising frame each fit happened to start
 * from. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "import_internal.h"
#include "satf/geometry.h"

#define SAMPLES 16

/* Eigenvector of the largest eigenvalue of a symmetric 4x4 matrix, by
 * cyclic Jacobi rotations. */
static void max_eigenvector4(double a[4][4], double out[4]) {
  double v[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  for (int sweep = 0; sweep < 50; sweep++) {
    double off = 0.0;
    for (int p = 0; p < 4; p++)
      for (int q = p + 1; q < 4; q++)
        off += a[p][q] * a[p][q];
    if (off < 1e-30)
      break;
    for (int p = 0; p < 4; p++)
      for (int q = p + 1; q < 4; q++) {
        if (fabs(a[p][q]) < 1e-300)
          continue;
        double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        double t = (theta >= 0 ? 1.0 : -1.0) /
                   (fabs(theta) + sqrt(theta * theta + 1.0));
        double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 4; k++) { /* a = J^T a J */
          double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 4; k++) {
          double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 4; k++) {
          double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  int best = 0;
  for (int k = 1; k < 4; k++)
    if (a[k][k] > a[best][best])
      best = k;
  for (int k = 0; k < 4; k++)
    out[k] = v[k][best];
}

/* Horn, "Closed-form solution of absolute orientation using unit
 * quaternions", JOSA A 4(4), 1987, with Umeyama's least-squares scale. */
double satf_import_similarity(const double *from, const double *to, int n,
                              double m[16]) {
  double cf[3] = {0, 0, 0}, ct[3] = {0, 0, 0};
  for (int i = 0; i < n; i++)
    for (int c = 0; c < 3; c++) {
      cf[c] += from[3 * i + c] / n;
      ct[c] += to[3 * i + c] / n;
    }
  double s[3][3] = {{0}}, var = 0.0;
  for (int i = 0; i < n; i++) {
    double x[3], y[3];
    for (int c = 0; c < 3; c++) {
      x[c] = from[3 * i + c] - cf[c];
      y[c] = to[3 * i + c] - ct[c];
      var += x[c] * x[c];
    }
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        s[r][c] += x[r] * y[c];
  }
  double N[4][4] = {{s[0][0] + s[1][1] + s[2][2], s[1][2] - s[2][1],
                     s[2][0] - s[0][2], s[0][1] - s[1][0]},
                    {s[1][2] - s[2][1], s[0][0] - s[1][1] - s[2][2],
                     s[0][1] + s[1][0], s[2][0] + s[0][2]},
                    {s[2][0] - s[0][2], s[0][1] + s[1][0],
                     -s[0][0] + s[1][1] - s[2][2], s[1][2] + s[2][1]},
                    {s[0][1] - s[1][0], s[2][0] + s[0][2], s[1][2] + s[2][1],
                     -s[0][0] - s[1][1] + s[2][2]}};
  double q[4];
  max_eigenvector4(N, q);
  double w = q[0], x = q[1], y = q[2], z = q[3];
  double R[3][3] = {
      {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
      {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
      {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  double num = 0.0;
  for (int i = 0; i < n; i++) {
    double xr[3] = {0, 0, 0};
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        xr[r] += R[r][c] * (from[3 * i + c] - cf[c]);
    for (int c = 0; c < 3; c++)
      num += xr[c] * (to[3 * i + c] - ct[c]);
  }
  double scale = var > 0.0 ? num / var : 1.0;
  if (!(scale > 0.0))
    scale = 1.0;
  memset(m, 0, 16 * sizeof(double));
  for (int r = 0; r < 3; r++) {
    double rc = 0.0;
    for (int c = 0; c < 3; c++) {
      m[4 * r + c] = scale * R[r][c];
      rc += R[r][c] * cf[c];
    }
    m[4 * r + 3] = ct[r] - scale * rc;
  }
  m[15] = 1.0;
  double res = 0.0;
  for (int i = 0; i < n; i++)
    for (int r = 0; r < 3; r++) {
      double p = m[4 * r + 3];
      for (int c = 0; c < 3; c++)
        p += m[4 * r + c] * from[3 * i + c];
      res += (p - to[3 * i + r]) * (p - to[3 * i + r]);
    }
  return n > 0 ? sqrt(res / n) : 0.0;
}

/* What the comparison needs of one fit: trajectory samples and the spread
 * tensors in world space at the same t. */
typedef struct shape {
  double pos[SAMPLES * 3];
  double spread[SAMPLES][3][3];
  double length;
} shape;

static satf_status make_shape(const satf_import_fit *f, shape *s,
                              satf_error *err) {
  satf_cluster *cl;
  satf_status st = satf_import_fit_cluster_create(f, &cl, err);
  if (st != SATF_OK)
    return st;
  s->length = satf_cluster_length(cl);
  for (int k = 0; k < SAMPLES; k++) {
    float t = (float)k / (SAMPLES - 1), p[3], tan[3], n1[3], n2[3];
    satf_cluster_trajectory(cl, t, p, NULL);
    satf_cluster_frame(cl, t, tan, n1, n2);
    double sp[3]; /* the moments follow the same B-spline as A and B */
    satf_bspline_eval(f->spread, f->n_radius, 3, t, sp, NULL, NULL);
    double xx = sp[0], xy = sp[1], yy = sp[2];
    for (int r = 0; r < 3; r++) {
      s->pos[3 * k + r] = p[r];
      for (int c = 0; c < 3; c++)
        s->spread[k][r][c] = xx * n1[r] * n1[c] +
                             xy * (n1[r] * n2[c] + n2[r] * n1[c]) +
                             yy * n2[r] * n2[c];
    }
  }
  satf_cluster_destroy(cl);
  return SATF_OK;
}

/* Relative mismatch of the spread of `to` and the spread of `from` carried
 * by m (s^2 R C R^T): Frobenius norm of the difference over that of `to`'s
 * spread, averaged over t (second moments of a few hundred strands carry
 * some 10% sampling noise, so the worst sample would reject true copies). */
static double spread_mismatch(const shape *from, const shape *to,
                              const double m[16]) {
  double sum = 0.0;
  for (int k = 0; k < SAMPLES; k++) {
    double mc[3][3] = {{0}}, out[3][3] = {{0}};
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        for (int e = 0; e < 3; e++)
          mc[r][c] += m[4 * r + e] * from->spread[k][e][c];
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        for (int e = 0; e < 3; e++)
          out[r][c] += mc[r][e] * m[4 * c + e];
    double diff = 0.0, norm = 0.0;
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) {
        double d = out[r][c] - to->spread[k][r][c];
        diff += d * d;
        norm += to->spread[k][r][c] * to->spread[k][r][c];
      }
    sum += norm > 0.0 ? sqrt(diff / norm) : (diff > 0.0 ? 1e9 : 0.0);
  }
  return sum / SAMPLES;
}

void satf_import_macro_free(satf_import_macro *m) {
  if (m) {
    free(m->prototype);
    free(m->macro_of);
    free(m->transform);
    free(m->residual);
    memset(m, 0, sizeof *m);
  }
}

/* A cluster of few strands, or a tuft of short ones, is drawn as its
 * strands (satf_scene_tracks_as_strands): a transform of another cluster
 * within the tolerance (a few per cent of its length) would move each
 * strand by several of its widths, and the other's strands are not its
 * own, so it stays a prototype of its own. */
static int sparse(const satf_import_fit *f) {
  return f->strands <= SATF_SCENE_SPARSE_STRANDS ||
         satf_scene_tracks_as_strands(f->track_slices, f->n_tracks,
                                      f->track_count,
                                      SATF_SCENE_SPARSE_STRANDS);
}

static size_t cluster_bytes(const satf_import_fit *f) {
  return (3 * (size_t)f->n_ctrl + 3 * (size_t)f->n_radius) * sizeof(float);
}

satf_status satf_import_find_macro(const satf_import_fit *fits, int n,
                                   float tolerance,
                                   satf_import_progress_fn progress,
                                   void *progress_ctx, satf_import_macro *out,
                                   satf_error *err) {
  memset(out, 0, sizeof *out);
  if (n < 1 || !isfinite(tolerance))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "macro-clusters: %d clusters, tolerance %g", n,
                          (double)tolerance);
  shape *shapes = malloc((size_t)n * sizeof *shapes);
  out->prototype = malloc((size_t)n * sizeof(int));
  out->macro_of = malloc((size_t)n * sizeof(int));
  out->transform = calloc((size_t)n * 16, sizeof(float));
  out->residual = calloc((size_t)n, sizeof(float));
  if (!shapes || !out->prototype || !out->macro_of || !out->transform ||
      !out->residual) {
    free(shapes);
    satf_import_macro_free(out);
    return satf_error_set(err, SATF_ERR_NOMEM, "macro-clusters: out of memory");
  }
  out->n_clusters = n;
  satf_status st = SATF_OK;
  for (int c = 0; c < n && st == SATF_OK; c++)
    st = make_shape(&fits[c], &shapes[c], err);
  if (st != SATF_OK) {
    free(shapes);
    satf_import_macro_free(out);
    return st;
  }
  for (int c = 0; c < n; c++)
    out->macro_of[c] = -1;
  for (int p = 0; p < n; p++) {
    if (progress && (p % 64 == 63 || p == n - 1))
      progress(progress_ctx, (size_t)p + 1, (size_t)n);
    if (out->macro_of[p] >= 0)
      continue;
    int id = out->n_macro++;
    out->prototype[id] = p;
    out->macro_of[p] = id;
    float *mp = out->transform + 16 * (size_t)p;
    mp[0] = mp[5] = mp[10] = mp[15] = 1.0f;
    out->bytes_shared += cluster_bytes(&fits[p]);
    if (tolerance <= 0.0f || sparse(&fits[p]))
      continue;
    for (int c = p + 1; c < n; c++) {
      if (out->macro_of[c] >= 0 || sparse(&fits[c]))
        continue;
      double m[16];
      double rms =
          satf_import_similarity(shapes[p].pos, shapes[c].pos, SAMPLES, m);
      /* measured in the prototype's units: the residual shrinks with it */
      double scale = cbrt(fabs(m[0] * (m[5] * m[10] - m[6] * m[9]) -
                               m[1] * (m[4] * m[10] - m[6] * m[8]) +
                               m[2] * (m[4] * m[9] - m[5] * m[8])));
      double rel = rms / (scale * shapes[p].length);
      if (!(rel <= tolerance))
        continue;
      if (!(spread_mismatch(&shapes[p], &shapes[c], m) <= 6.0 * tolerance))
        continue;
      out->macro_of[c] = id;
      out->residual[c] = (float)rel;
      for (int k = 0; k < 16; k++)
        out->transform[16 * (size_t)c + k] = (float)m[k];
      out->bytes_shared += 12 * sizeof(float);
    }
  }
  for (int c = 0; c < n; c++)
    out->bytes_separate += cluster_bytes(&fits[c]);
  free(shapes);
  return SATF_OK;
}
