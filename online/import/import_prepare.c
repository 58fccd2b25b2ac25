/* import_prepare.c - strands turned into the scene's axes and cleaned of
 * what no generalized cylinder fits: real files hold strands whose points
 * all coincide (a 48 K-strand fur has hundreds), which would give a cluster
 * a trajectory of no length. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "import_prepare.h"
#include "satf/common.h"
#include "satf/math.h"

static void identity(float m[16]) {
  memset(m, 0, 16 * sizeof *m);
  m[0] = m[5] = m[10] = m[15] = 1.0f;
}

/* a = a b, both row-major 4x4. */
static void mul(float a[16], const float b[16]) {
  float r[16];
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      double v = 0.0;
      for (int k = 0; k < 4; k++)
        v += (double)a[4 * i + k] * b[4 * k + j];
      r[4 * i + j] = (float)v;
    }
  memcpy(a, r, sizeof r);
}

/* Z-up to Y-up, as Blender's exporters convert: a -90 degree turn about X
 * (Blender's -Y, the front of a head, becomes +Z, where the default camera
 * of an imported scene looks from). */
static void up_matrix(const satf_import_options *o, float m[16]) {
  identity(m);
  if (o->up_z) {
    m[5] = 0.0f, m[6] = 1.0f;   /* y' = z */
    m[9] = -1.0f, m[10] = 0.0f; /* z' = -y */
  }
}

static void trs(const double t[3], const double axis_in[3], double angle_deg,
                const double scale[3], float m[16]) {
  double axis[3] = {axis_in[0], axis_in[1], axis_in[2]};
  double len = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  for (int c = 0; c < 3; c++)
    axis[c] = len > 0.0 ? axis[c] / len : (c == 1);
  satf_scene_matrix_trs(t, axis, angle_deg * SATF_PI / 180.0, scale, m);
}

int import_hair_matrix(const satf_import_options *o, float m[16]) {
  float u[16];
  trs(o->hair_translate, o->hair_axis, o->hair_angle_deg, o->hair_scale, m);
  up_matrix(o, u);
  mul(m, u);
  float id[16];
  identity(id);
  return memcmp(m, id, sizeof id) != 0;
}

void import_mesh_matrix(const satf_import_options *o, float m[16]) {
  float u[16];
  trs(o->mesh_translate, o->mesh_axis, o->mesh_angle_deg, o->mesh_scale, m);
  up_matrix(o, u);
  mul(m, u);
}

static void apply(const float *m, const float p[3], float out[3]) {
  for (int r = 0; r < 3; r++)
    out[r] = m ? m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] +
                     m[4 * r + 3]
               : p[r];
}

/* Equal within a few float steps at their distance from the origin: the
 * same point written twice, whatever the units. */
static int coincide(const float a[3], const float b[3]) {
  for (int c = 0; c < 3; c++) {
    float mag = fmaxf(fabsf(a[c]), fabsf(b[c]));
    if (fabsf(a[c] - b[c]) > 4.0f * FLT_EPSILON * mag)
      return 0;
  }
  return 1;
}

/* The cube root of the 3x3 part's determinant: how much the transform
 * scales a width on average. */
static float mean_scale(const float *m) {
  if (!m)
    return 1.0f;
  double det = m[0] * ((double)m[5] * m[10] - (double)m[6] * m[9]) -
               m[1] * ((double)m[4] * m[10] - (double)m[6] * m[8]) +
               m[2] * ((double)m[4] * m[9] - (double)m[5] * m[8]);
  return (float)cbrt(fabs(det));
}

satf_status import_prepare_strands(satf_strand_set **s, const float *m,
                                   int clean, const char *path, int *dropped,
                                   size_t *merged, satf_error *err) {
  *dropped = 0;
  *merged = 0;
  const satf_strand_set *in = *s;
  int n = satf_strand_set_count(in);
  size_t np = satf_strand_set_point_count(in);
  int thick = satf_strand_set_thickness(in, 0) != NULL;
  int coloured = satf_strand_set_colour(in, 0) != NULL;
  int *counts = malloc((size_t)n * sizeof *counts);
  float *pts = malloc(3 * np * sizeof *pts);
  float *th = thick ? malloc(np * sizeof *th) : NULL;
  float *rgb = coloured ? malloc(3 * np * sizeof *rgb) : NULL;
  if (!counts || !pts || (thick && !th) || (coloured && !rgb)) {
    free(counts);
    free(pts);
    free(th);
    free(rgb);
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  }
  float k = mean_scale(m);
  int kept = 0;
  size_t at = 0;
  for (int i = 0; i < n; i++) {
    int cnt;
    const float *p = satf_strand_set_strand(in, i, &cnt);
    const float *t = satf_strand_set_thickness(in, i);
    const float *c = satf_strand_set_colour(in, i);
    size_t start = at;
    int last = 0; /* the last point kept */
    for (int j = 0; j < cnt; j++) {
      if (clean && at > start && coincide(p + 3 * j, p + 3 * last)) {
        (*merged)++;
        continue;
      }
      last = j;
      apply(m, p + 3 * j, pts + 3 * at);
      if (thick)
        th[at] = t[j] * k;
      if (coloured)
        memcpy(rgb + 3 * at, c + 3 * j, 3 * sizeof *rgb);
      at++;
    }
    if (at - start >= 2) {
      counts[kept++] = (int)(at - start);
    } else { /* every point coincides: no length */
      (*dropped)++;
      *merged -= (size_t)cnt - (at - start);
      at = start;
    }
  }
  satf_status st = SATF_OK;
  satf_strand_set *out = NULL;
  if (kept == 0)
    st = satf_error_set(err, SATF_ERR_CORRUPT,
                        "%s: every one of its %d strands has zero length "
                        "(all its points coincide)",
                        path, n);
  else
    st = satf_strand_set_create(kept, counts, pts, th, &out, err);
  if (st == SATF_OK && coloured &&
      (st = satf_strand_set_add_colour(out, rgb, err)) != SATF_OK)
    satf_strand_set_destroy(out);
  if (st == SATF_OK) {
    satf_strand_set_destroy(*s);
    *s = out;
  }
  free(counts);
  free(pts);
  free(th);
  free(rgb);
  return st;
}
