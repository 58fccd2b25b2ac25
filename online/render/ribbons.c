/* ribbons.c - owns strands on the GPU (strands_gpu): camera-facing,
 * anti-aliased ribbons of each point's width (glsl/strand_vs.glsl), shaded
 * under the renderer's lights, material and shading model
 * (glsl/strand_fs.glsl with lighting.glsl; with the physical material the
 * fibre model of satf/fiber.h and Zinke's dual scattering, fiber_gpu.h),
 * into the deep opacity map (glsl/strand_dom_fs.glsl), blended "over" or
 * into the per-pixel fragment arrays. Their segments sort far to near on
 * the CPU for painter's order, which is exact for thin segments (one
 * cannot be both in front of and behind another). The strand path
 * (strands.c) and the sparse clusters (sparse.c) draw with them. */
#include "renderer_internal.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "draw.h"
#include "fiber_gpu.h"
#include "satf/common.h"
#include "satf/math.h"
#include "shaders.h"

#define MAX_STRANDS (1 << 30)

/* A vertex: each point of a strand is two, its -side and +side
 * (glsl/strand_vs.glsl). */
typedef struct strand_vertex {
  float pos[4];     /* x, y, z, width */
  float tangent[3]; /* central difference of the neighbouring points */
  float t;          /* arc length from the root over the strand's length */
  uint32_t strand;
} strand_vertex;

struct strands_gpu {
  int nstrands;
  size_t npoints, nsegs;
  float *points;   /* x, y, z, width per point (CPU copy, for sorting) */
  uint32_t *first; /* per segment: the index of its first point */
  uint32_t *keys, *order, *tmp_keys, *tmp_order; /* sort scratch */
  uint32_t *indices; /* 6 per segment, in the sorted order */
  GLuint vao, vbo, ibo;
  /* [0] Kajiya-Kay, [1] the physical material (PHYSICAL 1: the fibre
   * model's light per point, strand_light_cs.glsl), [2] the same with the
   * offsets each pixel covers on strands wider than STRAND_EXACT_PX */
  GLuint prog_shade[3], prog_dom;
  GLuint prog_list[3]; /* into the per-pixel arrays (sparse.c), or 0 */
  GLuint prog_bound;   /* the shading program of strands_gpu_begin */
  /* the physical material's light per point (strand_light_cs.glsl), into
   * light_buf (STRAND_LIGHT_VEC4 vec4 a point), which the PHYSICAL
   * programs read */
  GLuint prog_light, light_buf;
  GLuint prog_depth;  /* their whole fragments' depth (sparse.c), or 0 */
  float lo[3], hi[3]; /* bounds of the ribbons */
  float width;        /* the points' median width */
  fiber_gpu fiber;    /* the physical material's uniforms and tables */
};

static void free_data(strands_gpu *s) {
  free(s->points);
  free(s->first);
  free(s->keys);
  free(s->order);
  free(s->tmp_keys);
  free(s->tmp_order);
  free(s->indices);
}

void strands_gpu_destroy(strands_gpu *s) {
  if (!s)
    return;
  GLuint bufs[3] = {s->vbo, s->ibo, s->light_buf};
  glDeleteBuffers(3, bufs);
  if (s->vao)
    glDeleteVertexArrays(1, &s->vao);
  GLuint progs[9] = {s->prog_shade[0], s->prog_shade[1], s->prog_shade[2],
                     s->prog_list[0],  s->prog_list[1],  s->prog_list[2],
                     s->prog_dom,      s->prog_depth,    s->prog_light};
  for (int k = 0; k < 9; k++)
    if (progs[k])
      glDeleteProgram(progs[k]);
  fiber_gpu_release(&s->fiber);
  free_data(s);
  free(s);
}

/* Checks the caller's arrays; sets *points to the point total. */
static satf_status check_input(int n, const int *counts, const float *xyz,
                               const float *thickness, float default_width,
                               size_t *points, satf_error *err) {
  if (n < 0 || n >= MAX_STRANDS)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "strands: %d strands (0 to %d)", n, MAX_STRANDS - 1);
  if (n > 0 && !thickness && !(default_width > 0.0f && isfinite(default_width)))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "strands: no thickness and a default width of %g "
                          "(must be positive)",
                          (double)default_width);
  size_t total = 0;
  for (int i = 0; i < n; i++) {
    if (counts[i] < 2 || counts[i] > 65536)
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "strands: strand %d has %d points (2 to 65536)", i,
                            counts[i]);
    total += (size_t)counts[i];
  }
  if (total >= (size_t)UINT32_MAX / 8)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "strands: %zu points", total);
  for (size_t k = 0; k < 3 * total; k++)
    if (!isfinite(xyz[k]))
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "strands: point %zu is not finite", k / 3);
  for (size_t k = 0; thickness && k < total; k++)
    if (!(thickness[k] >= 0.0f && isfinite(thickness[k])))
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "strands: point %zu has thickness %g", k,
                            (double)thickness[k]);
  *points = total;
  return SATF_OK;
}

static float dist3(const float a[3], const float b[3]) {
  float d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  return sqrtf(satf_dot3f(d, d));
}

/* The vertices (two per point) and the segments' first points. */
static void fill_vertices(strands_gpu *s, const int *counts, strand_vertex *v) {
  size_t at = 0, seg = 0;
  for (int i = 0; i < s->nstrands; i++) {
    const float *p = s->points + 4 * at;
    int n = counts[i];
    float len = 0.0f, run = 0.0f;
    for (int j = 1; j < n; j++)
      len += dist3(p + 4 * j, p + 4 * j - 4);
    for (int j = 0; j < n; j++) {
      if (j > 0) {
        run += dist3(p + 4 * j, p + 4 * j - 4);
        s->first[seg++] = (uint32_t)(at + (size_t)j - 1);
      }
      /* the direction between the neighbours, the end segment's at the
       * ends: both quads at a point see the same */
      const float *a = p + 4 * (j > 0 ? j - 1 : j);
      const float *b = p + 4 * (j < n - 1 ? j + 1 : j);
      strand_vertex x;
      memcpy(x.pos, p + 4 * j, sizeof x.pos);
      for (int c = 0; c < 3; c++)
        x.tangent[c] = b[c] - a[c];
      x.t = len > 0.0f ? run / len : 0.0f;
      x.strand = (uint32_t)i;
      v[2 * (at + (size_t)j)] = x;
      v[2 * (at + (size_t)j) + 1] = x;
    }
    at += (size_t)n;
  }
}

/* The vertex buffer (static) and the index buffer (written each frame,
 * segments far to near). */
static satf_status upload(strands_gpu *s, const int *counts, satf_error *err) {
  size_t bytes = 2 * s->npoints * sizeof(strand_vertex);
  strand_vertex *v = malloc(bytes);
  if (!v)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  fill_vertices(s, counts, v);
  glGenVertexArrays(1, &s->vao);
  glGenBuffers(1, &s->vbo);
  glGenBuffers(1, &s->ibo);
  glBindVertexArray(s->vao);
  glBindBuffer(GL_ARRAY_BUFFER, s->vbo);
  glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)bytes, v, GL_STATIC_DRAW);
  free(v);
  GLsizei stride = (GLsizei)sizeof(strand_vertex);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, stride,
                        (void *)offsetof(strand_vertex, pos));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                        (void *)offsetof(strand_vertex, tangent));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride,
                        (void *)offsetof(strand_vertex, t));
  glEnableVertexAttribArray(3);
  glVertexAttribIPointer(3, 1, GL_UNSIGNED_INT, stride,
                         (void *)offsetof(strand_vertex, strand));
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, s->ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER,
               (GLsizeiptr)(6 * s->nsegs * sizeof(uint32_t)), NULL,
               GL_STREAM_DRAW);
  glBindVertexArray(0);
  glGenBuffers(1, &s->light_buf); /* filled by strands_gpu_begin */
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, s->light_buf);
  glBufferData(GL_SHADER_STORAGE_BUFFER,
               (GLsizeiptr)(s->npoints * 4 * STRAND_LIGHT_VEC4 * sizeof(float)),
               NULL, GL_DYNAMIC_COPY);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  return satf_gl_check("strand buffers", err);
}

/* The physical strands' width in pixels above which the shading samples
 * the offsets each pixel covers (strand_fs.glsl STRAND_EXACT_WIDTH). */
#define STRAND_EXACT_PX 2.0
#define STRAND_TEXT(x) #x
#define STRAND_DEFINE_EXACT(x) "#define STRAND_EXACT_WIDTH " STRAND_TEXT(x) "\n"

/* Both materials' programs: GL compiles a program's code when it is first
 * drawn with, so those a scene does not use cost only their linking. */
static satf_status build_strand_programs(strands_gpu *s, int list,
                                         satf_error *err) {
  static const char *const model[3] = {
      "", "#define PHYSICAL 1\n",
      "#define PHYSICAL 1\n" STRAND_DEFINE_EXACT(STRAND_EXACT_PX)};
  static const char *const label[3] = {"strands", "strands (physical)",
                                       "strands (physical, wide)"};
  satf_status st = SATF_OK;
  char extra[160];
  for (int m = 0; m < 3 && st == SATF_OK; m++)
    st = shaders_program(label[m], satf_glsl_strand_vs, satf_glsl_strand_fs,
                         model[m], &s->prog_shade[m], err);
  for (int m = 0; m < 3 && st == SATF_OK && list; m++) {
    snprintf(extra, sizeof extra, "#define LIST 1\n%s", model[m]);
    st = shaders_program("strands (fragment arrays)", satf_glsl_strand_vs,
                         satf_glsl_strand_fs, extra, &s->prog_list[m], err);
  }
  if (st == SATF_OK)
    st = shaders_compute("strands (light per point)", satf_glsl_strand_light_cs,
                         "", &s->prog_light, err);
  if (st == SATF_OK)
    st = shaders_program("strands (opacity map)", satf_glsl_strand_vs,
                         satf_glsl_strand_dom_fs, "", &s->prog_dom, err);
  if (st == SATF_OK && list)
    st = shaders_program("strands (opaque depth)", satf_glsl_strand_vs,
                         satf_glsl_strand_dom_fs, "#define WHOLE_DEPTH 1\n",
                         &s->prog_depth, err);
  return st;
}

/* The ribbons' bounds (the renderer's camera clip planes and light map
 * grow by them). */
static void strand_bounds(strands_gpu *s) {
  for (int a = 0; a < 3; a++) {
    s->lo[a] = INFINITY;
    s->hi[a] = -INFINITY;
  }
  for (size_t k = 0; k < s->npoints; k++)
    for (int a = 0; a < 3; a++) {
      float v = s->points[4 * k + (size_t)a], h = 0.5f * s->points[4 * k + 3];
      s->lo[a] = v - h < s->lo[a] ? v - h : s->lo[a];
      s->hi[a] = v + h > s->hi[a] ? v + h : s->hi[a];
    }
}

static int float_less(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

/* The median of the n points' widths (points: x, y, z, width each); 0 if
 * out of memory. */
static float median_width(const float *points, size_t n) {
  float *w = malloc((n > 0 ? n : 1) * sizeof *w);
  if (!w || n == 0) {
    free(w);
    return 0.0f;
  }
  for (size_t k = 0; k < n; k++)
    w[k] = points[4 * k + 3];
  qsort(w, n, sizeof *w, float_less);
  float m = w[n / 2];
  free(w);
  return m;
}

float strands_gpu_width(const strands_gpu *s) { return s ? s->width : 0.0f; }

int strands_gpu_count(const strands_gpu *s) { return s ? s->nstrands : 0; }

void strands_gpu_bounds(const strands_gpu *s, float lo[3], float hi[3]) {
  memcpy(lo, s->lo, sizeof s->lo);
  memcpy(hi, s->hi, sizeof s->hi);
}

static satf_status create_checked(int n_strands, const int *counts,
                                  const float *xyz, const float *thickness,
                                  float default_width, size_t total, int list,
                                  strands_gpu **out, satf_error *err);

satf_status strands_gpu_create(int n_strands, const int *counts,
                               const float *xyz, const float *thickness,
                               float default_width, int list, int curves,
                               strands_gpu **out, satf_error *err) {
  *out = NULL;
  size_t total = 0;
  satf_status st = check_input(n_strands, counts, xyz, thickness, default_width,
                               &total, err);
  if (st != SATF_OK || n_strands == 0)
    return st;
  if (!curves)
    return create_checked(n_strands, counts, xyz, thickness, default_width,
                          total, list, out, err);
  strand_curve c;
  st = strand_curve_refine(n_strands, counts, xyz, thickness, default_width, &c,
                           err);
  if (st == SATF_OK)
    st = create_checked(c.n, c.counts, c.xyz, c.width, 0.0f, c.total, list, out,
                        err);
  strand_curve_free(&c);
  return st;
}

/* strands_gpu_create of input check_input passed (total points) */
static satf_status create_checked(int n_strands, const int *counts,
                                  const float *xyz, const float *thickness,
                                  float default_width, size_t total, int list,
                                  strands_gpu **out, satf_error *err) {
  satf_status st;
  strands_gpu *s = calloc(1, sizeof *s);
  if (!s)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  /* the physical shading reads the dual scattering's global term and back
   * scattering from their tables (strand_fs.glsl), the light per point the
   * lobes' azimuthal scattering (strand_light_cs.glsl) */
  s->fiber.with_global = 1;
  s->fiber.with_azimuthal = 1;
  s->nstrands = n_strands;
  s->npoints = total;
  s->nsegs = total - (size_t)n_strands;
  s->points = malloc(total * 4 * sizeof(float));
  s->first = malloc(s->nsegs * sizeof(uint32_t));
  s->keys = malloc(s->nsegs * sizeof(uint32_t));
  s->order = malloc(s->nsegs * sizeof(uint32_t));
  s->tmp_keys = malloc(s->nsegs * sizeof(uint32_t));
  s->tmp_order = malloc(s->nsegs * sizeof(uint32_t));
  s->indices = malloc(6 * s->nsegs * sizeof(uint32_t));
  if (!s->points || !s->first || !s->keys || !s->order || !s->tmp_keys ||
      !s->tmp_order || !s->indices) {
    free_data(s);
    free(s);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  for (size_t k = 0; k < total; k++) {
    memcpy(s->points + 4 * k, xyz + 3 * k, 3 * sizeof(float));
    s->points[4 * k + 3] = thickness ? thickness[k] : default_width;
  }
  s->width = median_width(s->points, total);
  st = upload(s, counts, err);
  if (st == SATF_OK)
    st = build_strand_programs(s, list, err);
  if (st != SATF_OK) {
    strands_gpu_destroy(s);
    return st;
  }
  strand_bounds(s);
  *out = s;
  return SATF_OK;
}

static void write_indices(strands_gpu *s, const uint32_t *order);

/* An LSD radix sort (four byte passes)
 * of their midpoints' squared distances, whose float bits order as the
 * values do (they are >= 0); ties keep the strands' order. */
void strands_gpu_sort(strands_gpu *s, const float eye[3]) {
  size_t n = s->nsegs;
  for (size_t i = 0; i < n; i++) {
    const float *a = s->points + 4 * (size_t)s->first[i], *b = a + 4;
    float d2 = 0.0f;
    for (int c = 0; c < 3; c++) {
      float d = 0.5f * (a[c] + b[c]) - eye[c];
      d2 += d * d;
    }
    uint32_t bits;
    memcpy(&bits, &d2, sizeof bits);
    s->keys[i] = ~bits; /* far first */
    s->order[i] = s->first[i];
  }
  uint32_t *k0 = s->keys, *o0 = s->order, *k1 = s->tmp_keys, *o1 = s->tmp_order;
  for (int shift = 0; shift < 32; shift += 8) {
    size_t count[257] = {0};
    for (size_t i = 0; i < n; i++)
      count[((k0[i] >> shift) & 255u) + 1]++;
    for (int b = 0; b < 256; b++)
      count[b + 1] += count[b];
    for (size_t i = 0; i < n; i++) {
      size_t at = count[(k0[i] >> shift) & 255u]++;
      k1[at] = k0[i];
      o1[at] = o0[i];
    }
    uint32_t *t = k0;
    k0 = k1;
    k1 = t;
    t = o0;
    o0 = o1;
    o1 = t;
  }
  /* four passes: the sorted arrays are back in keys/order */
  write_indices(s, s->order);
}

void strands_gpu_in_order(strands_gpu *s) { write_indices(s, s->first); }

/* The index buffer: segments (their first points) in the order given, each
 * two triangles of its points' side vertices. */
static void write_indices(strands_gpu *s, const uint32_t *order) {
  size_t n = s->nsegs;
  for (size_t i = 0; i < n; i++) {
    uint32_t a = 2 * order[i], *q = s->indices + 6 * i;
    q[0] = a;
    q[1] = a + 2;
    q[2] = a + 3;
    q[3] = a;
    q[4] = a + 3;
    q[5] = a + 1;
  }
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, s->ibo);
  glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0,
                  (GLsizeiptr)(6 * n * sizeof(uint32_t)), s->indices);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
}

/* Pixels per scene unit at clip w = 1 for a target h pixels high: the
 * projection's y scale (row 1 of a look-at view is the unit up vector)
 * times half the height. */
static float px_scale(const float viewproj[16], int h) {
  return sqrtf(viewproj[4] * viewproj[4] + viewproj[5] * viewproj[5] +
               viewproj[6] * viewproj[6]) *
         0.5f * (float)h;
}

/* Whether some point of a strand in front of the eye is at least a pixel
 * wide there: otherwise no fragment is covered whole. */
/* Whether a point in front of the eye is at least px pixels wide. */
static int any_wider(const strands_gpu *s, const float viewproj[16], int h,
                     float px) {
  float k = px_scale(viewproj, h);
  for (size_t i = 0; i < s->npoints; i++) {
    const float *p = s->points + 4 * i;
    float w = viewproj[12] * p[0] + viewproj[13] * p[1] + viewproj[14] * p[2] +
              viewproj[15];
    if (w > 0.0f && p[3] * k >= px * w)
      return 1;
  }
  return 0;
}

int strands_gpu_any_wide(const strands_gpu *s, const float viewproj[16],
                         int h) {
  return any_wider(s, viewproj, h, 0.999f);
}

/* The pixel filter r draws strands with: AUTO resolved by the hair's
 * strand count (SATF_RENDER_FILTER_AUTO_STRANDS), the strands set where
 * the renderer draws them, else the scene's clusters' strands, so the
 * strand path and the cluster path of one imported hair (the strands file
 * and its clusters) take the same filter. */
static satf_pixel_filter strands_filter(const satf_renderer *r) {
  if (r->pixel_filter != SATF_PIXEL_FILTER_AUTO)
    return r->pixel_filter;
  long n = r->strands ? (long)strands_gpu_count(r->strands) : r->stats.strands;
  return n <= SATF_RENDER_FILTER_AUTO_STRANDS
             ? SATF_PIXEL_FILTER_BLACKMAN_HARRIS
             : SATF_PIXEL_FILTER_BOX;
}

/* The vertex shader's view uniforms of `prog` for a w x h target, and the
 * pixel filter of its coverage (strand_cover.glsl: 0 box, 1
 * Blackman-Harris). */
static void bind_strands(GLuint prog, const float viewproj[16], int w, int h,
                         satf_pixel_filter filter) {
  glUseProgram(prog);
  glUniform1i(glGetUniformLocation(prog, "u_pixel_filter"), (int)filter);
  glUniformMatrix4fv(glGetUniformLocation(prog, "u_viewproj"), 1, GL_TRUE,
                     viewproj);
  glUniform2f(glGetUniformLocation(prog, "u_viewport"), (float)w, (float)h);
  glUniform1f(glGetUniformLocation(prog, "u_px_scale"), px_scale(viewproj, h));
}

void strands_gpu_draw(const strands_gpu *s, size_t first, size_t count) {
  glBindVertexArray(s->vao);
  glDrawElements(GL_TRIANGLES, (GLsizei)(6 * count), GL_UNSIGNED_INT,
                 (void *)(6 * first * sizeof(uint32_t)));
  glBindVertexArray(0);
}

void strands_gpu_use(const strands_gpu *s) { glUseProgram(s->prog_bound); }

void strands_gpu_whole(const strands_gpu *s, int whole) {
  glUniform1i(glGetUniformLocation(s->prog_bound, "u_whole"), whole);
}

int strands_gpu_opaque_depth(const satf_renderer *r, const strands_gpu *s,
                             const float viewproj[16]) {
  if (!s->prog_depth || !strands_gpu_any_wide(s, viewproj, r->view.height))
    return 0; /* hair thinner than a pixel covers none whole */
  bind_strands(s->prog_depth, viewproj, r->view.width, r->view.height,
               strands_filter(r));
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  strands_gpu_draw(s, 0, s->nsegs);
  glDepthMask(GL_FALSE);
  glDisable(GL_DEPTH_TEST);
  return 1;
}

static void draw_segments(const strands_gpu *s) {
  strands_gpu_draw(s, 0, s->nsegs);
}

size_t strands_gpu_segments(const strands_gpu *s) { return s->nsegs; }

void strands_gpu_dom(satf_renderer *r, strands_gpu *s, int opacity) {
  /* a box: the map's texels are coverage, not a film */
  bind_strands(s->prog_dom, r->dom.viewproj, DOM_SIZE, DOM_SIZE,
               SATF_PIXEL_FILTER_BOX);
  glUniform1i(glGetUniformLocation(s->prog_dom, "u_depth_only"), !opacity);
  if (opacity)
    dom_uniforms(&r->dom, s->prog_dom);
  draw_segments(s);
}

/* The physical material's uniforms of `p` and its dual-scattering tables
 * (fiber_gpu.h). The tables' unit is made active first: the passes leave
 * unit 3 (the deep opacity map) active, and a first bind of the tables
 * there replaced the map for that frame. */
static void set_fiber_uniforms(const satf_renderer *r, strands_gpu *s,
                               GLuint p) {
  const satf_scene_material *m = &r->scene->material;
  if (m->model != SATF_MATERIAL_PHYSICAL) {
    /* unread, but GL refuses a draw whose samplers of two types share a
     * unit: each of the fibre's on its own */
    glUniform1i(glGetUniformLocation(p, "u_fiber_tables"), FIBER_TABLE_UNIT);
    glUniform1i(glGetUniformLocation(p, "u_fiber_global"),
                FIBER_TABLE_UNIT + 1);
    glUniform1i(glGetUniformLocation(p, "u_fiber_back"), FIBER_TABLE_UNIT + 2);
    glUniform1i(glGetUniformLocation(p, "u_fiber_azimuthal"),
                FIBER_AZIMUTHAL_UNIT);
    glUniform1i(glGetUniformLocation(p, "u_fiber_mp"),
                FIBER_AZIMUTHAL_UNIT + 1);
    return;
  }
  glActiveTexture(GL_TEXTURE0 + FIBER_TABLE_UNIT);
  fiber_gpu_bind(&s->fiber, m, p);
}

/* The physical material's light at every point for this frame's eye and
 * lights (strand_light_cs.glsl), for the programs that read it. */
static void light_points(const satf_renderer *r, strands_gpu *s, satf_aov aov) {
  GLuint p = s->prog_light;
  draw_shading_uniforms(r, p, aov);
  set_fiber_uniforms(r, s, p);
  draw_world_lights(r, p);
  glUniform1i(glGetUniformLocation(p, "u_npoints"), (int)s->npoints);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, s->vbo);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, s->light_buf);
  /* 64 points a group, in rows of at most 65535 groups (GL's least
   * limit on a dispatch's width) */
  size_t groups = (s->npoints + 63) / 64,
         wide = groups < 65535 ? groups : 65535;
  glDispatchCompute((GLuint)wide, (GLuint)((groups + wide - 1) / wide), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void strands_gpu_begin(const satf_renderer *r, strands_gpu *s, satf_aov aov,
                       const float viewproj[16], int list_mode) {
  int physical = r->scene->material.model == SATF_MATERIAL_PHYSICAL;
  /* the nearest passes (list modes 1 and 2) follow a plain pass of the
   * same frame, whose light per point they read as it left it */
  if (physical && list_mode <= 0)
    light_points(r, s, aov);
  /* the program with the per-pixel offsets only where a strand needs it
   * (the margin: the shader's width is interpolated, the test is per
   * point) */
  int m = !physical                                                        ? 0
          : any_wider(s, viewproj, r->view.height, 0.9f * STRAND_EXACT_PX) ? 2
                                                                           : 1;
  GLuint p = list_mode >= 0 ? s->prog_list[m] : s->prog_shade[m];
  s->prog_bound = p;
  draw_shading_uniforms(r, p, aov);
  set_fiber_uniforms(r, s, p);
  draw_world_lights(r, p);
  bind_strands(p, viewproj, r->view.width, r->view.height, strands_filter(r));
  glUniform1i(glGetUniformLocation(p, "u_whole"), -1);
  if (list_mode >= 0)
    glUniform1i(glGetUniformLocation(p, "u_list_mode"), list_mode);
}

/* The fragments the strands cover whole first, with the depth test and
 * writes of opaque surfaces (exact visibility among overlapping wide
 * strands, which painter's order per segment gets wrong where long ribbons
 * cross at nearly the same depth); then the partly covered fragments,
 * segments in their sorted order (far to near), "over" blended and tested
 * against all that depth. */
void strands_gpu_composite(const satf_renderer *r, strands_gpu *s, satf_aov aov,
                           const float viewproj[16]) {
  size_t segs = strands_gpu_segments(s);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); /* premultiplied "over" */
  glDisable(GL_CULL_FACE); /* a ribbon faces the eye either way round */
  strands_gpu_begin(r, s, aov, viewproj, -1);
  /* hair thinner than a pixel covers none whole */
  if (strands_gpu_any_wide(s, viewproj, r->view.height)) {
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    strands_gpu_whole(s, 1);
    strands_gpu_draw(s, 0, segs);
  }
  draw_hair_depth_test(1);
  strands_gpu_whole(s, 0);
  strands_gpu_draw(s, 0, segs);
  glDisable(GL_BLEND);
  draw_hair_depth_test(0);
}
