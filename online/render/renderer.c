/* renderer.c - see renderer.h. */
#include "satf/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/density.h"
#include "satf/gl.h"
#include "maps.h"
#include "mat4.h"
#include "shaders.h"
#include "satf/geometry.h"

#define DOM_SIZE 256
/* Fragments each pixel can keep at first; the arrays grow (up to
 * SATF_MAX_FRAGMENTS) when a frame needs more. */
#define START_SLOTS 16

typedef struct proto {
  satf_cluster *cluster;
  satf_shell_geom geom; /* features: procedural density, shared */
  satf_strands *strands;
  satf_vdb_grid *vdb;
  int layers;
  GLuint proxy_vao; /* the drawn outer shell (upload_frames) */
  GLuint proxy_vbo, proxy_ibo;
  GLsizei proxy_count;
  GLsizei coarse_count; /* light passes: rows every COARSE_ROWS, after */
  GLsizei *count;
} proto;

typedef struct inst {
  int proto;
  float m[16], inv[16], nmat[9];
  float centre[3]; /* world position of the cluster's middle, for sorting */
  satf_shell_geom geom; /* shallow copy; own features only with a VDB */
  int own_features;
  satf_neighbor_cache *own_neighbors; /* with own (VDB) features */
  float *angles, *texels;
  float eye[3], light[4];
  GLuint tex;
} inst;

typedef struct mesh_gpu {
  GLuint vao, vbo, ibo;
  GLsizei count;
  float m[16], nmat[9], color[3];
} mesh_gpu;

struct satf_renderer {
  const satf_scene *scene;
  const satf_db *db;
  satf_maps *maps;
  satf_map_options map_opt;
  satf_scene_camera camera;
  satf_scene_effects effects;
  satf_scene_light lights[4];
  int nlights;
  int width, height, threads, w;
  float lo[3], hi[3];
  int nprotos, ninsts, nmeshes;
  mesh_gpu *meshes;
  GLuint prog_mesh, prog_mesh_depth, prog_mesh_dom;
  proto *protos;
  inst *insts;
  satf_render_stats stats;
  /* GL */
  satf_composite composite;
  GLuint prog_shade, prog_shade_ordered, prog_depth, prog_dom, prog_resolve,
      prog_display;
  GLuint empty_vao, counts_tex, frags_tex, list_fbo;
  int slots; /* fragments kept per pixel */
  satf_gl_target *out, *dom_depth, *dom_opacity;
  float light_viewproj[16], dom_slab;
};

const char *satf_aov_name(satf_aov aov) {
  static const char *names[] = {"beauty", "diffuse", "specI",
                                "specII", "shadow",  "alpha"};
  return aov < SATF_AOV_COUNT ? names[aov] : "unknown";
}

/* ---- building the hierarchy ------------------------------------------- */

/* The scene gives A, B and twist as separate curves; the cluster takes one
 * control polygon for the three, so shorter ones are resampled linearly. */
static void resample_curve(const satf_scene_curve *c, int n, float *out) {
  for (int i = 0; i < n; i++) {
    if (c->count == 1 || n == 1) {
      out[i] = c->values[0];
      continue;
    }
    float x = (float)i / (float)(n - 1) * (float)(c->count - 1);
    int k = (int)x;
    if (k > c->count - 2)
      k = c->count - 2;
    float f = x - (float)k;
    out[i] = c->values[k] + f * (c->values[k + 1] - c->values[k]);
  }
}

/* Columns of the drawn proxy of a cluster's outermost shell. Shading
 * traces each ray through the shells analytically (shaders.c), so the
 * proxy only has to cover the cluster's silhouette; a CPU rasteriser pays
 * for every triangle on one thread, so it is kept coarse around the
 * cluster and as fine as the HSVs along it. */
#define PROXY_COLUMNS 12
/* The deep opacity map is coarse: its passes skip rows of the proxy. */
#define COARSE_ROWS 4

/* The proxy: (st + 1) x (PROXY_COLUMNS + 1) vertices on an elliptic
 * cylinder circumscribing the outer shell, each with position, hair
 * tangent, (u, t), and the cross-section at t as the shading pass needs it:
 * C(t), n1, n2, (A, B, theta, |dT/dt|), the unit tangent of T. */
enum { PROXY_FLOATS = 24 };
static satf_status upload_frames(proto *p, const satf_shell_params *sh,
                                 satf_error *err) {
  int cols = PROXY_COLUMNS + 1;
  size_t nv = (size_t)(sh->st + 1) * (size_t)cols;
  int coarse_rows = (sh->st + COARSE_ROWS - 1) / COARSE_ROWS;
  size_t ntri = 2 * (size_t)sh->st * PROXY_COLUMNS;
  size_t ncoarse = 2 * (size_t)coarse_rows * PROXY_COLUMNS;
  float *f = malloc(nv * PROXY_FLOATS * sizeof(float));
  uint32_t *idx = malloc((ntri + ncoarse) * 3 * sizeof(uint32_t));
  if (!f || !idx) {
    free(f);
    free(idx);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  /* the polygon's edges touch the shell: it covers every pixel the shell
   * covers */
  float inflate = 1.0f / cosf(3.14159265f / PROXY_COLUMNS);
  for (int i = 0; i <= sh->st; i++) {
    satf_cluster_section sec;
    float t = (float)i / (float)sh->st;
    satf_cluster_section_at(p->cluster, t, &sec);
    float speed = sqrtf(sec.dcenter[0] * sec.dcenter[0] +
                        sec.dcenter[1] * sec.dcenter[1] +
                        sec.dcenter[2] * sec.dcenter[2]);
    for (int j = 0; j < cols; j++) {
      float *v = f + PROXY_FLOATS * ((size_t)i * cols + (size_t)j);
      float u = 6.28318531f * (float)j / PROXY_COLUMNS;
      satf_cluster_section_point(&sec, inflate, u, v);
      satf_cluster_section_hair_tangent(&sec, 1.0f, u, v + 3);
      v[6] = (float)j / PROXY_COLUMNS;
      v[7] = t;
      memcpy(v + 8, sec.center, 3 * sizeof(float));
      memcpy(v + 11, sec.n1, 3 * sizeof(float));
      memcpy(v + 14, sec.n2, 3 * sizeof(float));
      v[17] = sec.a;
      v[18] = sec.b;
      v[19] = sec.theta;
      v[20] = speed;
      memcpy(v + 21, sec.tangent, 3 * sizeof(float));
    }
  }
  /* counter-clockwise seen from outside: d/du x d/dt points outwards */
  uint32_t *q = idx;
  for (int i = 0; i < sh->st; i++)
    for (int j = 0; j < PROXY_COLUMNS; j++) {
      uint32_t a = (uint32_t)(i * cols + j), b = a + 1;
      uint32_t c = a + (uint32_t)cols, d = c + 1;
      *q++ = a, *q++ = b, *q++ = c;
      *q++ = b, *q++ = d, *q++ = c;
    }
  for (int i = 0; i < sh->st; i += COARSE_ROWS) {
    int i1 = i + COARSE_ROWS < sh->st ? i + COARSE_ROWS : sh->st;
    for (int j = 0; j < PROXY_COLUMNS; j++) {
      uint32_t a = (uint32_t)(i * cols + j), b = a + 1;
      uint32_t c = (uint32_t)(i1 * cols + j), d = c + 1;
      *q++ = a, *q++ = b, *q++ = c;
      *q++ = b, *q++ = d, *q++ = c;
    }
  }
  glGenVertexArrays(1, &p->proxy_vao);
  glGenBuffers(1, &p->proxy_vbo);
  glGenBuffers(1, &p->proxy_ibo);
  glBindVertexArray(p->proxy_vao);
  glBindBuffer(GL_ARRAY_BUFFER, p->proxy_vbo);
  glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nv * PROXY_FLOATS * sizeof(float)),
               f, GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, p->proxy_ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER,
               (GLsizeiptr)((ntri + ncoarse) * 3 * sizeof(uint32_t)), idx,
               GL_STATIC_DRAW);
  free(f);
  free(idx);
  /* locations as in satf_glsl_cluster_vs / satf_glsl_layer_vs */
  const GLuint loc[7] = {0, 2, 3, 4, 5, 6, 7};
  const GLint sizes[7] = {3, 3, 2, 3, 3, 3, 4};
  const size_t offs[7] = {0, 3, 6, 8, 11, 14, 17};
  for (int a = 0; a < 7; a++) {
    glEnableVertexAttribArray(loc[a]);
    glVertexAttribPointer(loc[a], sizes[a], GL_FLOAT, GL_FALSE,
                          PROXY_FLOATS * sizeof(float),
                          (void *)(offs[a] * sizeof(float)));
  }
  glEnableVertexAttribArray(8);
  glVertexAttribPointer(8, 3, GL_FLOAT, GL_FALSE, PROXY_FLOATS * sizeof(float),
                        (void *)(21 * sizeof(float)));
  glBindVertexArray(0);
  p->proxy_count = (GLsizei)(ntri * 3);
  p->coarse_count = (GLsizei)(ncoarse * 3);
  return satf_gl_check("cluster proxy", err);
}

/* Deletes a prototype's GL geometry (not its density). */
static void release_geometry(proto *p) {
  if (p->proxy_vao) {
    glDeleteVertexArrays(1, &p->proxy_vao);
    glDeleteBuffers(1, &p->proxy_vbo);
    glDeleteBuffers(1, &p->proxy_ibo);
  }
  p->proxy_vao = p->proxy_vbo = p->proxy_ibo = 0;
  satf_cluster_destroy(p->cluster);
  p->cluster = NULL;
}

/* The generalized cylinder of a scene cluster, its shell geometry (sector
 * frames; features are kept when `keep` holds them), layer meshes and
 * frames on the GPU. Used at creation and when an animation moves it. */
static satf_status build_geometry(satf_renderer *r, int index,
                                  const satf_scene_cluster *c,
                                  const float *keep, satf_error *err) {
  proto *p = &r->protos[index];
  const char *name = r->scene->name ? r->scene->name : "scene";
  int n = c->a.count;
  if (c->b.count > n)
    n = c->b.count;
  if (c->twist.count > n)
    n = c->twist.count;
  float *radii = malloc(3 * (size_t)n * sizeof(float));
  if (!radii)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  resample_curve(&c->a, n, radii);
  resample_curve(&c->b, n, radii + n);
  resample_curve(&c->twist, n, radii + 2 * n);
  satf_cluster_desc desc = {c->n_points, c->trajectory, n,
                            radii,       radii + n,     radii + 2 * n};
  satf_error cerr;
  satf_status st = satf_cluster_create(&desc, &p->cluster, &cerr);
  free(radii);
  if (st != SATF_OK)
    return satf_error_set(err, st, "%s: macro_clusters[%d].prototype: %s", name,
                          index, cerr.message);
  satf_shell_params shell = {c->shell.layers, c->shell.st, c->shell.su,
                             c->shell.core};
  satf_shell_geom geom;
  st = satf_shell_geom_create(p->cluster, &shell, &geom, &cerr);
  if (st != SATF_OK)
    return satf_error_set(err, st, "%s: macro_clusters[%d].prototype.shell: %s",
                          name, index, cerr.message);
  if (keep)
    memcpy(geom.features, keep,
           satf_shell_sector_count(&shell) * 3 * sizeof(float));
  satf_shell_geom_destroy(&p->geom);
  p->geom = geom;
  p->layers = shell.layers;
  return upload_frames(p, &shell, err);
}

static satf_status build_proto(satf_renderer *r, int index,
                               const satf_scene_macro_cluster *mc,
                               satf_error *err) {
  proto *p = &r->protos[index];
  const satf_scene_cluster *c = &mc->prototype;
  const char *name = r->scene->name ? r->scene->name : "scene";
  satf_status st = build_geometry(r, index, c, NULL, err);
  if (st != SATF_OK)
    return st;
  satf_error cerr;
  if (c->density.type == SATF_SCENE_DENSITY_VDB) {
    st =
        satf_vdb_read(c->density.vdb_file, c->density.vdb_grid, &p->vdb, &cerr);
    if (st != SATF_OK)
      return satf_error_set(err, st,
                            "%s: macro_clusters[%d].prototype.density: %s",
                            name, index, cerr.message);
  } else {
    st = satf_strands_create(&c->density, &p->strands, &cerr);
    if (st == SATF_OK) /* once per prototype (SATF sec. 3.1) */
      st = satf_sector_features(p->cluster, &p->geom.shell, p->strands, NULL,
                                NULL, r->threads, p->geom.features, &cerr);
    if (st == SATF_OK)
      st = satf_maps_prepare(r->maps, &p->geom, &r->map_opt, &cerr);
    if (st != SATF_OK)
      return satf_error_set(err, st,
                            "%s: macro_clusters[%d].prototype.density: %s",
                            name, index, cerr.message);
    r->stats.strands += (long)c->density.strands * mc->n_instances;
  }
  return SATF_OK;
}

/* Everything of an instance that follows its prototype's geometry and its
 * transform: the shell view, the sorting centre and, for world-space (VDB)
 * density, the features. */
static satf_status place_inst(satf_renderer *r, inst *in, satf_error *err) {
  proto *p = &r->protos[in->proto];
  if (!satf_mat4_invert(in->m, in->inv))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: an instance transform of macro cluster %d is "
                          "singular",
                          r->scene->name ? r->scene->name : "scene", in->proto);
  satf_mat4_normal_matrix(in->m, in->nmat);
  float *own = in->own_features ? in->geom.features : NULL;
  in->geom = p->geom;
  if (own)
    in->geom.features = own;
  size_t sectors = satf_shell_sector_count(&p->geom.shell);
  float local[3] = {0, 0, 0};
  for (size_t q = 0; q < sectors; q++)
    for (int a = 0; a < 3; a++)
      local[a] += p->geom.frames[9 * q + a] / (float)sectors;
  satf_mat4_point(in->m, local, in->centre);
  if (p->vdb) {
    satf_status st =
        satf_sector_features(p->cluster, &p->geom.shell, NULL, p->vdb, in->m,
                             r->threads, in->geom.features, err);
    satf_neighbor_cache_free(in->own_neighbors);
    in->own_neighbors = NULL;
    in->geom.neighbors = NULL;
    if (st == SATF_OK)
      st = satf_maps_prepare(r->maps, &in->geom, &r->map_opt, err);
    in->own_neighbors = in->geom.neighbors;
    return st;
  }
  return SATF_OK;
}

static satf_status build_inst(satf_renderer *r, inst *in, int pi,
                              const satf_scene_instance *si, satf_error *err) {
  proto *p = &r->protos[pi];
  in->proto = pi;
  memcpy(in->m, si->m, sizeof in->m);
  size_t sectors = satf_shell_sector_count(&p->geom.shell);
  if (p->vdb) { /* world-space density: features differ per instance */
    in->own_features = 1;
    in->geom.features = malloc(sectors * 3 * sizeof(float));
    if (!in->geom.features)
      return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  satf_status st = place_inst(r, in, err);
  if (st != SATF_OK)
    return st;
  size_t texels = satf_maps_layer_texels(&p->geom, r->w) * (size_t)p->layers;
  in->angles = malloc(sectors * 2 * sizeof(float));
  in->texels = calloc(texels * 4, sizeof(float));
  if (!in->angles || !in->texels)
    return satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate %zu map texels",
                          texels);
  glGenTextures(1, &in->tex);
  glBindTexture(GL_TEXTURE_2D_ARRAY, in->tex);
  glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_RGBA32F, p->geom.shell.su * r->w,
                 2 * p->geom.shell.st, p->layers);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  r->stats.clusters++;
  r->stats.layers += p->layers;
  r->stats.hsvs += (long)satf_shell_hsv_count(&p->geom.shell);
  return satf_gl_check("map texture", err);
}

/* ---- GL resources ------------------------------------------------------ */

/* src with `line` inserted after its #version line. */
static char *with_define(const char *src, const char *line) {
  const char *nl = strchr(src, '\n');
  size_t head = nl ? (size_t)(nl - src) + 1 : 0;
  char *out = malloc(strlen(src) + strlen(line) + 1);
  if (out) {
    memcpy(out, src, head);
    strcpy(out + head, line);
    strcat(out, src + head);
  }
  return out;
}

static satf_status build_programs(satf_renderer *r, satf_error *err) {
  /* the light loop runs a compile-time count so it unrolls */
  char lights[64];
  snprintf(lights, sizeof lights, "#define NLIGHTS %d\n", r->nlights);
  char *exact = with_define(satf_glsl_shade_fs, lights);
  if (!exact)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  satf_status st = satf_gl_program_build("shade", satf_glsl_cluster_vs, exact,
                                         &r->prog_shade, err);
  char *ordered = with_define(exact, "#define EXACT 0\n");
  free(exact);
  if (!ordered)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  if (st == SATF_OK)
    st = satf_gl_program_build("shade (ordered)", satf_glsl_cluster_vs, ordered,
                               &r->prog_shade_ordered, err);
  free(ordered);
  if (st == SATF_OK)
    st = satf_gl_program_build("depth", satf_glsl_layer_vs, satf_glsl_depth_fs,
                               &r->prog_depth, err);
  if (st == SATF_OK)
    st = satf_gl_program_build("dom", satf_glsl_layer_vs, satf_glsl_dom_fs,
                               &r->prog_dom, err);
  if (st == SATF_OK)
    st = satf_gl_program_build("resolve", satf_glsl_fullscreen_vs,
                               satf_glsl_resolve_fs, &r->prog_resolve, err);
  if (st == SATF_OK)
    st = satf_gl_program_build("display", satf_glsl_fullscreen_vs,
                               satf_glsl_display_fs, &r->prog_display, err);
  if (st == SATF_OK)
    st = satf_gl_program_build("mesh", satf_glsl_mesh_vs, satf_glsl_mesh_fs,
                               &r->prog_mesh, err);
  if (st == SATF_OK)
    st = satf_gl_program_build("mesh depth", satf_glsl_mesh_vs,
                               satf_glsl_empty_fs, &r->prog_mesh_depth, err);
  if (st == SATF_OK)
    st = satf_gl_program_build("mesh opacity", satf_glsl_mesh_vs,
                               satf_glsl_dom_mesh_fs, &r->prog_mesh_dom, err);
  return st;
}

/* Per-pixel fragment arrays: an r32ui counter per pixel and a layered
 * rgba32ui image of `slots` fragments (colour as halves, depth). A texture
 * rather than a storage buffer: llvmpipe caps buffers at 128 MB, and a
 * per-pixel counter avoids the contention of one global atomic counter,
 * which made linked lists three times slower there. */
static satf_status alloc_lists(satf_renderer *r, int slots, satf_error *err) {
  if (r->counts_tex)
    glDeleteTextures(1, &r->counts_tex);
  if (r->frags_tex)
    glDeleteTextures(1, &r->frags_tex);
  glGenTextures(1, &r->counts_tex);
  glBindTexture(GL_TEXTURE_2D, r->counts_tex);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32UI, r->width, r->height);
  glGenTextures(1, &r->frags_tex);
  glBindTexture(GL_TEXTURE_2D_ARRAY, r->frags_tex);
  glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_RGBA32UI, r->width, r->height,
                 slots);
  r->slots = slots;
  return satf_gl_check("fragment arrays", err);
}

static satf_status alloc_screen(satf_renderer *r, satf_error *err) {
  /* half floats: what the EXR keeps, and faster to blend on llvmpipe */
  const satf_gl_format out_format = SATF_GL_RGBA16F;
  if (!r->list_fbo)
    glGenFramebuffers(1, &r->list_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, r->list_fbo);
  glFramebufferParameteri(GL_FRAMEBUFFER, GL_FRAMEBUFFER_DEFAULT_WIDTH,
                          r->width);
  glFramebufferParameteri(GL_FRAMEBUFFER, GL_FRAMEBUFFER_DEFAULT_HEIGHT,
                          r->height);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (r->out)
    satf_gl_target_destroy(r->out);
  r->out = NULL;
  satf_status st =
      satf_gl_target_create(r->width, r->height, 1, &out_format, &r->out, err);
  if (st == SATF_OK) {
    /* the hair's fragment pass tests against the meshes' depth */
    glBindFramebuffer(GL_FRAMEBUFFER, r->list_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D,
                           satf_gl_target_depth_texture(r->out), 0);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    st = alloc_lists(r, r->slots > 0 ? r->slots : START_SLOTS, err);
  }
  return st;
}

/* The scene's opaque meshes (OpenMesh reads OBJ and PLY), grown into the
 * scene bounds so the camera and the light's map cover them. */
static satf_status build_meshes(satf_renderer *r, satf_error *err) {
  const satf_scene *scene = r->scene;
  if (scene->n_meshes == 0)
    return SATF_OK;
  r->meshes = calloc((size_t)scene->n_meshes, sizeof *r->meshes);
  if (!r->meshes)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  r->nmeshes = scene->n_meshes;
  for (int i = 0; i < scene->n_meshes; i++) {
    const satf_scene_mesh *sm = &scene->meshes[i];
    mesh_gpu *g = &r->meshes[i];
    satf_mesh *mesh = NULL;
    satf_error merr;
    satf_status st = satf_mesh_read(sm->file, &mesh, &merr);
    if (st != SATF_OK)
      return satf_error_set(err, st, "%s: meshes[%d]: %s",
                            scene->name ? scene->name : "scene", i,
                            merr.message);
    memcpy(g->m, sm->m, sizeof g->m);
    memcpy(g->color, sm->color, sizeof g->color);
    satf_mat4_normal_matrix(g->m, g->nmat);
    float lo[3], hi[3];
    satf_mesh_bounds(mesh, lo, hi);
    for (int c = 0; c < 8; c++) {
      float p[3] = {c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1],
                    c & 4 ? hi[2] : lo[2]},
            w[3];
      satf_mat4_point(g->m, p, w);
      for (int a = 0; a < 3; a++) {
        r->lo[a] = w[a] < r->lo[a] ? w[a] : r->lo[a];
        r->hi[a] = w[a] > r->hi[a] ? w[a] : r->hi[a];
      }
    }
    glGenVertexArrays(1, &g->vao);
    glGenBuffers(1, &g->vbo);
    glGenBuffers(1, &g->ibo);
    glBindVertexArray(g->vao);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glBufferData(
        GL_ARRAY_BUFFER,
        (GLsizeiptr)(satf_mesh_vertex_count(mesh) * sizeof(satf_mesh_vertex)),
        satf_mesh_vertices(mesh), GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ibo);
    glBufferData(
        GL_ELEMENT_ARRAY_BUFFER,
        (GLsizeiptr)(satf_mesh_triangle_count(mesh) * 3 * sizeof(uint32_t)),
        satf_mesh_indices(mesh), GL_STATIC_DRAW);
    GLsizei stride = (GLsizei)sizeof(satf_mesh_vertex);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride,
                          (void *)offsetof(satf_mesh_vertex, pos));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                          (void *)offsetof(satf_mesh_vertex, normal));
    glBindVertexArray(0);
    g->count = (GLsizei)(satf_mesh_triangle_count(mesh) * 3);
    satf_mesh_destroy(mesh);
  }
  return satf_gl_check("meshes", err);
}

satf_status satf_renderer_create(const satf_scene *scene, const satf_db *db,
                                 int width, int height, int threads,
                                 satf_renderer **out, satf_error *err) {
  *out = NULL;
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 43)
    return satf_error_set(err, SATF_ERR_GL,
                          "the renderer needs OpenGL 4.3 (shader storage "
                          "buffers and image atomics); this context has %d.%d",
                          major, minor);
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "image size %dx%d", width,
                          height);
  satf_renderer *r = calloc(1, sizeof *r);
  if (!r)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  r->scene = scene;
  r->db = db;
  r->width = width;
  r->height = height;
  r->threads = threads > 0 ? threads : satf_cpu_count();
  r->camera = scene->camera;
  r->effects = scene->effects;
  r->nlights = scene->n_lights < 4 ? scene->n_lights : 4;
  memcpy(r->lights, scene->lights,
         (size_t)r->nlights * sizeof(satf_scene_light));
  r->map_opt = satf_map_options_default();
  satf_scene_bounds(scene, r->lo, r->hi);
  satf_status st = satf_maps_create(db, &r->maps, err);
  if (st != SATF_OK) {
    free(r);
    return st;
  }
  r->w = satf_maps_width(r->maps);
  r->nprotos = scene->n_macro_clusters;
  r->protos = calloc((size_t)r->nprotos, sizeof(proto));
  r->ninsts = (int)satf_scene_cluster_count(scene);
  r->insts = calloc((size_t)r->ninsts, sizeof(inst));
  if (!r->protos || !r->insts) {
    satf_renderer_destroy(r);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  r->stats.macro_clusters = r->nprotos;
  int ii = 0;
  for (int m = 0; m < r->nprotos && st == SATF_OK; m++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    st = build_proto(r, m, mc, err);
    for (int i = 0; i < mc->n_instances && st == SATF_OK; i++)
      st = build_inst(r, &r->insts[ii++], m, &mc->instances[i], err);
    r->stats.prototypes_shared += mc->n_instances - 1;
  }
  if (st == SATF_OK)
    st = build_meshes(r, err);
  if (st == SATF_OK)
    st = build_programs(r, err);
  if (st == SATF_OK) {
    glGenVertexArrays(1, &r->empty_vao);
    st = alloc_screen(r, err);
  }
  if (st == SATF_OK)
    st = satf_gl_target_create(DOM_SIZE, DOM_SIZE, 1, NULL, &r->dom_depth, err);
  if (st == SATF_OK)
    st = satf_gl_target_create(DOM_SIZE, DOM_SIZE, 1, NULL, &r->dom_opacity,
                               err);
  if (st == SATF_OK) {
    GLuint dom[2] = {satf_gl_target_depth_texture(r->dom_depth),
                     satf_gl_target_color_texture(r->dom_opacity, 0)};
    for (int k = 0; k < 2; k++) {
      glBindTexture(GL_TEXTURE_2D, dom[k]);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    st = satf_gl_check("renderer set-up", err);
  }
  if (st != SATF_OK) {
    satf_renderer_destroy(r);
    return st;
  }
  *out = r;
  return SATF_OK;
}

void satf_renderer_destroy(satf_renderer *r) {
  if (!r)
    return;
  for (int i = 0; r->insts && i < r->ninsts; i++) {
    inst *in = &r->insts[i];
    if (in->own_features)
      free(in->geom.features);
    satf_neighbor_cache_free(in->own_neighbors);
    free(in->angles);
    free(in->texels);
    if (in->tex)
      glDeleteTextures(1, &in->tex);
  }
  for (int m = 0; r->protos && m < r->nprotos; m++) {
    proto *p = &r->protos[m];
    release_geometry(p);
    satf_shell_geom_destroy(&p->geom);
    satf_strands_destroy(p->strands);
    satf_vdb_grid_destroy(p->vdb);
  }
  free(r->protos);
  free(r->insts);
  for (int i = 0; r->meshes && i < r->nmeshes; i++) {
    glDeleteVertexArrays(1, &r->meshes[i].vao);
    glDeleteBuffers(1, &r->meshes[i].vbo);
    glDeleteBuffers(1, &r->meshes[i].ibo);
  }
  free(r->meshes);
  GLuint mesh_progs[3] = {r->prog_mesh, r->prog_mesh_depth, r->prog_mesh_dom};
  for (int i = 0; i < 3; i++)
    if (mesh_progs[i])
      glDeleteProgram(mesh_progs[i]);
  GLuint progs[6] = {r->prog_shade, r->prog_shade_ordered, r->prog_depth,
                     r->prog_dom,   r->prog_resolve,       r->prog_display};
  for (int i = 0; i < 6; i++)
    if (progs[i])
      glDeleteProgram(progs[i]);
  if (r->empty_vao)
    glDeleteVertexArrays(1, &r->empty_vao);
  GLuint texs[2] = {r->counts_tex, r->frags_tex};
  glDeleteTextures(2, texs);
  if (r->list_fbo)
    glDeleteFramebuffers(1, &r->list_fbo);
  satf_gl_target_destroy(r->out);
  satf_gl_target_destroy(r->dom_depth);
  satf_gl_target_destroy(r->dom_opacity);
  satf_maps_destroy(r->maps);
  free(r);
}

satf_status satf_renderer_resize(satf_renderer *r, int width, int height,
                                 satf_error *err) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "image size %dx%d", width,
                          height);
  if (width == r->width && height == r->height)
    return SATF_OK;
  r->width = width;
  r->height = height;
  return alloc_screen(r, err);
}

void satf_renderer_stats(const satf_renderer *r, satf_render_stats *s) {
  *s = r->stats;
}
void satf_renderer_size(const satf_renderer *r, int *width, int *height) {
  *width = r->width;
  *height = r->height;
}
satf_scene_camera *satf_renderer_camera(satf_renderer *r) { return &r->camera; }
satf_scene_effects *satf_renderer_effects(satf_renderer *r) {
  return &r->effects;
}
satf_scene_light *satf_renderer_light(satf_renderer *r, int i) {
  return i >= 0 && i < r->nlights ? &r->lights[i] : NULL;
}
int satf_renderer_light_count(const satf_renderer *r) { return r->nlights; }
void satf_renderer_set_composite(satf_renderer *r, satf_composite mode) {
  r->composite = mode;
}
satf_composite satf_renderer_composite(const satf_renderer *r) {
  return r->composite;
}
unsigned satf_renderer_texture(const satf_renderer *r) {
  return satf_gl_target_color_texture(r->out, 0);
}
unsigned satf_renderer_framebuffer(const satf_renderer *r) {
  return satf_gl_target_fbo(r->out);
}

/* ---- per-frame CPU work (Table 1: I, C, M) ----------------------------- */

/* Light 0 as seen from a point: xyz + w (0: direction to it, 1: position). */
static void light_vector(const satf_scene_light *l, float out[4]) {
  if (l->type == SATF_SCENE_LIGHT_POINT) {
    memcpy(out, l->position, 3 * sizeof(float));
    out[3] = 1.0f;
  } else {
    out[0] = -l->direction[0];
    out[1] = -l->direction[1];
    out[2] = -l->direction[2];
    out[3] = 0.0f;
  }
}

static int angles_job(void *ctx, size_t i, int thread) {
  (void)thread;
  satf_renderer *r = ctx;
  inst *in = &r->insts[i];
  float lv[4];
  light_vector(&r->lights[0], lv);
  satf_mat4_point(in->inv, r->camera.position, in->eye);
  if (lv[3] != 0.0f) {
    satf_mat4_point(in->inv, lv, in->light);
  } else {
    satf_mat4_vector(in->inv, lv, in->light);
  }
  in->light[3] = lv[3];
  satf_maps_angles(&in->geom, in->eye, in->light, in->angles);
  return 0;
}

typedef struct layer_jobs {
  satf_renderer *r;
  int *inst_of, *layer_of;
  long *lookups;
} layer_jobs;

static int layer_job(void *ctx, size_t i, int thread) {
  layer_jobs *j = ctx;
  satf_renderer *r = j->r;
  inst *in = &r->insts[j->inst_of[i]];
  int k = j->layer_of[i];
  size_t n = satf_maps_layer_texels(&in->geom, r->w) * 4;
  j->lookups[thread] +=
      satf_maps_build_layer(r->maps, &in->geom, in->angles, &r->map_opt, k,
                            in->texels + (size_t)k * n);
  return 0;
}

static int shadow_job(void *ctx, size_t i, int thread) {
  (void)thread;
  satf_renderer *r = ctx;
  satf_maps_shadow_sums(&r->insts[i].geom, r->w, r->insts[i].texels);
  return 0;
}

static satf_status update_maps(satf_renderer *r, satf_frame_timing *t,
                               satf_error *err) {
  double t0 = satf_now_seconds();
  satf_parallel_for((size_t)r->ninsts, r->threads, angles_job, r, NULL, NULL);
  double t1 = satf_now_seconds();
  size_t jobs = 0;
  for (int i = 0; i < r->ninsts; i++)
    jobs += (size_t)r->protos[r->insts[i].proto].layers;
  layer_jobs lj = {r, malloc(jobs * sizeof(int)), malloc(jobs * sizeof(int)),
                   calloc((size_t)r->threads, sizeof(long))};
  if (!lj.inst_of || !lj.layer_of || !lj.lookups) {
    free(lj.inst_of);
    free(lj.layer_of);
    free(lj.lookups);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  size_t q = 0;
  for (int i = 0; i < r->ninsts; i++)
    for (int k = 0; k < r->protos[r->insts[i].proto].layers; k++) {
      lj.inst_of[q] = i;
      lj.layer_of[q++] = k;
    }
  satf_parallel_for(jobs, r->threads, layer_job, &lj, NULL, NULL);
  satf_parallel_for((size_t)r->ninsts, r->threads, shadow_job, r, NULL, NULL);
  t->lookups = 0;
  for (int k = 0; k < r->threads; k++)
    t->lookups += lj.lookups[k];
  free(lj.inst_of);
  free(lj.layer_of);
  free(lj.lookups);
  double t2 = satf_now_seconds();
  for (int i = 0; i < r->ninsts; i++) {
    inst *in = &r->insts[i];
    const satf_shell_params *sh = &in->geom.shell;
    glBindTexture(GL_TEXTURE_2D_ARRAY, in->tex);
    glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, 0, sh->su * r->w, 2 * sh->st,
                    sh->layers, GL_RGBA, GL_FLOAT, in->texels);
  }
  glFinish();
  double t3 = satf_now_seconds();
  t->index_ms = 1e3 * (t1 - t0);
  t->maps_ms = 1e3 * (t2 - t1);
  t->upload_ms = 1e3 * (t3 - t2);
  return satf_gl_check("map upload", err);
}

/* ---- GPU passes (Table 1: L, S) ---------------------------------------- */

static void set_mat4(GLuint prog, const char *name, const float m[16]) {
  glUniformMatrix4fv(glGetUniformLocation(prog, name), 1, GL_TRUE, m);
}

/* Sets the per-pass uniforms of a layer program; returns its per-draw
 * uniform locations (model, normal matrix, layer, st). */
static void use_layer_program(const satf_renderer *r, GLuint prog,
                              const float viewproj[16], GLint loc[4]) {
  glUseProgram(prog);
  set_mat4(prog, "u_viewproj", viewproj);
  glUniform1i(glGetUniformLocation(prog, "u_maps"), 0);
  glUniform1i(glGetUniformLocation(prog, "u_satf"), r->effects.satf);
  glUniform1f(glGetUniformLocation(prog, "u_plain_opacity"), 3.0f);
  glUniform1i(glGetUniformLocation(prog, "u_map_width"), 0);
  loc[0] = glGetUniformLocation(prog, "u_model");
  loc[1] = glGetUniformLocation(prog, "u_st");
  loc[2] = glGetUniformLocation(prog, "u_layers");
  loc[3] = glGetUniformLocation(prog, "u_core");
  glActiveTexture(GL_TEXTURE0);
}

/* Per-cluster uniforms: transform, shells, and the eye and lights in the
 * prototype's frame (where the shading pass traces its rays). */
static void bind_instance(const satf_renderer *r, GLuint prog, const inst *in,
                          const GLint loc[4]) {
  glUniformMatrix4fv(loc[0], 1, GL_TRUE, in->m);
  glUniform1i(loc[1], in->geom.shell.st);
  glUniform1i(glGetUniformLocation(prog, "u_map_width"),
              in->geom.shell.su * r->w);
  glUniform1i(loc[2], in->geom.shell.layers);
  glUniform1f(loc[3], in->geom.shell.core);
  GLint eye = glGetUniformLocation(prog, "u_eye_local");
  if (eye >= 0) {
    float lights[16];
    for (int k = 0; k < r->nlights; k++) {
      float lv[4];
      light_vector(&r->lights[k], lv);
      if (lv[3] != 0.0f)
        satf_mat4_point(in->inv, lv, lights + 4 * k);
      else
        satf_mat4_vector(in->inv, lv, lights + 4 * k);
      lights[4 * k + 3] = lv[3];
    }
    glUniform3fv(eye, 1, in->eye);
    glUniform4fv(glGetUniformLocation(prog, "u_light_local"), r->nlights,
                 lights);
  }
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D_ARRAY, in->tex);
}

static void draw_proxy(const proto *p, int coarse) {
  glBindVertexArray(p->proxy_vao);
  if (coarse)
    glDrawElements(GL_TRIANGLES, p->coarse_count, GL_UNSIGNED_INT,
                   (void *)((size_t)p->proxy_count * sizeof(uint32_t)));
  else
    glDrawElements(GL_TRIANGLES, p->proxy_count, GL_UNSIGNED_INT, NULL);
}

/* The outermost shell of every cluster, in list order: each fragment
 * accounts for all the shells behind it (shaders.c). */
static void draw_clusters(satf_renderer *r, GLuint prog,
                          const float viewproj[16], int coarse) {
  GLint loc[4];
  use_layer_program(r, prog, viewproj, loc);
  for (int i = 0; i < r->ninsts; i++) {
    inst *in = &r->insts[i];
    proto *p = &r->protos[in->proto];
    bind_instance(r, prog, in, loc);
    draw_proxy(p, coarse);
  }
  glBindVertexArray(0);
}

/* The opaque meshes with `prog` (per-mesh model and normal matrices). */
static void draw_meshes(const satf_renderer *r, GLuint prog,
                        const float viewproj[16]) {
  glUseProgram(prog);
  set_mat4(prog, "u_viewproj", viewproj);
  GLint model = glGetUniformLocation(prog, "u_model");
  GLint nmat = glGetUniformLocation(prog, "u_normal_matrix");
  GLint albedo = glGetUniformLocation(prog, "u_albedo");
  for (int i = 0; i < r->nmeshes; i++) {
    const mesh_gpu *g = &r->meshes[i];
    glUniformMatrix4fv(model, 1, GL_TRUE, g->m);
    glUniformMatrix3fv(nmat, 1, GL_TRUE, g->nmat);
    glUniform3fv(albedo, 1, g->color);
    glBindVertexArray(g->vao);
    glDrawElements(GL_TRIANGLES, g->count, GL_UNSIGNED_INT, NULL);
  }
  glBindVertexArray(0);
}

static float scene_radius(const satf_renderer *r, float centre[3]) {
  float d2 = 0.0f;
  for (int a = 0; a < 3; a++) {
    centre[a] = 0.5f * (r->lo[a] + r->hi[a]);
    float h = 0.5f * (r->hi[a] - r->lo[a]);
    d2 += h * h;
  }
  return sqrtf(d2) + 1e-3f;
}

/* Deep opacity map from the key light: an orthographic view along its
 * direction (a point light is treated as directional from its position
 * towards the scene centre), four slabs behind the first hair. */
static void render_dom(satf_renderer *r) {
  float c[3], rad = scene_radius(r, c), lv[4], dir[3];
  light_vector(&r->lights[0], lv);
  for (int a = 0; a < 3; a++)
    dir[a] = lv[3] != 0.0f ? lv[a] - c[a] : lv[a];
  float len = sqrtf(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  for (int a = 0; a < 3; a++)
    dir[a] = len > 0 ? dir[a] / len : (a == 1);
  float eye[3] = {c[0] + 2 * rad * dir[0], c[1] + 2 * rad * dir[1],
                  c[2] + 2 * rad * dir[2]};
  float up[3] = {0, 1, 0};
  if (fabsf(dir[1]) > 0.95f) {
    up[1] = 0;
    up[2] = 1;
  }
  float view[16], proj[16];
  satf_mat4_look_at(eye, c, up, view);
  satf_mat4_ortho(-rad, rad, -rad, rad, rad, 3 * rad, proj);
  satf_mat4_mul(proj, view, r->light_viewproj);
  /* slabs a third of a typical cluster's radius deep, in depth units */
  float cluster_r = 0.0f;
  for (int m = 0; m < r->nprotos; m++)
    cluster_r += r->scene->macro_clusters[m].prototype.a.values[0];
  cluster_r /= (float)(r->nprotos > 0 ? r->nprotos : 1);
  r->dom_slab = 0.66f * cluster_r / (2.0f * rad) * 0.5f;

  satf_gl_target_bind(r->dom_depth);
  glClearColor(0, 0, 0, 0);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  draw_clusters(r, r->prog_depth, r->light_viewproj, 1);
  draw_meshes(r, r->prog_mesh_depth, r->light_viewproj);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDisable(GL_DEPTH_TEST);

  satf_gl_target_bind(r->dom_opacity);
  glClear(GL_COLOR_BUFFER_BIT);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE);
  glUseProgram(r->prog_dom);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_depth_texture(r->dom_depth));
  glUniform1i(glGetUniformLocation(r->prog_dom, "u_dom_depth"), 1);
  glUniform1f(glGetUniformLocation(r->prog_dom, "u_dom_slab"), r->dom_slab);
  draw_clusters(r, r->prog_dom, r->light_viewproj, 1);
  if (r->nmeshes > 0) {
    glUseProgram(r->prog_mesh_dom);
    glUniform1i(glGetUniformLocation(r->prog_mesh_dom, "u_dom_depth"), 1);
    glUniform1f(glGetUniformLocation(r->prog_mesh_dom, "u_dom_slab"),
                r->dom_slab);
    draw_meshes(r, r->prog_mesh_dom, r->light_viewproj);
  }
  glDisable(GL_BLEND);
}

static void camera_matrices(const satf_renderer *r, float viewproj[16]) {
  const satf_scene_camera *cam = &r->camera;
  float c[3], rad = scene_radius(r, c), view[16], proj[16];
  float n = cam->near_clip, f = cam->far_clip;
  if (!(n > 0.0f && f > n)) {
    float d = sqrtf((cam->position[0] - c[0]) * (cam->position[0] - c[0]) +
                    (cam->position[1] - c[1]) * (cam->position[1] - c[1]) +
                    (cam->position[2] - c[2]) * (cam->position[2] - c[2]));
    f = d + 1.5f * rad;
    n = d - 1.5f * rad;
    if (n < 0.002f * f)
      n = 0.002f * f;
  }
  satf_mat4_look_at(cam->position, cam->target, cam->up, view);
  satf_mat4_perspective(cam->fov_y, (float)r->width / (float)r->height, n, f,
                        proj);
  satf_mat4_mul(proj, view, viewproj);
}

static void set_shading_uniforms(satf_renderer *r, GLuint p, satf_aov aov) {
  const satf_scene_material *m = &r->scene->material;
  glUseProgram(p);
  glUniform1i(glGetUniformLocation(p, "u_nlights"), r->nlights);
  float col[12];
  for (int k = 0; k < r->nlights; k++)
    for (int a = 0; a < 3; a++)
      col[3 * k + a] = r->lights[k].color[a] * r->lights[k].intensity;
  glUniform3fv(glGetUniformLocation(p, "u_light_color"), r->nlights, col);
  glUniform1f(glGetUniformLocation(p, "u_kdif"), m->k_dif);
  glUniform1f(glGetUniformLocation(p, "u_kspe1"), m->k_speI);
  glUniform1f(glGetUniformLocation(p, "u_kspe2"), m->k_speII);
  glUniform1f(glGetUniformLocation(p, "u_exp1"), m->exponent_I);
  glUniform1f(glGetUniformLocation(p, "u_exp2"), m->exponent_II);
  glUniform1f(glGetUniformLocation(p, "u_shift1"), m->shift_I);
  glUniform1f(glGetUniformLocation(p, "u_shift2"), m->shift_II);
  glUniform3fv(glGetUniformLocation(p, "u_fdif"), 1, m->f_dif);
  glUniform3fv(glGetUniformLocation(p, "u_fspe1"), 1, m->f_speI);
  glUniform3fv(glGetUniformLocation(p, "u_fspe2"), 1, m->f_speII);
  glUniform1f(glGetUniformLocation(p, "u_kshadow"), m->k_shadow);
  glUniform1f(glGetUniformLocation(p, "u_noise"), m->noise);
  glUniform1i(glGetUniformLocation(p, "u_secondary"),
              r->effects.secondary_highlight);
  glUniform1i(glGetUniformLocation(p, "u_self_shadow"), r->effects.self_shadow);
  glUniform1i(glGetUniformLocation(p, "u_cluster_shadow"),
              r->effects.cluster_shadows);
  glUniform1i(glGetUniformLocation(p, "u_aov"), (int)aov);
  glUniform1i(glGetUniformLocation(p, "u_slots"), r->slots);
  glUniform1f(glGetUniformLocation(p, "u_kcluster"), 1.0f);
  glUniform1f(glGetUniformLocation(p, "u_dom_slab"), r->dom_slab);
  set_mat4(p, "u_light_viewproj", r->light_viewproj);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_depth_texture(r->dom_depth));
  glUniform1i(glGetUniformLocation(p, "u_dom_depth"), 2);
  glActiveTexture(GL_TEXTURE3);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_color_texture(r->dom_opacity, 0));
  glUniform1i(glGetUniformLocation(p, "u_dom_opacity"), 3);
}

/* Pixel rectangle (x, y, w, h) covering the projected scene bounds; the
 * whole frame when a corner is behind the eye. */
static void screen_box(const satf_renderer *r, const float viewproj[16],
                       int box[4]) {
  float mn[2] = {1e30f, 1e30f}, mx[2] = {-1e30f, -1e30f};
  int behind = 0;
  for (int c = 0; c < 8; c++) {
    float p[3] = {c & 1 ? r->hi[0] : r->lo[0], c & 2 ? r->hi[1] : r->lo[1],
                  c & 4 ? r->hi[2] : r->lo[2]};
    float w = viewproj[12] * p[0] + viewproj[13] * p[1] + viewproj[14] * p[2] +
              viewproj[15];
    if (w <= 1e-6f) {
      behind = 1;
      break;
    }
    for (int a = 0; a < 2; a++) {
      float q = (viewproj[4 * a] * p[0] + viewproj[4 * a + 1] * p[1] +
                 viewproj[4 * a + 2] * p[2] + viewproj[4 * a + 3]) /
                w;
      mn[a] = q < mn[a] ? q : mn[a];
      mx[a] = q > mx[a] ? q : mx[a];
    }
  }
  int size[2] = {r->width, r->height};
  for (int a = 0; a < 2; a++) {
    int lo = behind ? 0 : (int)floorf((mn[a] * 0.5f + 0.5f) * size[a]) - 1;
    int hi = behind ? size[a] : (int)ceilf((mx[a] * 0.5f + 0.5f) * size[a]) + 1;
    lo = lo < 0 ? 0 : lo > size[a] ? size[a] : lo;
    hi = hi < lo ? lo : hi > size[a] ? size[a] : hi;
    box[a] = lo;
    box[2 + a] = hi - lo;
  }
}

/* Clears the frame to the background (or black for AOVs) and draws the
 * opaque meshes, leaving their depth for the hair to test against. */
static void begin_frame(satf_renderer *r, satf_aov aov,
                        const float viewproj[16]) {
  satf_gl_target_bind(r->out);
  if (aov == SATF_AOV_BEAUTY)
    glClearColor(r->scene->background[0], r->scene->background[1],
                 r->scene->background[2], 0.0f);
  else
    glClearColor(0, 0, 0, 0);
  glClearDepth(1.0);
  glDepthMask(GL_TRUE);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (r->nmeshes == 0)
    return;
  GLuint p = r->prog_mesh;
  glUseProgram(p);
  float vec[16], col[12];
  for (int k = 0; k < r->nlights; k++) {
    light_vector(&r->lights[k], vec + 4 * k);
    for (int a = 0; a < 3; a++)
      col[3 * k + a] = r->lights[k].color[a] * r->lights[k].intensity;
  }
  glUniform3fv(glGetUniformLocation(p, "u_eye"), 1, r->camera.position);
  glUniform1i(glGetUniformLocation(p, "u_nlights"), r->nlights);
  glUniform4fv(glGetUniformLocation(p, "u_light_vec"), r->nlights, vec);
  glUniform3fv(glGetUniformLocation(p, "u_light_color"), r->nlights, col);
  glUniform1i(glGetUniformLocation(p, "u_cluster_shadow"),
              r->effects.cluster_shadows);
  glUniform1i(glGetUniformLocation(p, "u_aov"), (int)aov);
  glUniform1f(glGetUniformLocation(p, "u_kcluster"), 1.0f);
  glUniform1f(glGetUniformLocation(p, "u_dom_slab"), r->dom_slab);
  set_mat4(p, "u_light_viewproj", r->light_viewproj);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_depth_texture(r->dom_depth));
  glUniform1i(glGetUniformLocation(p, "u_dom_depth"), 2);
  glActiveTexture(GL_TEXTURE3);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_color_texture(r->dom_opacity, 0));
  glUniform1i(glGetUniformLocation(p, "u_dom_opacity"), 3);
  glActiveTexture(GL_TEXTURE0);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  draw_meshes(r, p, viewproj);
  glDisable(GL_DEPTH_TEST);
}

/* Hair tests against the meshes' depth without writing it. */
static void hair_depth_test(int on) {
  if (on) {
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_FALSE);
  } else {
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
  }
}

/* Per-pixel fragment arrays, then the sorted composite (SATF eq. 14).
 * Returns the largest number of fragments a pixel received. */
static GLuint render_lists(satf_renderer *r, satf_aov aov,
                           const float viewproj[16], long *fragments) {
  GLuint zero = 0;
  begin_frame(r, aov, viewproj);
  glClearTexImage(r->counts_tex, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glBindImageTexture(0, r->counts_tex, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
  glBindImageTexture(1, r->frags_tex, 0, GL_TRUE, 0, GL_READ_WRITE,
                     GL_RGBA32UI);
  glBindFramebuffer(GL_FRAMEBUFFER, r->list_fbo);
  glViewport(0, 0, r->width, r->height);
  hair_depth_test(r->nmeshes > 0);
  glDisable(GL_CULL_FACE);
  set_shading_uniforms(r, r->prog_shade, aov);
  glEnable(GL_CULL_FACE); /* front faces: each traces the whole cluster */
  glCullFace(GL_BACK);
  draw_clusters(r, r->prog_shade, viewproj, 0);
  glDisable(GL_CULL_FACE);
  hair_depth_test(0);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                  GL_TEXTURE_FETCH_BARRIER_BIT);
  satf_gl_target_bind(r->out);
  glEnable(GL_BLEND); /* the hair's composite over background and meshes */
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  /* only pixels the hair can cover need resolving */
  int box[4];
  screen_box(r, viewproj, box);
  glEnable(GL_SCISSOR_TEST);
  glScissor(box[0], box[1], box[2], box[3]);
  glUseProgram(r->prog_resolve);
  glUniform1i(glGetUniformLocation(r->prog_resolve, "u_slots"), r->slots);
  glBindVertexArray(r->empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
  /* the deepest pixel decides whether the arrays were large enough */
  size_t n = (size_t)r->width * (size_t)r->height;
  GLuint *counts = malloc(n * sizeof(GLuint)), most = 0;
  *fragments = 0;
  if (counts) {
    glBindTexture(GL_TEXTURE_2D, r->counts_tex);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, counts);
    for (size_t i = 0; i < n; i++) {
      most = counts[i] > most ? counts[i] : most;
      *fragments += counts[i];
    }
    free(counts);
  }
  return most;
}

typedef struct depth_key {
  float d2;
  float centre[3];
  int index;
} depth_key;

/* Far first; equal distances by position, never by list order. */
static int farther_first(const void *a, const void *b) {
  const depth_key *x = a, *y = b;
  if (x->d2 != y->d2)
    return x->d2 < y->d2 ? 1 : -1;
  for (int k = 0; k < 3; k++)
    if (x->centre[k] != y->centre[k])
      return x->centre[k] < y->centre[k] ? -1 : 1;
  return 0;
}

/* SATF eq. 14 by drawing order (see satf_composite in renderer.h). */
static satf_status render_ordered(satf_renderer *r, satf_aov aov,
                                  const float viewproj[16], satf_error *err) {
  depth_key *keys = malloc((size_t)r->ninsts * sizeof *keys);
  if (!keys)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  for (int i = 0; i < r->ninsts; i++) {
    const float *c = r->insts[i].centre, *e = r->camera.position;
    keys[i].d2 = (c[0] - e[0]) * (c[0] - e[0]) + (c[1] - e[1]) * (c[1] - e[1]) +
                 (c[2] - e[2]) * (c[2] - e[2]);
    memcpy(keys[i].centre, c, sizeof keys[i].centre);
    keys[i].index = i;
  }
  qsort(keys, (size_t)r->ninsts, sizeof *keys, farther_first);
  begin_frame(r, aov, viewproj);
  hair_depth_test(r->nmeshes > 0);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); /* premultiplied "over" */
  glEnable(GL_CULL_FACE);
  GLuint prog = r->prog_shade_ordered;
  set_shading_uniforms(r, prog, aov);
  GLint loc[4];
  use_layer_program(r, prog, viewproj, loc);
  glCullFace(GL_BACK);
  for (int q = 0; q < r->ninsts; q++) {
    const inst *in = &r->insts[keys[q].index];
    const proto *p = &r->protos[in->proto];
    bind_instance(r, prog, in, loc);
    draw_proxy(p, 0);
  }
  glBindVertexArray(0);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  hair_depth_test(0);
  free(keys);
  return SATF_OK;
}

/* A frame; with refresh 0 the maps and the deep opacity map of the
 * previous frame are reused (the AOV passes of one image). */
static satf_status render_frame(satf_renderer *r, satf_aov aov, int refresh,
                                satf_frame_timing *timing, satf_error *err) {
  satf_frame_timing t;
  memset(&t, 0, sizeof t);
  double t0 = satf_now_seconds();
  satf_status st = refresh ? update_maps(r, &t, err) : SATF_OK;
  if (st != SATF_OK)
    return st;
  double t1 = satf_now_seconds();
  if (refresh && r->effects.cluster_shadows)
    render_dom(r);
  glFinish();
  double t2 = satf_now_seconds();
  float viewproj[16];
  camera_matrices(r, viewproj);
  long count = 0;
  GLuint most = 0;
  if (r->composite == SATF_COMPOSITE_ORDERED) {
    st = render_ordered(r, aov, viewproj, err);
    if (st != SATF_OK)
      return st;
  } else {
    most = render_lists(r, aov, viewproj, &count);
  }
  if (r->composite == SATF_COMPOSITE_EXACT && (int)most > r->slots &&
      r->slots < SATF_MAX_FRAGMENTS) {
    /* some pixel had more fragments than slots: grow and draw again */
    int slots = (int)most + 4;
    st = alloc_lists(r, slots < SATF_MAX_FRAGMENTS ? slots : SATF_MAX_FRAGMENTS,
                     err);
    if (st != SATF_OK)
      return st;
    render_lists(r, aov, viewproj, &count);
  }
  glFinish();
  double t3 = satf_now_seconds();
  t.shadow_ms = 1e3 * (t2 - t1);
  t.lighting_ms = 1e3 * (t3 - t2);
  t.total_ms = 1e3 * (t3 - t0);
  t.fragments = (long)count;
  if (timing)
    *timing = t;
  return satf_gl_check("frame", err);
}

satf_status satf_renderer_render(satf_renderer *r, satf_aov aov,
                                 satf_frame_timing *timing, satf_error *err) {
  return render_frame(r, aov, 1, timing, err);
}

void satf_renderer_present(satf_renderer *r) {
  glUseProgram(r->prog_display);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_color_texture(r->out, 0));
  glUniform1i(glGetUniformLocation(r->prog_display, "u_image"), 0);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glBindVertexArray(r->empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}

satf_status satf_renderer_render_image(satf_renderer *r, int aovs,
                                       satf_image **out,
                                       satf_frame_timing *timing,
                                       satf_error *err) {
  *out = NULL;
  static const char *const names[] = {
      "R",         "G",         "B",        "A",       "diffuse.R",
      "diffuse.G", "diffuse.B", "specI.R",  "specI.G", "specI.B",
      "specII.R",  "specII.G",  "specII.B", "shadow",  "alpha"};
  int n = aovs ? 15 : 4;
  satf_image *img = NULL;
  satf_status st = satf_image_create(r->width, r->height, names, n, &img, err);
  if (st != SATF_OK)
    return st;
  size_t px = (size_t)r->width * (size_t)r->height;
  float *buf = malloc(px * 4 * sizeof(float));
  if (!buf) {
    satf_image_destroy(img);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  const char *const *dest[SATF_AOV_COUNT] = {
      (const char *const[]){"R", "G", "B", "A"},
      (const char *const[]){"diffuse.R", "diffuse.G", "diffuse.B", NULL},
      (const char *const[]){"specI.R", "specI.G", "specI.B", NULL},
      (const char *const[]){"specII.R", "specII.G", "specII.B", NULL},
      (const char *const[]){"shadow", NULL, NULL, NULL},
      (const char *const[]){"alpha", NULL, NULL, NULL}};
  int passes = aovs ? SATF_AOV_COUNT : 1;
  for (int a = 0; a < passes && st == SATF_OK; a++) {
    /* shadow and alpha AOVs are coverage-weighted: their composite over a
     * black background, as the other AOVs */
    st = render_frame(r, (satf_aov)a, a == 0, a == 0 ? timing : NULL, err);
    if (st == SATF_OK)
      st = satf_gl_target_read_bottom_up(r->out, 0, buf, px * 4, err);
    if (st == SATF_OK)
      st = satf_image_store_interleaved(img, buf, 4, dest[a],
                                        SATF_ROWS_BOTTOM_UP, err);
  }
  free(buf);
  if (st != SATF_OK) {
    satf_image_destroy(img);
    return st;
  }
  *out = img;
  return SATF_OK;
}

satf_status satf_renderer_export_meshes(const satf_renderer *r,
                                        const char *path, int *written,
                                        satf_error *err) {
  *written = 0;
  const char *dot = strrchr(path, '.');
  if (!dot || (strcmp(dot, ".obj") && strcmp(dot, ".ply")))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: mesh files must end in .obj or .ply", path);
  for (int m = 0; m < r->nprotos; m++) {
    const proto *p = &r->protos[m];
    for (int k = 0; k < p->layers; k++) {
      char file[4096];
      int n = snprintf(file, sizeof file, "%.*s-m%d-l%d%s", (int)(dot - path),
                       path, m, k, dot);
      if (n < 0 || (size_t)n >= sizeof file)
        return satf_error_set(err, SATF_ERR_ARGUMENT, "%s: path too long",
                              path);
      satf_mesh *mesh = NULL;
      satf_status st = satf_cluster_build_layer_mesh(p->cluster, &p->geom.shell,
                                                     k, &mesh, err);
      if (st == SATF_OK)
        st = satf_mesh_write(mesh, file, err);
      satf_mesh_destroy(mesh);
      if (st != SATF_OK)
        return st;
      (*written)++;
    }
  }
  return SATF_OK;
}

static int curve_equal(const satf_scene_curve *a, const satf_scene_curve *b) {
  return a->count == b->count &&
         !memcmp(a->values, b->values, (size_t)a->count * sizeof(float));
}

/* Same generalized cylinder (trajectory, A, B, twist, shells). */
static int cluster_geometry_equal(const satf_scene_cluster *a,
                                  const satf_scene_cluster *b) {
  return a->n_points == b->n_points &&
         !memcmp(a->trajectory, b->trajectory,
                 3 * (size_t)a->n_points * sizeof(float)) &&
         curve_equal(&a->a, &b->a) && curve_equal(&a->b, &b->b) &&
         curve_equal(&a->twist, &b->twist) &&
         !memcmp(&a->shell, &b->shell, sizeof a->shell);
}

satf_status satf_renderer_set_scene(satf_renderer *r, const satf_scene *scene,
                                    int *rebuilt, satf_error *err) {
  int moved = 0;
  if (scene->n_macro_clusters != r->nprotos)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: %d macro-clusters, the renderer has %d",
                          scene->name ? scene->name : "scene",
                          scene->n_macro_clusters, r->nprotos);
  for (int m = 0; m < r->nprotos; m++) {
    const satf_scene_macro_cluster *a = &r->scene->macro_clusters[m];
    const satf_scene_macro_cluster *b = &scene->macro_clusters[m];
    if (a->n_instances != b->n_instances ||
        memcmp(&a->prototype.shell, &b->prototype.shell,
               sizeof a->prototype.shell))
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "%s: macro_clusters[%d] changed its instances or "
                            "shells; only geometry and transforms can animate",
                            scene->name ? scene->name : "scene", m);
  }
  const satf_scene *old = r->scene;
  r->scene = scene;
  int ii = 0;
  satf_status st = SATF_OK;
  for (int m = 0; m < r->nprotos && st == SATF_OK; m++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    int changed = !cluster_geometry_equal(&old->macro_clusters[m].prototype,
                                          &mc->prototype);
    if (changed) { /* the density, in the cluster's own frame, stays */
      proto *p = &r->protos[m];
      float *features = p->geom.features;
      satf_neighbor_cache *nb = p->geom.neighbors;
      p->geom.features = NULL;
      p->geom.neighbors = NULL;
      release_geometry(p);
      st = build_geometry(r, m, &mc->prototype, features, err);
      free(features);
      if (st == SATF_OK)
        p->geom.neighbors = nb;
      else
        satf_neighbor_cache_free(nb);
      moved++;
    }
    for (int i = 0; i < mc->n_instances && st == SATF_OK; i++, ii++) {
      inst *in = &r->insts[ii];
      if (changed || memcmp(in->m, mc->instances[i].m, sizeof in->m)) {
        memcpy(in->m, mc->instances[i].m, sizeof in->m);
        st = place_inst(r, in, err);
      }
    }
  }
  r->camera = scene->camera;
  r->nlights = scene->n_lights < 4 ? scene->n_lights : 4;
  memcpy(r->lights, scene->lights,
         (size_t)r->nlights * sizeof(satf_scene_light));
  satf_scene_bounds(scene, r->lo, r->hi);
  if (rebuilt)
    *rebuilt = moved;
  return st;
}
