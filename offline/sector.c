/* sector.c - generalized sectors and their random generator (SATF sec.
 * 3.2-3.3 and 5). */
#include "satf/offline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"

satf_status satf_sector_create(const satf_sector_shape *shape, int ns, int nt,
                               float strand_sigma, satf_sector **out,
                               satf_error *err) {
  *out = NULL;
  satf_status st = satf_sector_shape_check(shape, err);
  if (st != SATF_OK)
    return st;
  if (ns < 2 || nt < 2 || ns > 4096 || nt > 4096)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "sector grid %dx%d must be within [2, 4096]", ns, nt);
  if (!(strand_sigma > 0.0f) || !(strand_sigma < 10.0f))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "strand width %g must be positive",
                          (double)strand_sigma);
  satf_sector *s = calloc(1, sizeof *s);
  float *d = calloc((size_t)ns * (size_t)nt, sizeof *d);
  float *xy = malloc(2 * (size_t)ns * (size_t)nt * sizeof *xy);
  if (!s || !d || !xy) {
    free(s);
    free(d);
    free(xy);
    return satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate a %dx%d sector",
                          ns, nt);
  }
  s->shape = *shape;
  s->ns = ns;
  s->nt = nt;
  s->strand_sigma = strand_sigma;
  s->density = d;
  s->node_xy = xy;
  for (int j = 0; j < nt; j++)
    for (int i = 0; i < ns; i++)
      satf_sector_point(shape, (float)i / (float)(ns - 1),
                        (float)j / (float)(nt - 1), xy + 2 * (j * ns + i));
  *out = s;
  return SATF_OK;
}

void satf_sector_destroy(satf_sector *sector) {
  if (sector) {
    free(sector->density);
    free(sector->node_xy);
    free(sector->fibers);
    free(sector);
  }
}

void satf_sector_point(const satf_sector_shape *shape, float s, float t,
                       float xy[2]) {
  float r = shape->r_inner + s * (shape->r_outer - shape->r_inner);
  float phi = (t - 0.5f) * shape->phase_span;
  xy[0] = r * cosf(phi);
  xy[1] = r * sinf(phi);
}

int satf_sector_param(const satf_sector_shape *shape, const float xy[2],
                      float st[2]) {
  float r = sqrtf(xy[0] * xy[0] + xy[1] * xy[1]);
  float phi = atan2f(xy[1], xy[0]);
  st[0] = (r - shape->r_inner) / (shape->r_outer - shape->r_inner);
  st[1] = phi / shape->phase_span + 0.5f;
  return st[0] >= 0.0f && st[0] <= 1.0f && st[1] >= 0.0f && st[1] <= 1.0f;
}

/* SATF sec. 3.3: a strand's cross-section density is a circular Gaussian.
 * Mass pi sigma^2 makes the peak 1/2 (coverage units, see sector.h). */
static float strand_gaussian(float d2, float sigma) {
  return 0.5f * expf(-d2 / (2.0f * sigma * sigma));
}

static int clamp_index(float x, int n) {
  return x < 0.0f ? 0 : x > (float)(n - 1) ? n - 1 : (int)x;
}

/* Appends the strand to the fibre list; a failed allocation is remembered
 * (the tracer refuses such a sector) instead of dropping a fibre silently. */
static void add_fiber(satf_sector *sector, const float c[2]) {
  if (sector->fiber_count == sector->fiber_cap) {
    int cap = sector->fiber_cap ? 2 * sector->fiber_cap : 64;
    float *f = realloc(sector->fibers, 3 * (size_t)cap * sizeof *f);
    if (!f) {
      sector->fiber_failed = 1;
      return;
    }
    sector->fibers = f;
    sector->fiber_cap = cap;
  }
  float *f = sector->fibers + 3 * sector->fiber_count++;
  f[0] = c[0];
  f[1] = c[1];
  f[2] = sector->strand_sigma;
}

/* The density of a strand centred at (s, t), which may lie outside
 * [0,1]^2: its tail reaches the sector's nodes. */
static void add_density(satf_sector *sector, float s, float t) {
  const satf_sector_shape *sh = &sector->shape;
  float c[2];
  satf_sector_point(sh, s, t, c);
  float sigma = sector->strand_sigma;
  float cut = 4.0f * sigma; /* beyond 4 sigma: < 0.04% of the peak */
  /* Only nodes within the cut-off window in (s, t) can be reached; the
   * t extent uses the inner radius, where the phase is most compressed. */
  float ds = cut / (sh->r_outer - sh->r_inner) * (float)(sector->ns - 1);
  float dt = cut / (sh->r_inner * sh->phase_span) * (float)(sector->nt - 1);
  float si = s * (float)(sector->ns - 1), tj = t * (float)(sector->nt - 1);
  int i0 = clamp_index(floorf(si - ds), sector->ns);
  int i1 = clamp_index(ceilf(si + ds), sector->ns);
  int j0 = clamp_index(floorf(tj - dt), sector->nt);
  int j1 = clamp_index(ceilf(tj + dt), sector->nt);
  for (int j = j0; j <= j1; j++) {
    for (int i = i0; i <= i1; i++) {
      const float *p = sector->node_xy + 2 * (j * sector->ns + i);
      float dx = p[0] - c[0], dy = p[1] - c[1];
      float d2 = dx * dx + dy * dy;
      if (d2 < cut * cut)
        sector->density[j * sector->ns + i] += strand_gaussian(d2, sigma);
    }
  }
}

void satf_sector_add_strand(satf_sector *sector, float s, float t) {
  float c[2];
  satf_sector_point(&sector->shape, s, t, c);
  add_fiber(sector, c);
  add_density(sector, s, t);
}

void satf_sector_scale(satf_sector *sector, float k) {
  size_t n = (size_t)sector->ns * (size_t)sector->nt;
  for (size_t i = 0; i < n; i++)
    sector->density[i] *= k;
}

float satf_sector_density(const satf_sector *sector, float s, float t) {
  if (!(s >= 0.0f && s <= 1.0f && t >= 0.0f && t <= 1.0f))
    return 0.0f;
  float x = s * (float)(sector->ns - 1), y = t * (float)(sector->nt - 1);
  int i = (int)x, j = (int)y;
  if (i > sector->ns - 2)
    i = sector->ns - 2;
  if (j > sector->nt - 2)
    j = sector->nt - 2;
  float fx = x - (float)i, fy = y - (float)j;
  const float *d = sector->density + j * sector->ns + i;
  float a = d[0] + fx * (d[1] - d[0]);
  float b = d[sector->ns] + fx * (d[sector->ns + 1] - d[sector->ns]);
  return a + fy * (b - a);
}

const char *satf_layout_name(satf_layout layout) {
  switch (layout) {
  case SATF_LAYOUT_UNIFORM: return "uniform";
  case SATF_LAYOUT_CLUMPED: return "clumped";
  case SATF_LAYOUT_GRADIENT_S: return "gradient-s";
  case SATF_LAYOUT_GRADIENT_T: return "gradient-t";
  case SATF_LAYOUT_HOLES: return "holes";
  case SATF_LAYOUT_COUNT: break;
  }
  return "unknown";
}

/* Recipes and placements use separate random streams of the same sample so
 * that changing how strands are placed does not reshuffle the recipes. */
#define STREAM_RECIPE 0x5EC7011ull
#define STREAM_PLACE 0x9A11CEull

satf_sector_ranges satf_sector_ranges_default(satf_record_kind kind) {
  /* The shells of imported hair (the shared ponytail, a generated
   * straight curtain: tests/render/measure_db_range) look up sectors whose
   * density centroids lie beyond the paper's sectors' 0.09..0.9 in 6-23%
   * of their look-ups (16% of the ponytail's sectors that show hair): the
   * tails of strands of the neighbouring sectors reach in. The fibre
   * records' sectors have such tails too, which brings the ponytail's to
   * 3%. Wider strands (sigma up to 0.03 or 0.04, as wide against a sector
   * as the imports' 0.075-0.19 of a layer's depth) made the figures of
   * scripts/compare-cycles.sh worse (SSIM4 of the straight curtain 0.50
   * -> 0.47, the back-lit ponytail's luminance 1.35 -> 1.57), so sigma
   * keeps the paper's range. The Phong records keep the paper's sectors. */
  satf_sector_ranges phong = {0.008, 0.02, 0.0f};
  satf_sector_ranges fiber = {0.008, 0.02, 3.0f};
  return kind == SATF_RECORD_FIBER ? fiber : phong;
}

void satf_sector_recipe_random(uint64_t seed, uint64_t index,
                               satf_sector_recipe *r) {
  satf_sector_ranges ranges = satf_sector_ranges_default(SATF_RECORD_PHONG);
  satf_sector_recipe_draw(seed, index, &ranges, r);
}

/* The margin in (s, t) units of a recipe on shape sh: s across the depth,
 * t along the arc at mid depth. */
static void margins(const satf_sector_shape *sh, const satf_sector_recipe *r,
                    float m[2]) {
  float w = r->margin * r->strand_sigma;
  m[0] = w / (sh->r_outer - sh->r_inner);
  m[1] = w / (0.5f * (sh->r_inner + sh->r_outer) * sh->phase_span);
}

void satf_sector_recipe_draw(uint64_t seed, uint64_t index,
                             const satf_sector_ranges *ranges,
                             satf_sector_recipe *r) {
  satf_rng rng;
  satf_rng_seed(&rng, seed ^ STREAM_RECIPE, index);
  memset(r, 0, sizeof *r);
  r->layout = (satf_layout)satf_rng_below(&rng, SATF_LAYOUT_COUNT);
  r->strand_sigma =
      (float)satf_rng_range(&rng, ranges->sigma_lo, ranges->sigma_hi);
  r->margin = ranges->margin;
  /* The mean coverage (density) is spread log-uniformly over [0.01, 2.5] so
   * sparse sectors (a few strands) are as well represented as dense ones;
   * about 1 sample in 40 is empty to anchor the bottom of the feature
   * range. The strand count follows from coverage, sector area and strand
   * mass pi sigma^2. */
  double u = satf_rng_uniform(&rng);
  double coverage =
      exp(log(0.01) + (u - 0.025) / 0.975 * (log(2.5) - log(0.01)));
  satf_sector_shape sh = satf_sector_shape_default();
  double area =
      0.5 * sh.phase_span * (sh.r_outer * sh.r_outer - sh.r_inner * sh.r_inner);
  double mass = 3.14159265358979 * r->strand_sigma * r->strand_sigma;
  /* the strands of the grown sector keep the coverage inside */
  float m[2];
  margins(&sh, r, m);
  area *= (1.0 + 2.0 * m[0]) * (1.0 + 2.0 * m[1]);
  r->strands = u < 0.025 ? 0 : 1 + (int)(coverage * area / mass);
  switch (r->layout) {
  case SATF_LAYOUT_CLUMPED:
    r->param[0] = (float)(1 + satf_rng_below(&rng, 4));    /* clumps */
    r->param[1] = (float)satf_rng_range(&rng, 0.05, 0.25); /* spread */
    break;
  case SATF_LAYOUT_GRADIENT_S:
  case SATF_LAYOUT_GRADIENT_T:
    r->param[0] = (float)satf_rng_range(&rng, -1.0, 1.0); /* slope */
    break;
  case SATF_LAYOUT_HOLES:
    r->param[0] = (float)(1 + satf_rng_below(&rng, 3));   /* holes */
    r->param[1] = (float)satf_rng_range(&rng, 0.1, 0.35); /* radius */
    break;
  default: break;
  }
}

/* Rejection sampling against a linear ramp 1 + slope (x - 1/2), x in [0,1]. */
static float sample_ramp(satf_rng *rng, float slope) {
  for (;;) {
    float x = (float)satf_rng_uniform(rng);
    float w = (1.0f + slope * (x - 0.5f)) / (1.0f + fabsf(slope) * 0.5f);
    if ((float)satf_rng_uniform(rng) < w)
      return x;
  }
}

static float clamp01(float x) { return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x; }

void satf_sector_fill(satf_sector *sector, const satf_sector_recipe *r,
                      uint64_t seed, uint64_t index) {
  satf_rng rng;
  satf_rng_seed(&rng, seed ^ STREAM_PLACE, index);
  float centres[4][2] = {{0}};
  int nclumps = r->layout == SATF_LAYOUT_CLUMPED ? (int)r->param[0] : 0;
  int nholes = r->layout == SATF_LAYOUT_HOLES ? (int)r->param[0] : 0;
  for (int c = 0; c < nclumps + nholes && c < 4; c++) {
    centres[c][0] = (float)satf_rng_uniform(&rng);
    centres[c][1] = (float)satf_rng_uniform(&rng);
  }
  float m[2];
  margins(&sector->shape, r, m);
  for (int k = 0; k < r->strands; k++) {
    float s = 0.5f, t = 0.5f;
    switch (r->layout) {
    case SATF_LAYOUT_CLUMPED: {
      int c = (int)satf_rng_below(&rng, (uint32_t)nclumps);
      s = clamp01(centres[c][0] + r->param[1] * (float)satf_rng_normal(&rng));
      t = clamp01(centres[c][1] + r->param[1] * (float)satf_rng_normal(&rng));
      break;
    }
    case SATF_LAYOUT_GRADIENT_S:
      s = sample_ramp(&rng, 2.0f * r->param[0]);
      t = (float)satf_rng_uniform(&rng);
      break;
    case SATF_LAYOUT_GRADIENT_T:
      s = (float)satf_rng_uniform(&rng);
      t = sample_ramp(&rng, 2.0f * r->param[0]);
      break;
    case SATF_LAYOUT_HOLES: {
      int inside;
      int tries = 0;
      do { /* holes are in (s, t) units; give up after a while */
        s = (float)satf_rng_uniform(&rng);
        t = (float)satf_rng_uniform(&rng);
        inside = 0;
        for (int h = 0; h < nholes; h++) {
          float ds = s - centres[h][0], dt = t - centres[h][1];
          if (ds * ds + dt * dt < r->param[1] * r->param[1])
            inside = 1;
        }
      } while (inside && ++tries < 64);
      break;
    }
    default:
      s = (float)satf_rng_uniform(&rng);
      t = (float)satf_rng_uniform(&rng);
      break;
    }
    if (r->margin > 0.0f) { /* the layout over the grown sector */
      s = -m[0] + (1.0f + 2.0f * m[0]) * s;
      t = -m[1] + (1.0f + 2.0f * m[1]) * t;
    }
    if (s >= 0.0f && s <= 1.0f && t >= 0.0f && t <= 1.0f)
      satf_sector_add_strand(sector, s, t);
    else
      add_density(sector, s, t);
  }
}
