/* trace.c - planar ray tracing of generalized sectors (SATF sec. 5.1).
 *
 * The work is split the way the record grid allows: light transmittance
 * depends only on the light azimuth (one grid per light), ray samples and
 * their front-to-back weights only on the view azimuth (one pass per view),
 * and only the Phong shading of the samples needs both. satf_trace_hrir runs
 * the same code for a single pair, so both entry points agree exactly. */
#include "satf/math.h"
#include "satf/offline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* SATF eq. 5, written with the weight w = alpha (1 - acc_alpha) so the
 * tracer can keep w per sample and shade later with the same arithmetic. */
void satf_accumulate(float *acc_re, float *acc_alpha, float alpha, float re) {
  float w = alpha * (1.0f - *acc_alpha);
  *acc_re += w * re;
  *acc_alpha += w;
}

/* SATF sec. 5.1 asks for an opacity "proportional to the local density".
 * We use 1 - exp(-k rho ds), which is k rho ds to first order but stays in
 * [0, 1) and does not depend on how a segment is split into steps. */
float satf_step_opacity(float extinction, float rho, float ds) {
  return 1.0f - expf(-extinction * rho * ds);
}

float satf_phong(const satf_trace_params *p, const float n[2], const float l[2],
                 const float v[2], float transmittance) {
  float nl = n[0] * l[0] + n[1] * l[1];
  float diffuse = nl > 0.0f ? nl : 0.0f;
  /* r = 2 (n.l) n - l, the mirror of l about n. */
  float r[2] = {2.0f * nl * n[0] - l[0], 2.0f * nl * n[1] - l[1]};
  float rv = r[0] * v[0] + r[1] * v[1];
  float spec = rv > 0.0f && nl > 0.0f ? powf(rv, p->shininess) : 0.0f;
  return p->ambient +
         transmittance * (p->diffuse * diffuse + p->specular * spec);
}

/* The gradient of density is converted into a normal of length < 1: a
 * strand's edge (|grad| >> G0) gets a unit normal, a smooth interior a short
 * one, so flat regions fade to ambient instead of flickering with noise in
 * the gradient's direction. G0 is in density per sector unit. */
#define GRADIENT_SOFTNESS 2.0f

typedef struct grid_ctx {
  const satf_sector *sec;
  float *gx, *gy; /* -gradient of density in plane coordinates per node */
  float step;     /* march step, the smallest grid cell */
} grid_ctx;

static float bilerp(const float *f, int ns, int nt, float s, float t) {
  float x = s * (float)(ns - 1), y = t * (float)(nt - 1);
  int i = (int)x, j = (int)y;
  if (i > ns - 2)
    i = ns - 2;
  if (j > nt - 2)
    j = nt - 2;
  float fx = x - (float)i, fy = y - (float)j;
  const float *d = f + j * ns + i;
  float a = d[0] + fx * (d[1] - d[0]);
  float b = d[ns] + fx * (d[ns + 1] - d[ns]);
  return a + fy * (b - a);
}

static void compute_normals(grid_ctx *g) {
  const satf_sector *sec = g->sec;
  const satf_sector_shape *sh = &sec->shape;
  int ns = sec->ns, nt = sec->nt;
  float dr = sh->r_outer - sh->r_inner;
  for (int j = 0; j < nt; j++) {
    for (int i = 0; i < ns; i++) {
      const float *d = sec->density;
      int i0 = i > 0 ? i - 1 : i, i1 = i < ns - 1 ? i + 1 : i;
      int j0 = j > 0 ? j - 1 : j, j1 = j < nt - 1 ? j + 1 : j;
      float drho_ds = (d[j * ns + i1] - d[j * ns + i0]) /
                      ((float)(i1 - i0) / (float)(ns - 1));
      float drho_dt = (d[j1 * ns + i] - d[j0 * ns + i]) /
                      ((float)(j1 - j0) / (float)(nt - 1));
      float s = (float)i / (float)(ns - 1), t = (float)j / (float)(nt - 1);
      float r = sh->r_inner + s * dr, phi = (t - 0.5f) * sh->phase_span;
      float c = cosf(phi), sn = sinf(phi);
      /* chain rule through s = (r - r_inner)/dr, t = phi/span + 1/2 */
      float gx = drho_ds * c / dr - drho_dt * sn / (r * sh->phase_span);
      float gy = drho_ds * sn / dr + drho_dt * c / (r * sh->phase_span);
      float len =
          sqrtf(gx * gx + gy * gy + GRADIENT_SOFTNESS * GRADIENT_SOFTNESS);
      g->gx[j * ns + i] = -gx / len;
      g->gy[j * ns + i] = -gy / len;
    }
  }
}

/* Transmittance from each grid node towards the light (in-sector
 * self-shadowing): exp(-optical depth) along +l until the ray leaves. */
static void light_transmittance(const grid_ctx *g, const satf_trace_params *p,
                                float theta_l, float *T) {
  const satf_sector *sec = g->sec;
  int n = sec->ns * sec->nt;
  if (!p->self_shadow) {
    for (int k = 0; k < n; k++)
      T[k] = 1.0f;
    return;
  }
  float l[2] = {cosf(theta_l), sinf(theta_l)};
  float lo, hi;
  satf_sector_extent(&sec->shape, l, &lo, &hi);
  for (int k = 0; k < n; k++) {
    const float *x0 = sec->node_xy + 2 * k;
    float q0 = x0[0] * l[0] + x0[1] * l[1];
    float depth = 0.0f;
    /* half a step first: the node's own density does not shade itself */
    for (float tau = 0.5f * g->step; q0 + tau <= hi; tau += g->step) {
      float x[2] = {x0[0] + tau * l[0], x0[1] + tau * l[1]}, st[2];
      if (satf_sector_param(&sec->shape, x, st))
        depth += bilerp(sec->density, sec->ns, sec->nt, st[0], st[1]);
    }
    T[k] = expf(-p->extinction * depth * g->step);
  }
}

typedef struct ray_sample {
  float w;    /* front-to-back weight alpha_k (1 - accumulated alpha) */
  float s, t; /* where, for the transmittance look-up */
  float n[2]; /* soft normal */
} ray_sample;

typedef struct view_pass {
  ray_sample *samples; /* all rays' samples, ray after ray */
  int *first;          /* width + 1 offsets into samples */
  float *alpha;        /* accumulated alpha per ray */
  int cap;
} view_pass;

static int view_pass_reserve(view_pass *vp, int width, int per_ray) {
  int need = width * per_ray;
  if (need > vp->cap) {
    ray_sample *s = realloc(vp->samples, (size_t)need * sizeof *s);
    if (!s)
      return -1;
    vp->samples = s;
    vp->cap = need;
  }
  return 0;
}

/* Marches every ray of one view azimuth, front to back (SATF eq. 5). */
static void march_view(const grid_ctx *g, const satf_trace_params *p,
                       float theta_v, view_pass *vp) {
  const satf_sector *sec = g->sec;
  float d[2] = {cosf(theta_v), sinf(theta_v)}; /* towards the viewer */
  float e[2] = {-d[1], d[0]};
  float pmin, pmax, qmin, qmax;
  satf_sector_extent(&sec->shape, e, &pmin, &pmax);
  satf_sector_extent(&sec->shape, d, &qmin, &qmax);
  int count = 0;
  for (int j = 0; j < p->width; j++) {
    float pj = pmin + ((float)j + 0.5f) * (pmax - pmin) / (float)p->width;
    float acc = 0.0f;
    vp->first[j] = count;
    for (float q = qmax - 0.5f * g->step; q >= qmin; q -= g->step) {
      float x[2] = {pj * e[0] + q * d[0], pj * e[1] + q * d[1]}, st[2];
      if (!satf_sector_param(&sec->shape, x, st))
        continue;
      float rho = bilerp(sec->density, sec->ns, sec->nt, st[0], st[1]);
      float a = satf_step_opacity(p->extinction, rho, g->step);
      if (a <= 0.0f)
        continue;
      ray_sample *rs = &vp->samples[count++];
      rs->w = a * (1.0f - acc); /* the weight of satf_accumulate */
      acc += rs->w;
      rs->s = st[0];
      rs->t = st[1];
      rs->n[0] = bilerp(g->gx, sec->ns, sec->nt, st[0], st[1]);
      rs->n[1] = bilerp(g->gy, sec->ns, sec->nt, st[0], st[1]);
      if (acc > 1.0f - p->epsilon)
        break;
    }
    vp->alpha[j] = acc;
  }
  vp->first[p->width] = count;
}

static void shade_view(const grid_ctx *g, const satf_trace_params *p,
                       const view_pass *vp, float theta_v, float theta_l,
                       const float *T, float *re, float *alpha) {
  const satf_sector *sec = g->sec;
  float v[2] = {cosf(theta_v), sinf(theta_v)};
  float l[2] = {cosf(theta_l), sinf(theta_l)};
  for (int j = 0; j < p->width; j++) {
    float acc = 0.0f;
    for (int k = vp->first[j]; k < vp->first[j + 1]; k++) {
      const ray_sample *rs = &vp->samples[k];
      float tl = bilerp(T, sec->ns, sec->nt, rs->s, rs->t);
      acc += rs->w * satf_phong(p, rs->n, l, v, tl);
    }
    re[j] = acc;
    alpha[j] = vp->alpha[j];
  }
}

/* SATF sec. 5.1: the HRIR is smoothed with a Gaussian whose width is a
 * multiple of the strand Gaussian's. The extracted text reads "1:5"; we read
 * it as 1.5 (a ratio of 1.5 times), the default of smooth_ratio. */
static void smooth_record(float *f, float *tmp, int n, float sigma_px) {
  if (!(sigma_px > 0.05f))
    return;
  int radius = (int)ceilf(3.0f * sigma_px);
  if (radius > n)
    radius = n;
  float kernel[4097];
  float sum = 0.0f;
  for (int k = 0; k <= radius; k++) {
    kernel[k] = expf(-0.5f * (float)(k * k) / (sigma_px * sigma_px));
    sum += k == 0 ? kernel[k] : 2.0f * kernel[k];
  }
  for (int j = 0; j < n; j++) {
    float acc = 0.0f;
    /* outside the record nothing is hit, so zero padding is exact */
    for (int k = -radius; k <= radius; k++)
      if (j + k >= 0 && j + k < n)
        acc += kernel[k < 0 ? -k : k] * f[j + k];
    tmp[j] = acc / sum;
  }
  memcpy(f, tmp, (size_t)n * sizeof *f);
}

static float record_sigma_px(const satf_sector *sec, const satf_trace_params *p,
                             float theta_v) {
  float pmin, pmax;
  satf_trace_extent(&sec->shape, theta_v, &pmin, &pmax);
  float px = (pmax - pmin) / (float)p->width;
  return p->smooth_ratio * sec->strand_sigma / px;
}

typedef struct trace_job {
  int n_view, n_light;
  const float *theta_v, *theta_l;
} trace_job;

static satf_status trace_grid(const satf_sector *sec,
                              const satf_trace_params *p, const trace_job *job,
                              float *re, float *alpha, satf_error *err) {
  satf_status st = satf_trace_params_check(p, err);
  if (st != SATF_OK)
    return st;
  int ns = sec->ns, nt = sec->nt, w = p->width;
  const satf_sector_shape *sh = &sec->shape;
  float cell_s = (sh->r_outer - sh->r_inner) / (float)(ns - 1);
  float cell_t = sh->r_inner * sh->phase_span / (float)(nt - 1);
  grid_ctx g = {sec, NULL, NULL, cell_s < cell_t ? cell_s : cell_t};
  /* rays cannot meet more samples than the longest chord over the step */
  float lo, hi, dmax = 0.0f;
  for (int k = 0; k < 8; k++) {
    float e[2] = {cosf((float)k * 0.3927f), sinf((float)k * 0.3927f)};
    satf_sector_extent(sh, e, &lo, &hi);
    dmax = hi - lo > dmax ? hi - lo : dmax;
  }
  int per_ray = (int)(dmax * 1.5f / g.step) + 4;
  size_t nn = (size_t)ns * (size_t)nt;
  view_pass vp = {0};
  g.gx = malloc(nn * sizeof(float));
  g.gy = malloc(nn * sizeof(float));
  float *T = malloc(nn * (size_t)job->n_light * sizeof(float));
  float *tmp = malloc((size_t)w * sizeof(float));
  vp.first = malloc((size_t)(w + 1) * sizeof(int));
  vp.alpha = malloc((size_t)w * sizeof(float));
  if (!g.gx || !g.gy || !T || !tmp || !vp.first || !vp.alpha ||
      view_pass_reserve(&vp, w, per_ray) != 0) {
    st = satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate trace buffers");
    goto done;
  }
  compute_normals(&g);
  for (int il = 0; il < job->n_light; il++)
    light_transmittance(&g, p, job->theta_l[il], T + (size_t)il * nn);
  for (int iv = 0; iv < job->n_view; iv++) {
    march_view(&g, p, job->theta_v[iv], &vp);
    float sigma_px = record_sigma_px(sec, p, job->theta_v[iv]);
    for (int il = 0; il < job->n_light; il++) {
      size_t off = ((size_t)iv * (size_t)job->n_light + (size_t)il) * (size_t)w;
      shade_view(&g, p, &vp, job->theta_v[iv], job->theta_l[il],
                 T + (size_t)il * nn, re + off, alpha + off);
      smooth_record(re + off, tmp, w, sigma_px);
      smooth_record(alpha + off, tmp, w, sigma_px);
    }
  }
done:
  free(g.gx);
  free(g.gy);
  free(T);
  free(tmp);
  free(vp.samples);
  free(vp.first);
  free(vp.alpha);
  return st;
}

satf_status satf_trace_hrir(const satf_sector *sector,
                            const satf_trace_params *p, float theta_v,
                            float theta_l, float *re, float *alpha,
                            satf_error *err) {
  trace_job job = {1, 1, &theta_v, &theta_l};
  return trace_grid(sector, p, &job, re, alpha, err);
}

satf_status satf_trace_all(const satf_sector *sector,
                           const satf_trace_params *p, int n_view, int n_light,
                           float *re, float *alpha, satf_error *err) {
  if (n_view < 1 || n_light < 1 || n_view > 4096 || n_light > 4096)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "angle counts %d x %d out of range [1, 4096]", n_view,
                          n_light);
  float *angles = malloc((size_t)(n_view + n_light) * sizeof(float));
  if (!angles)
    return satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate angles");
  for (int i = 0; i < n_view; i++)
    angles[i] = SATF_TWO_PI_F * (float)i / (float)n_view;
  for (int i = 0; i < n_light; i++)
    angles[n_view + i] = SATF_TWO_PI_F * (float)i / (float)n_light;
  trace_job job = {n_view, n_light, angles, angles + n_view};
  satf_status st = trace_grid(sector, p, &job, re, alpha, err);
  free(angles);
  return st;
}
