/* baseline.c - owns the renderer's `--no-satf` path (effects.satf off):
 * Scheuermann 2004 (paper 002), the method SATF's Fig. 4(a) compares
 * against, with nothing from the HRIR database (no records, no database
 * alpha, no eq. 12 s-map). Per prototype it keeps the shell layers as
 * textured polygon patches (paper 002: "layered 2D polygon patches") and a
 * procedural hair texture (base brightness, tangent shift, noise, strand
 * alpha); per frame it draws the paper's four passes with approximate
 * depth sorting, and its own deep opacity map from the texture's alpha.
 * Shading: baseline_fs.glsl. Built on the first baseline frame, rebuilt
 * for a prototype whose shape an animation changed. */
#include "renderer_internal.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "depth.h"
#include "draw.h"
#include "path.h"
#include "satf/common.h"
#include "shaders.h"

/* The hair texture: TEX_U texels around a layer holding TEX_STRANDS
 * strands, TEX_T texels along it (mip-mapped: a strand is a few texels
 * wide, a few pixels or less on screen). */
#define TEX_U 1024
#define TEX_T 128
#define TEX_STRANDS 96
/* Optical depth along the normal through all of a cluster's layers: each
 * of L layers covers 1 - exp(-TAU / L) of its area, so the cluster blocks
 * ~95% of what is behind it whatever its layer count. */
#define TAU 3.0
/* Paper 002's first pass keeps "the opaque regions": texels at least this
 * opaque. */
#define OPAQUE_ALPHA 0.95f
/* The deep opacity map's first hair: texels at least this opaque. */
#define DOM_ALPHA 0.05f
/* The shift texture spans [-SHIFT_RANGE / 2, SHIFT_RANGE / 2] around each
 * highlight's own shift. */
#define SHIFT_RANGE 0.2f
/* Base brightness is stored as b / BASE_SCALE, b in [0.7, 1.2]. */
#define BASE_SCALE 1.25f

/* Vertex: position, normal, hair tangent, uv, ambient occlusion. */
enum { VERTEX_FLOATS = 12 };

typedef struct base_proto {
  GLuint vao, vbo, ibo, tex;
  GLsizei layer_count; /* indices per layer; layer k starts at k times it */
  int layers;
  float sig[32]; /* the shape it was built for (signature) */
} base_proto;

struct baseline {
  GLuint prog_shade, prog_alpha, prog_dom;
  GLuint prog_list; /* the depth AOV's: patches into the fragment arrays */
  int nprotos;
  base_proto *protos;
};

/* ---- the hair texture ------------------------------------------------- */

static uint32_t hash32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

/* A value in [0, 1) for (strand, channel, row). */
static float rand01(uint32_t strand, uint32_t channel, uint32_t row) {
  return (float)(hash32(strand * 0x9e3779b9u ^ hash32(channel * 131u + row)) >>
                 8) *
         (1.0f / 16777216.0f);
}

/* Smooth value noise along t for strand s and channel c (rows per t). */
static float strand_noise(uint32_t s, uint32_t c, float t, float rows) {
  float y = t * rows, f = y - floorf(y);
  uint32_t r = (uint32_t)y;
  f = f * f * (3.0f - 2.0f * f);
  return rand01(s, c, r) + f * (rand01(s, c, r + 1) - rand01(s, c, r));
}

static float smoothstepf(float e0, float e1, float x) {
  float f = (x - e0) / (e1 - e0);
  f = f < 0.0f ? 0.0f : f > 1.0f ? 1.0f : f;
  return f * f * (3.0f - 2.0f * f);
}

/* Texel (x, y) of the procedural hair texture for layers of coverage
 * `cover` (mean alpha): strands as stripes along t, each with its own
 * alpha (some fully opaque, so the opaque pass has work), length (tips fade
 * out before t = 1), brightness, tangent shift and secondary-highlight
 * noise. Every channel is constant across a strand's column, so mip-mapping
 * never mixes in undefined values. */
static void hair_texel(int x, int y, float cover, unsigned char out[4]) {
  float cols = (float)TEX_U / TEX_STRANDS;
  uint32_t s = (uint32_t)((float)x / cols);
  float across = ((float)x + 0.5f) / cols - (float)s; /* 0..1 in column */
  float t = ((float)y + 0.5f) / TEX_T;
  float strand_alpha = 0.5f + 0.7f * rand01(s, 0, 0);
  if (strand_alpha > 1.0f)
    strand_alpha = 1.0f;
  float width = cover / 0.8f; /* 0.8: mean strand alpha x profile */
  width = width > 1.0f ? 1.0f : width;
  float centre = 0.5f + (1.0f - width) * (rand01(s, 1, 0) - 0.5f);
  float d = fabsf(across - centre) / (0.5f * width + 1e-6f);
  float profile = 1.0f - smoothstepf(0.6f, 1.0f, d);
  float length = 0.75f + 0.25f * rand01(s, 2, 0);
  float tip = 1.0f - smoothstepf(length - 0.08f, length, t);
  float a = strand_alpha * profile * tip;
  float base = 0.7f + 0.5f * rand01(s, 3, 0);
  float shift = 0.6f * rand01(s, 4, 0) + 0.4f * strand_noise(s, 5, t, 3.0f);
  float noise = strand_noise(s, 6, t, 6.0f);
  float v[4] = {base / BASE_SCALE, shift, noise, a};
  for (int c = 0; c < 4; c++)
    out[c] = (unsigned char)lrintf(255.0f * v[c]);
}

/* The texture of a prototype with `layers` layers; *mean_alpha: the mean
 * alpha of its finest level. */
static GLuint hair_texture(int layers, float *mean_alpha) {
  unsigned char *px = malloc((size_t)TEX_U * TEX_T * 4);
  if (!px)
    return 0;
  float cover = 1.0f - expf(-(float)TAU / (float)layers);
  double sum = 0.0;
  for (int y = 0; y < TEX_T; y++)
    for (int x = 0; x < TEX_U; x++) {
      unsigned char *p = px + 4 * ((size_t)y * TEX_U + (size_t)x);
      hair_texel(x, y, cover, p);
      sum += p[3] / 255.0;
    }
  *mean_alpha = (float)(sum / ((double)TEX_U * TEX_T));
  GLuint tex;
  glGenTextures(1, &tex);
  glBindTexture(GL_TEXTURE_2D, tex);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, TEX_U, TEX_T, 0, GL_RGBA,
               GL_UNSIGNED_BYTE, px);
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                  GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  free(px);
  return tex;
}

/* ---- the patches ------------------------------------------------------ */

float baseline_layer_occlusion(float mean_alpha, int k, int layers) {
  /* Paper 002 stores "an ambient occlusion term per vertex ... computed in
   * a pre-processing step". Ours: the open sky a layer sees through the
   * layers outside it. Locally the shells are parallel sheets, so every
   * direction of the outward hemisphere crosses each outer layer once and
   * is passed by 1 - mean alpha of it: (1 - a)^(L - 1 - k) for layer k
   * (0 innermost), 1 for the outermost, whatever the direction. */
  return powf(1.0f - mean_alpha, (float)(layers - 1 - k));
}

/* What decides a prototype's patches: its shell and its cylinder sampled
 * along t. */
static void proto_signature(const proto *p, float sig[32]) {
  const satf_shell_params *sh = &p->geom.shell;
  memset(sig, 0, 32 * sizeof(float));
  sig[0] = (float)sh->layers;
  sig[1] = (float)sh->st;
  sig[2] = (float)sh->su;
  sig[3] = sh->core;
  for (int i = 0; i < 4; i++) {
    satf_cluster_section sec;
    satf_cluster_section_at(p->cluster, (float)i / 3.0f, &sec);
    float *o = sig + 4 + 7 * i;
    memcpy(o, sec.center, 3 * sizeof(float));
    o[3] = sec.a;
    o[4] = sec.b;
    o[5] = sec.theta;
    o[6] = sec.n1[0] + 2.0f * sec.n1[1] + 3.0f * sec.n1[2];
  }
}

static void release_proto(base_proto *b) {
  if (b->vao) {
    glDeleteVertexArrays(1, &b->vao);
    glDeleteBuffers(1, &b->vbo);
    glDeleteBuffers(1, &b->ibo);
  }
  if (b->tex)
    glDeleteTextures(1, &b->tex);
  memset(b, 0, sizeof *b);
}

/* Copies layer k's mesh into the vertex and index arrays: uv turned by a
 * per-layer offset (so layers show different strands), AO per vertex. */
static void add_layer(const satf_mesh *mesh, int k, float ao, float *vert,
                      uint32_t *idx) {
  size_t nv = satf_mesh_vertex_count(mesh);
  const satf_mesh_vertex *mv = satf_mesh_vertices(mesh);
  float offset = (float)fmod(0.6180339887 * (k + 1), 1.0);
  for (size_t i = 0; i < nv; i++) {
    float *o = vert + VERTEX_FLOATS * i;
    memcpy(o, mv[i].pos, 3 * sizeof(float));
    memcpy(o + 3, mv[i].normal, 3 * sizeof(float));
    memcpy(o + 6, mv[i].tangent, 3 * sizeof(float));
    o[9] = mv[i].uv[0] + offset;
    o[10] = mv[i].uv[1];
    o[11] = ao;
  }
  const uint32_t *mi = satf_mesh_indices(mesh);
  size_t ni = 3 * satf_mesh_triangle_count(mesh);
  for (size_t i = 0; i < ni; i++)
    idx[i] = mi[i] + (uint32_t)((size_t)k * nv);
}

static void upload_patches(base_proto *b, const float *vert, size_t nv,
                           const uint32_t *idx, size_t ni) {
  glGenVertexArrays(1, &b->vao);
  glGenBuffers(1, &b->vbo);
  glGenBuffers(1, &b->ibo);
  glBindVertexArray(b->vao);
  glBindBuffer(GL_ARRAY_BUFFER, b->vbo);
  glBufferData(GL_ARRAY_BUFFER,
               (GLsizeiptr)(nv * VERTEX_FLOATS * sizeof(float)), vert,
               GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b->ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(ni * sizeof(uint32_t)),
               idx, GL_STATIC_DRAW);
  const GLint sizes[5] = {3, 3, 3, 2, 1};
  const size_t offs[5] = {0, 3, 6, 9, 11};
  for (GLuint a = 0; a < 5; a++) {
    glEnableVertexAttribArray(a);
    glVertexAttribPointer(a, sizes[a], GL_FLOAT, GL_FALSE,
                          VERTEX_FLOATS * sizeof(float),
                          (void *)(offs[a] * sizeof(float)));
  }
  glBindVertexArray(0);
}

/* Every layer mesh of prototype m (SATF sec. 6.1 builds the same shells)
 * in one buffer, innermost first, and its texture. */
static satf_status build_proto(const satf_renderer *r, int m, base_proto *b,
                               satf_error *err) {
  const proto *p = &r->protos[m];
  const satf_shell_params *sh = &p->geom.shell;
  release_proto(b);
  float mean_alpha = 0.0f;
  b->tex = hair_texture(sh->layers, &mean_alpha);
  satf_mesh *grid = NULL;
  float *vert = NULL;
  uint32_t *idx = NULL;
  size_t nv = 0, ni = 0;
  satf_status st = SATF_OK;
  satf_error cerr;
  for (int k = 0; k < sh->layers && st == SATF_OK; k++) {
    satf_mesh *mesh = NULL;
    st = satf_cluster_build_layer_mesh_from(p->cluster, sh, k, grid, &mesh,
                                            &cerr);
    if (st != SATF_OK)
      break;
    if (!vert) {
      nv = satf_mesh_vertex_count(mesh);
      ni = 3 * satf_mesh_triangle_count(mesh);
      vert = malloc((size_t)sh->layers * nv * VERTEX_FLOATS * sizeof(float));
      idx = malloc((size_t)sh->layers * ni * sizeof(uint32_t));
      if (!vert || !idx || !b->tex)
        st = satf_error_set(&cerr, SATF_ERR_NOMEM, "out of memory");
    }
    if (st == SATF_OK)
      add_layer(mesh, k, baseline_layer_occlusion(mean_alpha, k, sh->layers),
                vert + (size_t)k * nv * VERTEX_FLOATS, idx + (size_t)k * ni);
    if (!grid)
      grid = mesh;
    else
      satf_mesh_destroy(mesh);
  }
  if (st == SATF_OK) {
    upload_patches(b, vert, (size_t)sh->layers * nv, idx,
                   (size_t)sh->layers * ni);
    b->layer_count = (GLsizei)ni;
    b->layers = sh->layers;
    proto_signature(p, b->sig);
  }
  satf_mesh_destroy(grid);
  free(vert);
  free(idx);
  if (st != SATF_OK)
    return satf_error_set(err, st,
                          "%s: macro_clusters[%d]: baseline patches: %s",
                          scene_name(r->scene), m, cerr.message);
  return satf_gl_check("baseline patches", err);
}

/* ---- programs and state ----------------------------------------------- */

static satf_status build_programs(const satf_renderer *r, struct baseline *b,
                                  satf_error *err) {
  const struct {
    const char *label;
    int pass;
    GLuint *out;
  } progs[] = {{"baseline shade", 0, &b->prog_shade},
               {"baseline alpha test", 1, &b->prog_alpha},
               {"baseline opacity", 2, &b->prog_dom},
               {"baseline lists", 3, &b->prog_list}};
  satf_status st = SATF_OK;
  for (size_t i = 0; i < 4 && st == SATF_OK; i++) {
    char defines[160];
    snprintf(defines, sizeof defines,
             "#define SATF_MAX_LIGHTS %d\n#define NLIGHTS %d\n"
             "#define BASE_PASS %d\n",
             SATF_SCENE_MAX_LIGHTS, r->view.nlights, progs[i].pass);
    const char *fs = satf_glsl_baseline_fs, *nl = strchr(fs, '\n');
    size_t head = nl ? (size_t)(nl - fs) + 1 : 0;
    char *text = malloc(strlen(fs) + strlen(defines) + 1);
    if (!text)
      return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
    memcpy(text, fs, head);
    strcpy(text + head, defines);
    strcat(text, fs + head);
    st = satf_gl_program_build(progs[i].label, satf_glsl_baseline_vs, text,
                               progs[i].out, err);
    free(text);
  }
  return st;
}

/* The path's state the first time it is chosen: its programs. */
static satf_status baseline_create(satf_renderer *r, satf_error *err) {
  if (r->baseline)
    return SATF_OK;
  struct baseline *b = calloc(1, sizeof *b);
  if (!b)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  r->baseline = b;
  return build_programs(r, b, err);
}

/* The patches of every prototype that has none or whose shape changed
 * since they were built. */
static satf_status baseline_prepare(satf_renderer *r, satf_error *err) {
  struct baseline *b = r->baseline;
  if (b->nprotos != r->nprotos) {
    for (int m = 0; m < b->nprotos; m++)
      release_proto(&b->protos[m]);
    free(b->protos);
    b->nprotos = 0;
    b->protos = calloc((size_t)r->nprotos, sizeof *b->protos);
    if (!b->protos && r->nprotos > 0)
      return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
    b->nprotos = r->nprotos;
  }
  for (int m = 0; m < r->nprotos; m++) {
    float sig[32];
    proto_signature(&r->protos[m], sig);
    if (b->protos[m].vao && !memcmp(sig, b->protos[m].sig, sizeof sig))
      continue;
    satf_status st = build_proto(r, m, &b->protos[m], err);
    if (st != SATF_OK)
      return st;
  }
  return SATF_OK;
}

static void baseline_destroy(satf_renderer *r) {
  struct baseline *b = r->baseline;
  if (!b)
    return;
  for (int m = 0; m < b->nprotos; m++)
    release_proto(&b->protos[m]);
  free(b->protos);
  GLuint progs[4] = {b->prog_shade, b->prog_alpha, b->prog_dom, b->prog_list};
  for (int i = 0; i < 4; i++)
    if (progs[i])
      glDeleteProgram(progs[i]);
  free(b);
  r->baseline = NULL;
}

/* ---- drawing ---------------------------------------------------------- */

/* Which layers of a cluster a draw covers, and in which order. */
typedef enum { ALL_LAYERS, OUTER_FIRST, INNER_FIRST } layer_order;

/* The patches of every cluster in `order` (instance indices) with `prog`.
 * A mirroring transform turns the outward faces clockwise. */
static void draw_patches(const satf_renderer *r, GLuint prog,
                         const float viewproj[16], const int *order,
                         layer_order layers) {
  const struct baseline *b = r->baseline;
  glUseProgram(prog);
  draw_set_mat4(prog, "u_viewproj", viewproj);
  glUniform1i(glGetUniformLocation(prog, "u_hair"), 0);
  GLint model = glGetUniformLocation(prog, "u_model");
  GLint nmat = glGetUniformLocation(prog, "u_normal_matrix");
  glActiveTexture(GL_TEXTURE0);
  for (int q = 0; q < r->ninsts; q++) {
    const inst *in = &r->insts[order ? order[q] : q];
    const base_proto *p = &b->protos[in->proto];
    const float *m = in->m;
    float det = m[0] * (m[5] * m[10] - m[6] * m[9]) -
                m[1] * (m[4] * m[10] - m[6] * m[8]) +
                m[2] * (m[4] * m[9] - m[5] * m[8]);
    glFrontFace(det < 0.0f ? GL_CW : GL_CCW);
    glUniformMatrix4fv(model, 1, GL_TRUE, in->m);
    glUniformMatrix3fv(nmat, 1, GL_TRUE, in->nmat);
    glBindTexture(GL_TEXTURE_2D, p->tex);
    glBindVertexArray(p->vao);
    if (layers == ALL_LAYERS) {
      glDrawElements(GL_TRIANGLES, p->layer_count * p->layers, GL_UNSIGNED_INT,
                     NULL);
      continue;
    }
    for (int j = 0; j < p->layers; j++) {
      int k = layers == INNER_FIRST ? j : p->layers - 1 - j;
      glDrawElements(
          GL_TRIANGLES, p->layer_count, GL_UNSIGNED_INT,
          (void *)((size_t)k * (size_t)p->layer_count * sizeof(uint32_t)));
    }
  }
  glBindVertexArray(0);
  glFrontFace(GL_CCW);
}

/* The deep opacity map (dom.h) from the patches' own alpha: the
 * first hair at least DOM_ALPHA opaque, then every patch's alpha summed
 * into four slabs behind it. */
static void dom_patches(satf_renderer *r, void *ctx, int opacity) {
  const struct baseline *b = ctx;
  if (opacity) {
    dom_uniforms(&r->dom, b->prog_dom);
    draw_patches(r, b->prog_dom, r->dom.viewproj, NULL, ALL_LAYERS);
    return;
  }
  glUseProgram(b->prog_alpha);
  glUniform1f(glGetUniformLocation(b->prog_alpha, "u_alpha_ref"), DOM_ALPHA);
  draw_patches(r, b->prog_alpha, r->dom.viewproj, NULL, ALL_LAYERS);
}

static void baseline_dom(satf_renderer *r) {
  draw_dom(r, dom_cluster_radius(r->scene, r->nprotos), hierarchy_hair_width(r),
           dom_patches, r->baseline);
}

/* The full pixel shader's uniforms: the clusters' material, lights,
 * effects and deep opacity map (draw_shading_uniforms), and its own. */
static void base_uniforms(const satf_renderer *r, GLuint p, satf_aov aov) {
  draw_shading_uniforms(r, p, aov);
  draw_world_lights(r, p);
  glUniform1f(glGetUniformLocation(p, "u_shift_range"), SHIFT_RANGE);
  glUniform1f(glGetUniformLocation(p, "u_base_scale"), BASE_SCALE);
  /* the paper's ambient occlusion is its self-shadowing approximation:
   * --no-self-shadow switches it off */
  glUniform1i(glGetUniformLocation(p, "u_ao"), r->effects.self_shadow);
}

/* Paper 002, "Rendering with approximate depth sorting", over the opaque
 * meshes' depth (draw_begin_frame): clusters in a coarse back-to-front order
 * (their centres' distance from the eye, hierarchy_far_to_near, which the
 * paper's static draw order stands for), each pass over all of them. */
static void draw_passes(satf_renderer *r, satf_aov aov,
                        const float viewproj[16], const int *order) {
  const struct baseline *b = r->baseline;
  glEnable(GL_DEPTH_TEST);
  /* 1: "prime the Z buffer for the opaque regions": alpha test, no
   * culling, no colour writes */
  glDisable(GL_CULL_FACE);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glUseProgram(b->prog_alpha);
  glUniform1f(glGetUniformLocation(b->prog_alpha, "u_alpha_ref"), OPAQUE_ALPHA);
  draw_patches(r, b->prog_alpha, viewproj, order, ALL_LAYERS);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  /* 2: "Z test to equal so that the same opaque pixels ... get shaded";
   * premultiplied "over" as every pass after it */
  GLuint p = b->prog_shade;
  base_uniforms(r, p, aov);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glDepthFunc(GL_EQUAL);
  glDepthMask(GL_FALSE);
  draw_patches(r, p, viewproj, order, ALL_LAYERS);
  /* 3: "disable Z writing, enable front-face culling, and set the Z test
   * to less": the back-facing transparent regions, each cluster's outer
   * layers (farther at its back) first */
  glDepthFunc(GL_LESS);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_FRONT);
  draw_patches(r, p, viewproj, order, OUTER_FIRST);
  /* 4: "reenable Z writing, set the Z test to less, and enable back-face
   * culling": the front-facing ones, inner layers (farther at the front)
   * first */
  glDepthMask(GL_TRUE);
  glCullFace(GL_BACK);
  draw_patches(r, p, viewproj, order, INNER_FIRST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDisable(GL_DEPTH_TEST);
}

/* The depth AOV's fill (depth.h): every patch's alpha into the per-pixel
 * arrays, in no order (they sort it), so the depth does not depend on the
 * approximate order of the passes above. */
static void depth_fill(satf_renderer *r, void *ctx, const float viewproj[16],
                       int mode) {
  GLuint p = ((struct baseline *)ctx)->prog_list;
  glUseProgram(p);
  glUniform1i(glGetUniformLocation(p, "u_slots"), r->lists.slots);
  glUniform1i(glGetUniformLocation(p, "u_list_mode"), mode);
  draw_patches(r, p, viewproj, NULL, ALL_LAYERS);
}

static satf_status baseline_frame(satf_renderer *r, satf_aov aov, int refresh,
                                  satf_frame_timing *timing, satf_error *err) {
  satf_frame_timing t;
  memset(&t, 0, sizeof t);
  double t0 = satf_now_seconds();
  satf_status st = baseline_prepare(r, err);
  if (st != SATF_OK)
    return st;
  double t1 = satf_now_seconds();
  if (refresh && r->effects.cluster_shadows)
    baseline_dom(r);
  glFinish();
  double t2 = satf_now_seconds();
  float viewproj[16];
  view_camera(&r->view, viewproj);
  int *order = hierarchy_far_to_near(r, r->view.camera.position);
  if (!order)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  if (aov == SATF_AOV_DEPTH) {
    st = depth_lists(r, viewproj, depth_fill, r->baseline, err);
  } else {
    draw_begin_frame(r, aov, viewproj);
    draw_passes(r, aov, viewproj, order);
  }
  free(order);
  if (st != SATF_OK)
    return st;
  glFinish();
  double t3 = satf_now_seconds();
  r->stats.overflow_pixels = 0;
  t.maps_ms = 1e3 * (t1 - t0); /* patches (re)built, usually nothing */
  t.shadow_ms = 1e3 * (t2 - t1);
  t.lighting_ms = 1e3 * (t3 - t2);
  t.total_ms = 1e3 * (t3 - t0);
  if (timing)
    *timing = t;
  return satf_gl_check("baseline frame", err);
}

const render_path baseline_path = {"baseline", baseline_create, baseline_frame,
                                   baseline_destroy};
