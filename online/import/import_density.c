/* import_density.c - strands as density (SATF sec. 3.3): each strand's
 * cross-section is a circular Gaussian. Per cluster the field lives in the
 * cluster's own (t, v, u) coordinates (normalised so v = 1 is the
 * envelope); for the whole hairstyle it is a world-space OpenVDB grid. Both
 * use the coverage units of the HRIR database (satf/sector.h): a strand of
 * Gaussian width sigma has mass pi sigma^2 per unit length. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "import_internal.h"
#include "satf/db.h"
#include "satf/math.h"

#define WIDTH_SLICES 5
/* The shells' hollow core (SATF sec. 3.2: "a homogeneous transparent
 * interior core"): no sector sees the strands inside it, so it is only as
 * wide as leaves CORE_QUANTILE of the points there, and at most
 * SHELL_CORE, the radius for hair that fills its cluster's rim. Fur and
 * other clusters whose strands crowd the axis had 38% of their points in
 * a core of 0.4, which left fur see-through. */
#define SHELL_CORE 0.4
#define CORE_QUANTILE 0.03
#define CORE_BINS 40
#define WIDTH_PROBES 1500

/* Mean nearest-neighbour distance among n points (x, y interleaved). */
static double mean_nn(const float *xy, int n) {
  double sum = 0.0;
  for (int i = 0; i < n; i++) {
    double best = INFINITY;
    for (int j = 0; j < n; j++) {
      if (j == i)
        continue;
      double dx = xy[2 * i] - xy[2 * j], dy = xy[2 * i + 1] - xy[2 * j + 1];
      double d = dx * dx + dy * dy;
      best = d < best ? d : best;
    }
    sum += sqrt(best);
  }
  return sum / n;
}

/* The ratio E[v] / sqrt(2 E[v^2]) for a disk whose density goes as
 * 1 + g (v - 1/2): it does not depend on the disk's radius, so it can be
 * measured without knowing where the hair really ends. */
static double gradient_ratio(double g) {
  double ev = (2.0 / 3.0 + g / 6.0) / (1.0 + g / 6.0);
  double ev2 = (0.5 + 3.0 * g / 20.0) / (1.0 + g / 6.0);
  return ev / sqrt(2.0 * ev2);
}

/* The v below which CORE_QUANTILE of np points lie (at most SHELL_CORE),
 * from a histogram of their v over [0, SHELL_CORE) in CORE_BINS bins,
 * rounded down to a bin edge. */
static float core_radius(const int *bins, size_t np) {
  double allowed = CORE_QUANTILE * (double)np, seen = 0.0;
  for (int b = 0; b < CORE_BINS; b++) {
    seen += bins[b];
    if (seen > allowed)
      return (float)(SHELL_CORE * b / CORE_BINS);
  }
  return (float)SHELL_CORE;
}

void satf_import_estimate_density(const satf_import_projection *proj,
                                  satf_import_fit *fit) {
  satf_import_fit_tracks(proj, fit);
  int n = proj->n_strands;
  int m = n < WIDTH_PROBES ? n : WIDTH_PROBES;
  float *xy = malloc(2 * (size_t)(m ? m : 1) * sizeof(float));
  double width_sum = 0.0;
  int width_count = 0;
  for (int s = 0; xy && s < WIDTH_SLICES; s++) {
    float t = 0.2f + 0.6f * (float)s / (WIDTH_SLICES - 1);
    int got = 0, crossing = 0;
    for (int i = 0; i < n; i++) {
      float p[2];
      if (!satf_import_projection_at(proj, i, t, p))
        continue;
      crossing++;
      /* an even subsample of the crossing strands */
      if ((int64_t)got * n <= (int64_t)i * m && got < m) {
        xy[2 * got] = p[0];
        xy[2 * got + 1] = p[1];
        got++;
      }
    }
    if (got < 2)
      continue;
    /* a subsample of got of `crossing` points is sqrt(crossing/got) times
     * sparser */
    width_sum += 2.0 * mean_nn(xy, got) * sqrt((double)got / crossing);
    width_count++;
  }
  free(xy);
  float w = width_count ? (float)(width_sum / width_count) : 0.5f;
  fit->strand_width = w < 0.01f ? 0.01f : w > 0.5f ? 0.5f : w;
  double ma = 0.0, mb = 0.0;
  for (int j = 0; j < fit->n_radius; j++) {
    ma += fit->a[j];
    mb += fit->b[j];
  }
  fit->radius = (float)(sqrt(ma * mb) / fit->n_radius);
  /* radial profile */
  double sv = 0.0, sv2 = 0.0;
  size_t np = proj->offset[n];
  int vbins[CORE_BINS] = {0};
  for (size_t k = 0; k < np; k++) {
    double x = proj->txy[3 * k + 1], y = proj->txy[3 * k + 2];
    double v2 = x * x + y * y;
    sv += sqrt(v2);
    sv2 += v2;
    int b = (int)(sqrt(v2) * CORE_BINS / SHELL_CORE);
    if (b < CORE_BINS)
      vbins[b]++;
  }
  fit->core = core_radius(vbins, np);
  fit->layout = SATF_SCENE_LAYOUT_UNIFORM;
  fit->gradient = 0.0f;
  if (np < 64 || sv2 <= 0.0)
    return;
  double r = (sv / np) / sqrt(2.0 * sv2 / np);
  double lo = -1.0, hi = 1.0; /* gradient_ratio grows with g */
  if (r <= gradient_ratio(lo) || r >= gradient_ratio(hi)) {
    fit->gradient = r <= gradient_ratio(lo) ? -1.0f : 1.0f;
  } else {
    for (int it = 0; it < 50; it++) {
      double mid = 0.5 * (lo + hi);
      if (gradient_ratio(mid) < r)
        lo = mid;
      else
        hi = mid;
    }
    fit->gradient = (float)(0.5 * (lo + hi));
  }
  if (fabsf(fit->gradient) >= 0.4f)
    fit->layout = SATF_SCENE_LAYOUT_GRADIENT;
  else
    fit->gradient = 0.0f;
}

/* A one-strand cluster narrower than its strand grows round it to the
 * strand's width: A and B by k, its tracks (positions are track_xy x
 * (A, B)) and ends by 1/k, so the strand stays where it is and is drawn
 * at its own width (the tracks hold strands of up to 2 radii). */
static void grow_round_strand(satf_import_fit *f, float width) {
  float k = 0.5f * width / f->radius;
  for (int j = 0; j < f->n_radius; j++) {
    f->a[j] *= k;
    f->b[j] *= k;
  }
  size_t pts = 0;
  for (int i = 0; i < f->n_tracks; i++)
    pts += (size_t)f->track_count[i];
  for (size_t i = 0; f->track_xy && i < 2 * pts; i++)
    f->track_xy[i] /= k;
  for (int i = 0; f->track_ends && i < 6 * f->n_tracks; i++)
    if (i % 3 != 0) /* (t, x, y): t stays */
      f->track_ends[i] /= k;
  f->radius *= k;
  f->strand_width = 2.0f;
}

void satf_import_width_from_thickness(const satf_strand_set *s,
                                      const int *members, int n,
                                      satf_import_fit *fit) {
  double sum = 0.0;
  size_t count = 0;
  for (int i = 0; i < n; i++) {
    const float *th = satf_strand_set_thickness(s, members[i]);
    if (!th)
      return;
    int m = satf_strand_set_points(s, members[i]);
    for (int k = 0; k < m; k++)
      sum += th[k];
    count += (size_t)m;
  }
  if (count == 0 || !(sum > 0.0) || !(fit->radius > 0.0f))
    return;
  float width = (float)(sum / (double)count);
  if (n == 1 && width > 2.0f * fit->radius) {
    grow_round_strand(fit, width);
    return;
  }
  /* up to 2 (the tracks' range, satf/scene.h): a one-strand cluster's
   * radius is half its strand's thickness */
  float w = width / fit->radius;
  fit->strand_width = w < 0.005f ? 0.005f : w > 2.0f ? 2.0f : w;
  /* drawn as its strands (the renderer's sparse clusters), each strand
   * at its own width: at the mean, the ponytail's were 0.6x to 1.7x
   * (p10, p90) as wide as in the strands file, hence as the reference */
  if (fit->n_tracks < 2 || !fit->track_member)
    return;
  free(fit->track_width);
  fit->track_width = malloc((size_t)fit->n_tracks * sizeof(float));
  for (int k = 0; fit->track_width && k < fit->n_tracks; k++) {
    int i = members[fit->track_member[k]];
    const float *th = satf_strand_set_thickness(s, i);
    int m = satf_strand_set_points(s, i);
    double own = 0.0;
    for (int j = 0; j < m; j++)
      own += th[j];
    float v = (float)(own / m) / fit->radius;
    fit->track_width[k] = v < 0.005f ? 0.005f : v > 2.0f ? 2.0f : v;
  }
}

void satf_import_density_free(satf_import_density *d) {
  if (d) {
    free(d->values);
    memset(d, 0, sizeof *d);
  }
}

double satf_import_density_slice_mass(const satf_import_density *d, int i) {
  double h = 2.0 * d->extent / d->n, sum = 0.0;
  const float *v = d->values + (size_t)i * d->n * d->n;
  for (int k = 0; k < d->n * d->n; k++)
    sum += v[k];
  return sum * h * h;
}

/* SATF sec. 3.3: adds one strand's circular Gaussian cross-section, its
 * discrete weights renormalised so the slice gains exactly pi sigma^2. */
static void add_cross_section(float *slice, int n, float extent, float sigma,
                              const float c[2]) {
  float h = 2.0f * extent / n;
  float fx = (c[0] + extent) / h - 0.5f, fy = (c[1] + extent) / h - 0.5f;
  int r = (int)ceilf(3.0f * sigma / h);
  int cx = (int)lroundf(fx), cy = (int)lroundf(fy);
  double total = 0.0;
  for (int pass = 0; pass < 2; pass++) {
    double k = pass ? SATF_PI_F * sigma * sigma / (total * h * h) : 0.0;
    for (int y = cy - r; y <= cy + r; y++) {
      if (y < 0 || y >= n)
        continue;
      for (int x = cx - r; x <= cx + r; x++) {
        if (x < 0 || x >= n)
          continue;
        float dx = ((float)x - fx) * h, dy = ((float)y - fy) * h;
        double g = exp(-(dx * dx + dy * dy) / (2.0 * sigma * sigma));
        if (pass)
          slice[y * n + x] += (float)(k * g);
        else
          total += g;
      }
    }
    if (!(total > 0.0)) { /* narrower than a cell: all in the nearest */
      if (cx >= 0 && cx < n && cy >= 0 && cy < n)
        slice[cy * n + cx] += SATF_PI_F * sigma * sigma / (h * h);
      return;
    }
  }
}

satf_status satf_import_cluster_density(const satf_import_projection *proj,
                                        int nt, int n, float extent,
                                        float sigma, satf_import_density *out,
                                        satf_error *err) {
  memset(out, 0, sizeof *out);
  if (nt < 1 || nt > 4096 || n < 2 || n > 4096 || !(extent > 0.0f) ||
      !(sigma > 0.0f) || !isfinite(extent) || !isfinite(sigma))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "cluster density: %d slices (1..4096) of %d x %d "
                          "cells (2..4096), extent %g and sigma %g (> 0)",
                          nt, n, n, (double)extent, (double)sigma);
  if ((size_t)nt * n * n > (256u << 20))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "cluster density: %d x %d x %d cells is too many", nt,
                          n, n);
  out->values = calloc((size_t)nt * n * n, sizeof(float));
  if (!out->values)
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cluster density: out of memory");
  out->nt = nt;
  out->n = n;
  out->extent = extent;
  out->sigma = sigma;
  for (int i = 0; i < nt; i++) {
    float t = ((float)i + 0.5f) / nt;
    float *slice = out->values + (size_t)i * n * n;
    for (int s = 0; s < proj->n_strands; s++) {
      float c[2];
      if (satf_import_projection_at(proj, s, t, c) && fabsf(c[0]) < extent &&
          fabsf(c[1]) < extent)
        add_cross_section(slice, n, extent, sigma, c);
    }
  }
  return SATF_OK;
}

/* Strands of width w (a diameter) with n per unit area hide n w of every
 * unit of a ray's path; their density (Gaussians of mass pi w^2 / 4) is
 * rho = n pi w^2 / 4, so the optical depth per unit path is 4 rho / (pi w).
 * A record's is extinction x rho (satf_trace_params), the same only for
 * w = 4 / (pi extinction), 0.127 cluster radii at the default 10; thinner
 * strands, fur's 0.09, came out at 60-65% of their coverage (sector by
 * sector, measured against opaque strands). Wider ones are left
 * as they are: a few wide Gaussians are no thinner than the strands. The
 * default database's parameters: a scene names the database it was
 * imported for, built with them. */
float satf_import_density_scale(float strand_width, float layer_depth) {
  float ext = satf_trace_params_default().extinction;
  satf_sector_shape sh = satf_sector_shape_default();
  float k =
      strand_width > 0.0f ? 4.0f / (SATF_PI_F * strand_width * ext) : 1.0f;
  k = k > 1.0f ? k : 1.0f;
  /* a layer deeper than the records' sector holds more hair on a ray than
   * its record shows at the same density: the density says so instead
   * (measured on fur, curls and the ponytail) */
  float depth = sh.r_outer - sh.r_inner;
  if (layer_depth > 0.0f && depth > 0.0f)
    k *= layer_depth / depth;
  return k < 100.0f ? k : 100.0f; /* the scene's limit */
}

float satf_import_world_sigma(const satf_import_fit *fit) {
  return 0.5f * fit->strand_width * fit->radius;
}

satf_status satf_import_build_vdb(const satf_strand_set *s, const int *labels,
                                  const satf_import_fit *fits, float voxel,
                                  satf_vdb_builder **out,
                                  satf_import_progress_fn progress,
                                  void *progress_ctx, satf_error *err) {
  *out = NULL;
  satf_vdb_builder *b;
  satf_status st = satf_vdb_builder_create(voxel, &b, err);
  if (st != SATF_OK)
    return st;
  int n = satf_strand_set_count(s);
  for (int i = 0; i < n && st == SATF_OK; i++) {
    float sigma = satf_import_world_sigma(&fits[labels[i]]);
    int m;
    const float *p = satf_strand_set_strand(s, i, &m);
    /* the file's own thickness where it has one (SATF sec. 3.3: the
     * strand's cross-section, half its diameter as the Gaussian's width),
     * so sparse strands stay as thin as they are drawn */
    const float *th = satf_strand_set_thickness(s, i);
    for (int k = 0; k + 1 < m && st == SATF_OK; k++) {
      float sg = sigma;
      if (th && th[k] + th[k + 1] > 0.0f)
        sg = 0.25f * (th[k] + th[k + 1]);
      st = satf_vdb_builder_add_tube(b, p + 3 * k, p + 3 * k + 3, sg,
                                     SATF_PI_F * sg * sg, err);
    }
    if (progress && (i % 256 == 255 || i == n - 1))
      progress(progress_ctx, (size_t)i + 1, (size_t)n);
  }
  if (st != SATF_OK) {
    satf_vdb_builder_destroy(b);
    return st;
  }
  *out = b;
  return SATF_OK;
}
