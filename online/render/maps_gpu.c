/* maps_gpu.c - see maps_gpu.h. */
#include "maps_gpu.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "half.h"
#include "maps_gpu_bytes.h"
#include "maps_gpu_fiber.h"
#include "renderer_internal.h"
#include "satf/common.h"
#include "shaders.h"
#include "storage.h"

/* the shader storage buffers, at these bindings (maps_kk_cs.glsl; the
 * records are the fibre records and the last three the physical mode's,
 * maps_fiber_cs.glsl) */
enum {
  BUF_RECORDS,
  BUF_COLUMNS,
  BUF_LEVELS,
  BUF_SECTORS,
  BUF_NEIGHBORS,
  BUF_INSTS,
  BUF_LIGHTS,
  BUF_MP,
  BUF_REL,
  BUF_COUNT
};

/* an instance's entry of BUF_INSTS (std430 MapsInst) */
typedef struct gpu_inst {
  float eye[4], light[4];
  int32_t base[4];  /* first sector, sector and HSV neighbours, layer */
  int32_t shell[4]; /* su, st, layers, orientation-free */
} gpu_inst;

struct maps_gpu {
  GLuint prog, prog_sums, buf[BUF_COUNT];
  GLint u_first, u_first_sums, u_n_lights, u_trt;
  int k;     /* neighbours per entry (MAPS_K) */
  int fiber; /* the physical mode's maps (maps_fiber_cs.glsl) */
  /* per instance: the geometry serial its sectors and neighbours were
   * uploaded for (0: none) and where they start (gpu_inst.base[0..2]) */
  int ninsts;
  unsigned long *serial;
  int32_t (*base)[3];
  gpu_inst *insts; /* this frame's entries */
  float *lights;   /* theirs in the physical mode (maps_gpu_fiber.h) */
};

void maps_gpu_destroy(maps_gpu *g) {
  if (!g)
    return;
  if (g->prog)
    glDeleteProgram(g->prog);
  if (g->prog_sums)
    glDeleteProgram(g->prog_sums);
  glDeleteBuffers(BUF_COUNT, g->buf);
  free(g->serial);
  free(g->base);
  free(g->insts);
  free(g->lights);
  free(g);
}

/* The database's reflectance and alpha, every record, as the halfs they
 * are (satf_db_finalize rounds them), in maps_kk_cs.glsl's order. */
static satf_status upload_records(const satf_db *db, GLuint buf,
                                  satf_error *err) {
  const satf_build_params *p = satf_db_params(db);
  int w = p->trace.width;
  size_t halfs = maps_gpu_kk_halfs(p);
  satf_status st =
      storage_fits(halfs, 2, "reflectance and alpha values", "halfs", err);
  if (st != SATF_OK)
    return st;
  uint16_t *h = calloc(halfs + 1, sizeof *h); /* whole words */
  if (!h)
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate %zu database halfs", halfs);
  uint16_t *o = h;
  for (int s = 0; s < p->samples; s++)
    for (int il = 0; il < p->n_light; il++)
      for (int iv = 0; iv < p->n_view; iv++, o += 2 * w) {
        const float *re, *al;
        satf_db_record(db, s, iv, il, &re, &al);
        half_pack(re, o, (size_t)w);
        half_pack(al, o + w, (size_t)w);
      }
  storage_upload(buf, maps_gpu_half_bytes(halfs), h);
  free(h);
  return SATF_OK;
}

satf_status maps_gpu_create(const satf_renderer *r, maps_gpu **out,
                            satf_error *err) {
  *out = NULL;
  maps_gpu *g = calloc(1, sizeof *g);
  if (!g)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  g->k = maps_gpu_k(&r->map_opt);
  g->fiber = r->fiber != NULL;
  char defines[400];
  snprintf(defines, sizeof defines,
           "#define MAPS_W %d\n#define MAPS_BINS %d\n#define MAPS_K %d\n"
           "#define PHYSICAL %d\n#define MAPS_SECTOR_FLOATS %d\n",
           r->w, MAPS_AZIMUTH_BINS, g->k, g->fiber, MAPS_GPU_SECTOR_FLOATS);
  if (g->fiber)
    maps_gpu_fiber_defines(r, defines, sizeof defines);
  satf_status st =
      shaders_compute(g->fiber ? "physical maps (GPU)" : "maps (GPU)",
                      g->fiber ? satf_glsl_maps_fiber_cs : satf_glsl_maps_kk_cs,
                      defines, &g->prog, err);
  if (st == SATF_OK)
    st = shaders_compute("maps' s-map sums (GPU)", satf_glsl_maps_sums_cs,
                         defines, &g->prog_sums, err);
  if (st != SATF_OK) {
    maps_gpu_destroy(g);
    return st;
  }
  glGenBuffers(BUF_COUNT, g->buf);
  st = g->fiber ? maps_gpu_fiber_tables(r, g->prog, g->buf[BUF_RECORDS],
                                        g->buf[BUF_MP], g->buf[BUF_REL], err)
                : upload_records(r->db, g->buf[BUF_RECORDS], err);
  size_t cols = maps_gpu_column_floats(r->w) / 2;
  int samples = satf_db_samples(r->db);
  float *col = st == SATF_OK ? malloc(cols * 2 * sizeof *col) : NULL;
  if (st == SATF_OK && !col)
    st = satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  if (st != SATF_OK) {
    maps_gpu_destroy(g);
    return st;
  }
  const uint16_t *index;
  const float *frac;
  maps_column_table(r->maps, &index, &frac);
  for (size_t c = 0; c < cols; c++) {
    col[2 * c] = (float)index[c];
    col[2 * c + 1] = frac[c];
  }
  storage_upload(g->buf[BUF_COLUMNS], cols * 2 * sizeof *col, col);
  free(col);
  storage_upload(g->buf[BUF_LEVELS], (size_t)samples * sizeof(float),
                 maps_sample_levels(r->maps));
  const satf_build_params *p = satf_db_params(r->db);
  float lo[SATF_FEATURES], hi[SATF_FEATURES], scale[SATF_FEATURES];
  satf_db_feature_range(r->db, lo, hi);
  for (int a = 0; a < SATF_FEATURES; a++) /* maps.c: satf_maps_create */
    scale[a] = hi[a] > lo[a] ? 1.0f / (hi[a] - lo[a]) : 1.0f;
  glUseProgram(g->prog);
  glUniform1i(glGetUniformLocation(g->prog, "u_n_view"), p->n_view);
  glUniform1i(glGetUniformLocation(g->prog, "u_n_light"), p->n_light);
  glUniform1f(glGetUniformLocation(g->prog, "u_re_scale"),
              maps_reflectance_scale(r->maps));
  glUniform3fv(glGetUniformLocation(g->prog, "u_fscale"), 1, scale);
  glUniform1f(glGetUniformLocation(g->prog, "u_threshold"),
              r->map_opt.k_threshold);
  g->u_first = glGetUniformLocation(g->prog, "u_first");
  g->u_first_sums = glGetUniformLocation(g->prog_sums, "u_first");
  g->u_n_lights = glGetUniformLocation(g->prog, "u_n_lights");
  g->u_trt = glGetUniformLocation(g->prog, "u_trt");
  glUseProgram(0);
  st = satf_gl_check("maps (GPU) tables", err);
  if (st != SATF_OK) {
    maps_gpu_destroy(g);
    return st;
  }
  *out = g;
  return SATF_OK;
}

/* The neighbours of entry e (sector or HSV) into nb, MAPS_K slots, weight
 * 0 past those found. */
static void put_neighbors(const satf_db_neighbors *e, int k, uint32_t *nb) {
  for (int n = 0; n < k; n++) {
    uint32_t idx = 0, wbits = 0;
    if (n < e->count) {
      idx = (uint32_t)e->index[n];
      memcpy(&wbits, &e->weight[n], sizeof wbits);
    }
    nb[2 * n] = idx;
    nb[2 * n + 1] = wbits;
  }
}

/* Whether instance i has maps (its prototype is drawn as a cluster). */
static int has_maps(const satf_renderer *r, int i) {
  const proto *p = &r->protos[r->insts[i].proto];
  return p->ready && !p->sparse;
}

/* Every instance's sectors and neighbours uploaded again (one geometry
 * once where instances share it: a prototype's, not a VDB's). */
static satf_status upload_geometry(const satf_renderer *r, maps_gpu *g,
                                   satf_error *err) {
  if (g->ninsts != r->ninsts) {
    free(g->serial);
    free(g->base);
    free(g->insts);
    free(g->lights);
    g->ninsts = 0;
    size_t n = (size_t)(r->ninsts > 0 ? r->ninsts : 1);
    g->serial = calloc(n, sizeof *g->serial);
    g->base = calloc(n, sizeof *g->base);
    g->insts = calloc(n, sizeof *g->insts);
    g->lights = calloc(n * MAPS_GPU_FIBER_LIGHT_VEC4S * 4, sizeof *g->lights);
    if (!g->serial || !g->base || !g->insts || !g->lights)
      return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
    g->ninsts = r->ninsts;
  }
  size_t sectors = 0, hsvs = 0;
  for (int i = 0; i < r->ninsts; i++) {
    const satf_shell_geom *geom = &r->insts[i].geom;
    if (!has_maps(r, i) ||
        (i > 0 && r->insts[i - 1].geom.serial == geom->serial &&
         has_maps(r, i - 1)))
      continue;
    size_t ns = satf_shell_sector_count(&geom->shell);
    sectors += ns;
    hsvs += satf_shell_hsv_count(&geom->shell);
  }
  if (sectors > (size_t)INT32_MAX / MAPS_GPU_SECTOR_FLOATS ||
      sectors + hsvs > (size_t)INT32_MAX / (size_t)g->k)
    return satf_error_set(err, SATF_ERR_INCOMPATIBLE,
                          "%zu sectors: more than the GPU's maps index",
                          sectors);
  size_t sec_bytes = maps_gpu_sector_bytes(sectors);
  size_t nb_bytes = maps_gpu_neighbor_bytes(sectors, hsvs, g->k);
  float *sec = malloc(sec_bytes > 0 ? sec_bytes : 1);
  uint32_t *nb = malloc(nb_bytes > 0 ? nb_bytes : 1);
  if (!sec || !nb) {
    free(sec);
    free(nb);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate the GPU's copy of %zu sectors",
                          sectors);
  }
  size_t s0 = 0, e0 = 0;
  for (int i = 0; i < r->ninsts; i++) {
    const satf_shell_geom *geom = &r->insts[i].geom;
    g->serial[i] = 0;
    if (!has_maps(r, i))
      continue;
    if (i > 0 && g->serial[i - 1] == geom->serial) {
      memcpy(g->base[i], g->base[i - 1], sizeof g->base[i]);
      g->serial[i] = geom->serial;
      continue;
    }
    const satf_shell_params *sh = &geom->shell;
    size_t ns = satf_shell_sector_count(sh);
    size_t nh = satf_shell_hsv_count(sh);
    if (!maps_sector_neighbors(geom, 0, g->k) ||
        !maps_hsv_neighbors(geom, 0, g->k)) {
      free(sec);
      free(nb);
      return satf_error_set(err, SATF_ERR_INCOMPATIBLE,
                            "%s: cluster instance %d has no neighbours "
                            "cached for k = %d, which the GPU's maps read",
                            scene_name(r->scene), i, g->k);
    }
    for (size_t q = 0; q < ns; q++) {
      memcpy(sec + (s0 + q) * MAPS_GPU_SECTOR_FLOATS, geom->frames + 9 * q,
             9 * sizeof(float));
      memcpy(sec + (s0 + q) * MAPS_GPU_SECTOR_FLOATS + 9,
             geom->features + 3 * q, 3 * sizeof(float));
      float *hair = sec + (s0 + q) * MAPS_GPU_SECTOR_FLOATS + 12;
      if (geom->hair)
        memcpy(hair, geom->hair + 3 * q, 3 * sizeof(float));
      else
        hair[0] = hair[1] = hair[2] = 0.0f;
      put_neighbors(maps_sector_neighbors(geom, q, g->k), g->k,
                    nb + (e0 + q) * 2 * (size_t)g->k);
    }
    for (size_t q = 0; q < nh; q++)
      put_neighbors(maps_hsv_neighbors(geom, q, g->k), g->k,
                    nb + (e0 + ns + q) * 2 * (size_t)g->k);
    g->base[i][0] = (int32_t)s0;
    g->base[i][1] = (int32_t)e0;
    g->base[i][2] = (int32_t)(e0 + ns);
    g->serial[i] = geom->serial;
    s0 += ns;
    e0 += ns + nh;
  }
  storage_upload(g->buf[BUF_SECTORS], sec_bytes, sec);
  storage_upload(g->buf[BUF_NEIGHBORS], nb_bytes, nb);
  free(sec);
  free(nb);
  return SATF_OK;
}

/* Whether some instance's geometry changed since its upload. */
static int geometry_stale(const satf_renderer *r, const maps_gpu *g) {
  if (g->ninsts != r->ninsts)
    return 1;
  for (int i = 0; i < r->ninsts; i++)
    if (has_maps(r, i) && g->serial[i] != r->insts[i].geom.serial)
      return 1;
  return 0;
}

/* Work groups of 64 for `n` invocations, as x by y (x at most 32768:
 * OpenGL allows 65535 a dimension); the shaders number them y-major. */
static void groups(size_t n, GLuint *x, GLuint *y) {
  size_t g = (n + 63) / 64;
  *x = (GLuint)(g < 32768 ? (g > 0 ? g : 1) : 32768);
  *y = (GLuint)((g + *x - 1) / *x);
}

/* The bound program over the n instances moved[], one dispatch per run
 * of instances of one prototype in one texture array (hierarchy.c gives a
 * prototype's instances their layers in order; prototypes of one map size
 * share arrays), work group z the
 * instance's entry: an invocation per HSV (sums 0; per boundary sector,
 * one more row of them, in the physical mode) or per texel of a layer
 * (sums 1). */
static void dispatch(const satf_renderer *r, const maps_gpu *g,
                     const int *moved, int n, GLint u_first, int sums,
                     GLenum access) {
  for (int m = 0; m < n;) {
    const inst *in = &r->insts[moved[m]];
    const satf_shell_params *sh = &in->geom.shell;
    int run = 1;
    while (m + run < n && r->insts[moved[m + run]].tex == in->tex &&
           r->insts[moved[m + run]].proto == in->proto)
      run++;
    glBindImageTexture(0, in->tex, 0, GL_TRUE, 0, access,
                       g->fiber ? GL_RGBA32UI : GL_RGBA16F);
    glUniform1i(u_first, m);
    GLuint x, y;
    size_t items = sums       ? satf_maps_layer_texels(&in->geom, r->w)
                   : g->fiber ? satf_shell_sector_count(sh)
                              : satf_shell_hsv_count(sh);
    groups(items, &x, &y);
    glDispatchCompute(x, y, (GLuint)run);
    m += run;
  }
}

satf_status maps_gpu_build(satf_renderer *r, maps_gpu *g, const int *moved,
                           int n, double *upload_ms, satf_error *err) {
  double t0 = satf_now_seconds();
  satf_status st = SATF_OK;
  if (geometry_stale(r, g))
    st = upload_geometry(r, g, err);
  if (st != SATF_OK)
    return st;
  for (int m = 0; m < n; m++) {
    const inst *in = &r->insts[moved[m]];
    const satf_shell_params *sh = &in->geom.shell;
    gpu_inst *e = &g->insts[m];
    memcpy(e->eye, in->eye, sizeof in->eye);
    e->eye[3] = r->protos[in->proto].tilt; /* maps_fiber_cs.glsl */
    memcpy(e->light, in->light, sizeof e->light);
    memcpy(e->base, g->base[moved[m]], sizeof g->base[0]);
    e->base[3] = in->layer0;
    e->shell[0] = sh->su;
    e->shell[1] = sh->st;
    e->shell[2] = sh->layers;
    /* as kk_layer gives it (cluster_cpu.c) */
    e->shell[3] =
        r->map_opt.orientation_free && r->protos[in->proto].from_strands;
    if (g->fiber)
      maps_gpu_fiber_lights(
          r, in, g->lights + (size_t)m * MAPS_GPU_FIBER_LIGHT_VEC4S * 4);
  }
  size_t nn = (size_t)(n > 0 ? n : 1);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, g->buf[BUF_INSTS]);
  glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(nn * sizeof *g->insts),
               g->insts, GL_STREAM_DRAW);
  if (g->fiber) {
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, g->buf[BUF_LIGHTS]);
    glBufferData(
        GL_SHADER_STORAGE_BUFFER,
        (GLsizeiptr)(nn * MAPS_GPU_FIBER_LIGHT_VEC4S * 4 * sizeof *g->lights),
        g->lights, GL_STREAM_DRAW);
  }
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  *upload_ms = 1e3 * (satf_now_seconds() - t0);
  for (int b = 0; b < BUF_COUNT; b++)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)b, g->buf[b]);
  /* the maps, an invocation per HSV (maps_kk_cs.glsl) or boundary sector
   * (maps_fiber_cs.glsl), then their s-map sums, an invocation per texel
   * of a layer (maps_sums_cs.glsl) */
  glUseProgram(g->prog);
  if (g->fiber) {
    glUniform1i(g->u_n_lights, r->view.nlights);
    glUniform1i(g->u_trt, r->effects.secondary_highlight);
  }
  dispatch(r, g, moved, n, g->u_first, 0, GL_WRITE_ONLY);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  glUseProgram(g->prog_sums);
  dispatch(r, g, moved, n, g->u_first_sums, 1, GL_READ_WRITE);
  /* the shading and the deep opacity map fetch them */
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY,
                     g->fiber ? GL_RGBA32UI : GL_RGBA16F);
  glUseProgram(0);
  return satf_gl_check("maps (GPU)", err);
}
