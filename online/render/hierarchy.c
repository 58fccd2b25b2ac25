/* hierarchy.c - owns the renderer's prototypes and instances: each
 * macro-cluster's generalized cylinder, shell geometry, density features
 * and drawn proxy, and each instance's transform, map texture and (for
 * world-space density) own features; built at creation, rebuilt where an
 * animation frame changes them, released at destruction. */
#include "renderer_internal.h"

#include <stdlib.h>
#include <string.h>

#include "mat4.h"
#include "satf/math.h"

/* Columns of the drawn proxy of a cluster's outermost shell. Shading
 * traces each ray through the shells analytically (glsl/shade_fs.glsl),
 * so the proxy only has to cover the cluster's silhouette; a CPU
 * rasteriser pays for every triangle on one thread, so it is kept coarse
 * around the cluster and as fine as the HSVs along it. Thin clusters far
 * away take half the columns and coarser rows (lod.h); the deep opacity
 * map's passes take LOD_PROXY_DOM. */
#define PROXY_COLUMNS 12
#define THIN_COLUMNS 6

/* The proxy: (st + 1) x (PROXY_COLUMNS + 1) vertices on an elliptic
 * cylinder circumscribing the outer shell (then the thin ring's, then the
 * hubs of the end caps that close it for the shading passes: a cluster
 * seen down its axis shows no outward wall), each with position, hair
 * tangent, (u, t), and the cross-section at t as the shading pass needs it:
 * C(t), the ellipse's axes n1, n2 (already turned by the twist theta, SATF
 * eq. 1 as satf/geometry.h reads it, so the shader measures the phase u
 * from them directly), (A, B, theta, |dT/dt|), the unit tangent of T. */
enum { PROXY_FLOATS = 24 };

void hierarchy_resample_curve(const satf_scene_curve *c, int n, float *out) {
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

/* One proxy vertex (PROXY_FLOATS, layout above) of section sec at t: at
 * radius v (1: the outer shell) and phase u, texture u coordinate `tex_u`;
 * the hair's direction is the outer shell's where v lies beyond it. */
static void proxy_vertex(const satf_cluster_section *sec, float t, float v,
                         float u, float tex_u, float *out) {
  satf_cluster_section_point(sec, v, u, out);
  satf_cluster_section_hair_tangent(sec, v < 1.0f ? v : 1.0f, u, out + 3);
  out[6] = tex_u;
  out[7] = t;
  memcpy(out + 8, sec->center, 3 * sizeof(float));
  memcpy(out + 11, sec->n1, 3 * sizeof(float));
  memcpy(out + 14, sec->n2, 3 * sizeof(float));
  out[17] = sec->a;
  out[18] = sec->b;
  out[19] = sec->theta;
  out[20] = sqrtf(satf_dot3f(sec->dcenter, sec->dcenter));
  memcpy(out + 21, sec->tangent, 3 * sizeof(float));
}

/* The proxy's vertices (PROXY_FLOATS each, layout above) for `columns`
 * columns around. */
static void proxy_vertices(const satf_cluster *cluster, int st, int columns,
                           float *f) {
  int cols = columns + 1;
  /* the polygon's edges touch the shell: it covers every pixel the shell
   * covers */
  float inflate = 1.0f / cosf(SATF_PI_F / (float)columns);
  for (int i = 0; i <= st; i++) {
    satf_cluster_section sec;
    float t = (float)i / (float)st;
    satf_cluster_section_at(cluster, t, &sec);
    for (int j = 0; j < cols; j++)
      proxy_vertex(&sec, t, inflate, SATF_TWO_PI_F * (float)j / (float)columns,
                   (float)j / (float)columns,
                   f + PROXY_FLOATS * ((size_t)i * cols + (size_t)j));
  }
}

/* The centres of the proxy's two ends, t = 0 then t = 1, into f (2 x
 * PROXY_FLOATS): the hubs of its end caps. */
static void proxy_hubs(const satf_cluster *cluster, float *f) {
  for (int e = 0; e < 2; e++) {
    satf_cluster_section sec;
    satf_cluster_section_at(cluster, (float)e, &sec);
    proxy_vertex(&sec, (float)e, 0.0f, 0.0f, 0.0f, f + PROXY_FLOATS * e);
  }
}

/* Two triangles between rows i0 and i1 of a proxy of `columns` columns
 * whose vertices start at `base`, for every column, counter-clockwise seen
 * from outside (d/du x d/dt points outwards); returns the end of what was
 * written. */
static uint32_t *proxy_band(int i0, int i1, int columns, uint32_t base,
                            uint32_t *q) {
  int cols = columns + 1;
  for (int j = 0; j < columns; j++) {
    uint32_t a = base + (uint32_t)(i0 * cols + j), b = a + 1;
    uint32_t c = base + (uint32_t)(i1 * cols + j), d = c + 1;
    *q++ = a, *q++ = b, *q++ = c;
    *q++ = b, *q++ = d, *q++ = c;
  }
  return q;
}

/* Whether proxy `level` is closed by caps at its ends: the shading's
 * levels, not the light passes' (LOD_PROXY_DOM: its walls' alpha is the
 * whole column's, cluster_dom.c). */
static int proxy_capped(int level) { return level != LOD_PROXY_DOM; }

/* Triangles of proxy `level` (lod.h) for st rows. */
static size_t proxy_triangles(int level, int st) {
  int rows = lod_proxy_rows(level);
  int cols = lod_proxy_thin(level) ? THIN_COLUMNS : PROXY_COLUMNS;
  return 2 * (size_t)((st + rows - 1) / rows) * (size_t)cols +
         (proxy_capped(level) ? 2 * (size_t)cols : 0);
}

/* The two end caps of a proxy of `columns` columns whose ring vertices
 * start at `base` (st rows) and whose hubs are `hubs` (t = 0) and hubs + 1
 * (t = 1): a fan each, counter-clockwise seen from outside, as
 * proxy_band's faces (d/du x d/dt outwards makes n1 x n2 the direction of
 * growing t, so the fan turns with u at t = 1 and against it at t = 0). */
static uint32_t *proxy_caps(int st, int columns, uint32_t base, uint32_t hubs,
                            uint32_t *q) {
  int cols = columns + 1;
  for (int j = 0; j < columns; j++) {
    uint32_t a = base + (uint32_t)j, e = base + (uint32_t)(st * cols + j);
    *q++ = hubs, *q++ = a + 1, *q++ = a;
    *q++ = hubs + 1, *q++ = e, *q++ = e + 1;
  }
  return q;
}

/* Every proxy's bands and caps, one after another (p->lod_first,
 * p->lod_count); the thin ones' vertices start at `thin_base`, the hubs
 * at `hubs`. */
static void proxy_indices(proto *p, int st, uint32_t thin_base, uint32_t hubs,
                          uint32_t *q) {
  const uint32_t *start = q;
  for (int level = 0; level < LOD_PROXIES; level++) {
    int rows = lod_proxy_rows(level), thin = lod_proxy_thin(level);
    int columns = thin ? THIN_COLUMNS : PROXY_COLUMNS;
    uint32_t base = thin ? thin_base : 0;
    p->lod_first[level] = (GLsizei)(q - start);
    for (int i = 0; i < st; i += rows)
      q = proxy_band(i, i + rows < st ? i + rows : st, columns, base, q);
    if (proxy_capped(level))
      q = proxy_caps(st, columns, base, hubs, q);
    p->lod_count[level] = (GLsizei)(q - start) - p->lod_first[level];
  }
}

/* The proxy's buffers and vertex attributes, at the locations of
 * glsl/cluster_vs.glsl and glsl/layer_vs.glsl. */
static void proxy_upload(proto *p, const float *f, size_t nv,
                         const uint32_t *idx, size_t nidx) {
  glGenVertexArrays(1, &p->proxy_vao);
  glGenBuffers(1, &p->proxy_vbo);
  glGenBuffers(1, &p->proxy_ibo);
  glBindVertexArray(p->proxy_vao);
  glBindBuffer(GL_ARRAY_BUFFER, p->proxy_vbo);
  glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nv * PROXY_FLOATS * sizeof(float)),
               f, GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, p->proxy_ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(nidx * sizeof(uint32_t)),
               idx, GL_STATIC_DRAW);
  const GLuint loc[8] = {0, 2, 3, 4, 5, 6, 7, 8};
  const GLint sizes[8] = {3, 3, 2, 3, 3, 3, 4, 3};
  const size_t offs[8] = {0, 3, 6, 8, 11, 14, 17, 21};
  for (int a = 0; a < 8; a++) {
    glEnableVertexAttribArray(loc[a]);
    glVertexAttribPointer(loc[a], sizes[a], GL_FLOAT, GL_FALSE,
                          PROXY_FLOATS * sizeof(float),
                          (void *)(offs[a] * sizeof(float)));
  }
  glBindVertexArray(0);
}

static satf_status build_proxy(proto *p, const satf_shell_params *sh,
                               satf_error *err) {
  size_t nfull = (size_t)(sh->st + 1) * (size_t)(PROXY_COLUMNS + 1);
  size_t nthin = (size_t)(sh->st + 1) * (size_t)(THIN_COLUMNS + 1);
  size_t nv = nfull + nthin + 2; /* and the caps' two hubs */
  size_t ntri = 0;
  for (int level = 0; level < LOD_PROXIES; level++)
    ntri += proxy_triangles(level, sh->st);
  float *f = malloc(nv * PROXY_FLOATS * sizeof(float));
  uint32_t *idx = malloc(ntri * 3 * sizeof(uint32_t));
  if (!f || !idx) {
    free(f);
    free(idx);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  proxy_vertices(p->cluster, sh->st, PROXY_COLUMNS, f);
  proxy_vertices(p->cluster, sh->st, THIN_COLUMNS, f + nfull * PROXY_FLOATS);
  proxy_hubs(p->cluster, f + (nfull + nthin) * PROXY_FLOATS);
  proxy_indices(p, sh->st, (uint32_t)nfull, (uint32_t)(nfull + nthin), idx);
  lod_measure(f, nfull, PROXY_FLOATS, PROXY_COLUMNS + 1, sh->st, p->lod_sphere,
              &p->lod_width, &p->lod_sag);
  proxy_upload(p, f, nv, idx, ntri * 3);
  free(f);
  free(idx);
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

satf_status hierarchy_cluster_create(const satf_scene_cluster *c,
                                     satf_cluster **out, satf_error *err) {
  int n = c->a.count;
  if (c->b.count > n)
    n = c->b.count;
  if (c->twist.count > n)
    n = c->twist.count;
  float *radii = malloc(3 * (size_t)n * sizeof(float));
  if (!radii)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  hierarchy_resample_curve(&c->a, n, radii);
  hierarchy_resample_curve(&c->b, n, radii + n);
  hierarchy_resample_curve(&c->twist, n, radii + 2 * n);
  satf_cluster_desc desc = {c->n_points, c->trajectory, n,
                            radii,       radii + n,     radii + 2 * n};
  satf_status st = satf_cluster_create(&desc, out, err);
  free(radii);
  return st;
}

/* The generalized cylinder of a scene cluster, its shell geometry (sector
 * frames; features are kept when `keep` holds them), layer meshes and
 * frames on the GPU. Used at creation and when an animation moves it. */
static satf_status build_geometry(satf_renderer *r, int index,
                                  const satf_scene_cluster *c,
                                  const float *keep, satf_error *err) {
  proto *p = &r->protos[index];
  const char *name = scene_name(r->scene);
  satf_error cerr;
  satf_status st = hierarchy_cluster_create(c, &p->cluster, &cerr);
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
  return build_proxy(p, &shell, err);
}

/* Prototype index's density grid: a handle on an earlier prototype's grid
 * when that names the same file and grid (an imported scene names one file
 * in every cluster, and a copy per cluster of a 30 MB grid ran into tens of
 * gigabytes), else read from the file. */
static satf_status read_vdb(const satf_renderer *r, int index,
                            const satf_scene_density *d, satf_vdb_grid **out,
                            satf_error *err) {
  for (int m = 0; m < index; m++) {
    const satf_scene_density *e =
        &r->scene->macro_clusters[m].prototype.density;
    if (!r->protos[m].vdb || e->type != SATF_SCENE_DENSITY_VDB ||
        strcmp(e->vdb_file, d->vdb_file) || strcmp(e->vdb_grid, d->vdb_grid))
      continue;
    *out = satf_vdb_grid_share(r->protos[m].vdb);
    return *out ? SATF_OK
                : satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory",
                                 d->vdb_file);
  }
  return satf_vdb_read(d->vdb_file, d->vdb_grid, out, err);
}

int hierarchy_sparse(const satf_scene_cluster *c, int max) {
  const satf_scene_density *d = &c->density;
  return d->type == SATF_SCENE_DENSITY_TRACKS &&
         satf_scene_tracks_as_strands(d->track_slices, d->n_tracks,
                                      d->track_count, max);
}

static satf_status build_proto(satf_renderer *r, int index,
                               const satf_scene_macro_cluster *mc,
                               satf_error *err) {
  proto *p = &r->protos[index];
  const satf_scene_cluster *c = &mc->prototype;
  const char *name = scene_name(r->scene);
  satf_status st = build_geometry(r, index, c, NULL, err);
  if (st != SATF_OK)
    return st;
  p->sparse = hierarchy_sparse(c, r->sparse_max);
  p->from_strands = c->density.type != SATF_SCENE_DENSITY_PROCEDURAL;
  p->tilt = c->density.type == SATF_SCENE_DENSITY_VDB
                ? 0.0f
                : c->density.curl * (SATF_PI_F / 180.0f);
  if (c->density.type != SATF_SCENE_DENSITY_VDB)
    return SATF_OK;
  satf_error cerr;
  st = read_vdb(r, index, &c->density, &p->vdb, &cerr);
  if (st != SATF_OK)
    return satf_error_set(err, st,
                          "%s: macro_clusters[%d].prototype.density: %s", name,
                          index, cerr.message);
  return SATF_OK;
}

static satf_status map_textures_create(satf_renderer *r, satf_error *err);

/* Where the strands of a prototype of imported hair (a "tracks" density)
 * run in each of its sectors (satf_sector_hair_directions), for the
 * physical maps' M_p (maps_fiber.c); other densities and the kk mode keep
 * the trajectory's direction. Depends on the geometry: made again when an
 * animation changes it (rebuild_proto). */
static satf_status proto_hair(const satf_renderer *r, proto *p,
                              const satf_scene_density *d, satf_error *err) {
  if (!r->fiber || d->type != SATF_SCENE_DENSITY_TRACKS)
    return SATF_OK;
  size_t n = satf_shell_sector_count(&p->geom.shell);
  float *dirs = malloc(n * 3 * sizeof *dirs);
  if (!dirs)
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "cannot allocate the hair of %zu sectors", n);
  satf_status st = satf_sector_hair_directions(p->cluster, &p->geom.shell, d,
                                               r->threads, dirs, err);
  if (st == SATF_OK)
    st = satf_shell_geom_set_hair(&p->geom, dirs, err);
  free(dirs);
  return st;
}

/* What a prototype drawn as a cluster needs beyond its geometry: its
 * procedural or track strands and their features (once per prototype, SATF
 * sec. 3.1; a VDB's are per instance, place_inst), the database neighbours,
 * and its instances' map texels and textures. Left out for one drawn as
 * its strands: in an imported hairstyle most clusters are single strands
 * (the shared ponytail: 3,821 of 4,053, holding 92% of the HSVs), whose
 * features and maps cost most of the set-up and are never drawn. */
static satf_status prepare_proto(satf_renderer *r, int index, satf_error *err) {
  proto *p = &r->protos[index];
  const satf_scene_cluster *c = &r->scene->macro_clusters[index].prototype;
  satf_status st = SATF_OK;
  satf_error cerr;
  if (!p->vdb) {
    if (!p->strands)
      st = satf_strands_create(&c->density, &p->strands, &cerr);
    if (st == SATF_OK)
      st = satf_sector_features(p->cluster, &p->geom.shell, p->strands, NULL,
                                NULL, r->threads, p->geom.features, &cerr);
    if (st == SATF_OK)
      st = proto_hair(r, p, &c->density, &cerr);
    if (st == SATF_OK)
      st = satf_maps_prepare(r->maps, &p->geom, &r->map_opt, &cerr);
    if (st != SATF_OK)
      return satf_error_set(err, st,
                            "%s: macro_clusters[%d].prototype.density: %s",
                            scene_name(r->scene), index, cerr.message);
    /* the instances' shallow copies (place_inst) take the neighbours */
    for (int i = 0; i < p->ninsts; i++)
      r->insts[p->first_inst + i].geom = p->geom;
  }
  size_t texels =
      satf_maps_layer_texels(&p->geom, r->w) * (size_t)(p->layers * r->quads);
  for (int i = 0; i < p->ninsts; i++) {
    inst *in = &r->insts[p->first_inst + i];
    in->texels = calloc(texels * 4, sizeof *in->texels);
    if (!in->texels)
      return satf_error_set(err, SATF_ERR_NOMEM,
                            "cannot allocate %zu map texels", texels);
    cluster_cpu_forget_lookups(in);
  }
  p->ready = 1; /* its textures: map_textures_create, for all at once */
  return SATF_OK;
}

satf_status hierarchy_prepare(satf_renderer *r, satf_error *err) {
  satf_status st = SATF_OK;
  for (int m = 0; m < r->nprotos && st == SATF_OK; m++)
    if (!r->protos[m].ready && !r->protos[m].sparse)
      st = prepare_proto(r, m, err);
  return st == SATF_OK ? map_textures_create(r, err) : st;
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
                          scene_name(r->scene), in->proto);
  /* Shading measures Kajiya-Kay angles (SATF eq. 9-11) and the records'
   * azimuths (eq. 5) in the prototype's frame, which only rotations,
   * mirrors and uniform scale preserve: refuse the rest rather than draw
   * wrong highlights and wrong records. */
  float len[3];
  if (satf_mat4_similarity_error(in->m, len) > 1e-3f)
    return satf_error_set(
        err, SATF_ERR_ARGUMENT,
        "%s: macro_clusters[%d]: an instance has non-uniform scale or shear "
        "(axis lengths %g, %g, %g); the renderer draws cluster instances "
        "that are rotations, mirrors, uniform scales and translations, "
        "because it measures shading and database angles in the prototype's "
        "frame: scale the prototype's trajectory, a and b instead",
        scene_name(r->scene), in->proto, len[0], len[1], len[2]);
  satf_mat4_normal_matrix(in->m, in->nmat);
  if (in->looked_up) /* its frames or features may have moved */
    cluster_cpu_forget_lookups(in);
  /* a mirror turns the proxy inside out: its outward faces then wind
   * clockwise on screen (cluster_gpu.c flips the front face for it) */
  in->mirrored = satf_mat4_det3(in->m) < 0.0f;
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

/* St taken up to a multiple of 4 so that prototypes of nearly equal length
 * share texture arrays (the shaders address texels by the prototype's own
 * st and width, so the rows past them go unread). */
int hierarchy_map_rows(int st) { return 2 * ((st + 3) / 4 * 4); }

typedef struct map_need {
  int proto, width, rows;
} map_need;

static int map_need_order(const void *pa, const void *pb) {
  const map_need *a = pa, *b = pb;
  if (a->width != b->width)
    return a->width < b->width ? -1 : 1;
  if (a->rows != b->rows)
    return a->rows < b->rows ? -1 : 1;
  return a->proto < b->proto ? -1 : a->proto > b->proto;
}

typedef struct tex_key {
  GLuint tex;
  int inst;
} tex_key;

static int tex_key_order(const void *pa, const void *pb) {
  const tex_key *a = pa, *b = pb;
  if (a->tex != b->tex)
    return a->tex < b->tex ? -1 : 1;
  return a->inst < b->inst ? -1 : a->inst > b->inst;
}

/* r->tex_order: every instance, by map texture array, then by index (so a
 * prototype's instances in one array stay a run). */
static satf_status order_by_texture(satf_renderer *r, satf_error *err) {
  size_t n = (size_t)(r->ninsts > 0 ? r->ninsts : 1);
  tex_key *keys = malloc(n * sizeof *keys);
  int *order = realloc(r->tex_order, n * sizeof *order);
  if (order)
    r->tex_order = order;
  if (!keys || !order) {
    free(keys);
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  }
  for (int i = 0; i < r->ninsts; i++)
    keys[i] = (tex_key){r->insts[i].tex, i};
  qsort(keys, (size_t)r->ninsts, sizeof *keys, tex_key_order);
  for (int i = 0; i < r->ninsts; i++)
    order[i] = keys[i].inst;
  free(keys);
  return SATF_OK;
}

/* Texture array tex for maps of need's size, `layers` deep. */
static void map_array_storage(const satf_renderer *r, GLuint tex,
                              const map_need *need, int layers) {
  glBindTexture(GL_TEXTURE_2D_ARRAY, tex);
  glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1,
                 r->quads == 2 ? GL_RGBA32UI : GL_RGBA16F, need->width,
                 need->rows, layers);
  /* the shaders read texels (texelFetch); an integer texture with a
   * linear filter would be incomplete */
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

/* Map textures for every prepared prototype that has none: each instance
 * takes one layer per shell, su * w texels around and hierarchy_map_rows(st)
 * rows (half floats, half.h: RGBA16F, or in the physical mode RGBA32UI holding
 * a key and a fill quad of halfs, maps_fiber.h, so one fetch reads both),
 * in texture arrays shared by all the prototypes of one size (at most
 * GL_MAX_ARRAY_TEXTURE_LAYERS layers an array). Binding another texture
 * between two draws into the fragment arrays cost llvmpipe about 0.4 ms
 * (the shared ponytail: 242 shell clusters, 100 ms of its shading pass's
 * 300 at 640x480, as much at 160x120); drawn in the arrays' order
 * (cluster_gpu.c) the pass binds one per size. */
static satf_status map_textures_create(satf_renderer *r, satf_error *err) {
  GLint most = 256;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &most);
  map_need *need =
      malloc((size_t)(r->nprotos > 0 ? r->nprotos : 1) * sizeof *need);
  if (!need)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  int n = 0;
  for (int m = 0; m < r->nprotos; m++) {
    const proto *p = &r->protos[m];
    if (p->ready && !p->sparse && !p->textured && p->ninsts > 0)
      need[n++] = (map_need){m, p->geom.shell.su * r->w,
                             hierarchy_map_rows(p->geom.shell.st)};
  }
  qsort(need, (size_t)n, sizeof *need, map_need_order);
  satf_status st = SATF_OK;
  for (int a = 0; a < n && st == SATF_OK;) {
    int b = a; /* prototypes a .. b - 1 are of one size */
    while (b < n && need[b].width == need[a].width &&
           need[b].rows == need[a].rows)
      b++;
    /* their instances in order, in arrays of at most `most` layers: first
     * how many arrays, then their instances given them, each array made
     * as deep as its instances' layers once it is full */
    int arrays = 0, used = most;
    for (int k = a; k < b; k++) {
      const proto *p = &r->protos[need[k].proto];
      for (int i = 0; i < p->ninsts; i++) {
        if (used + p->layers > most)
          arrays++, used = 0;
        used += p->layers;
      }
    }
    GLuint *grown = realloc(r->map_arrays, (size_t)(r->n_map_arrays + arrays) *
                                               sizeof *r->map_arrays);
    if (!grown) {
      st = satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
      break;
    }
    r->map_arrays = grown;
    GLuint *tex = r->map_arrays + r->n_map_arrays;
    glGenTextures(arrays, tex);
    r->n_map_arrays += arrays;
    int at = -1;
    used = most;
    for (int k = a; k < b; k++) {
      proto *p = &r->protos[need[k].proto];
      for (int i = 0; i < p->ninsts; i++) {
        if (used + p->layers > most) { /* the array before is full */
          if (at >= 0)
            map_array_storage(r, tex[at], &need[a], used);
          at++, used = 0;
        }
        inst *in = &r->insts[p->first_inst + i];
        in->tex = tex[at];
        in->layer0 = used;
        used += p->layers;
      }
      p->textured = 1;
    }
    map_array_storage(r, tex[at], &need[a], used);
    a = b;
  }
  free(need);
  if (st == SATF_OK)
    st = order_by_texture(r, err);
  return st == SATF_OK ? satf_gl_check("map textures", err) : st;
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
  in->angles = malloc(sectors * 2 * sizeof(float));
  in->looked_up = malloc(sectors * 2 * sizeof(float));
  if (!in->angles || !in->looked_up)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  cluster_cpu_forget_lookups(in);
  r->stats.clusters++;
  r->stats.layers += p->layers;
  r->stats.hsvs += (long)satf_shell_hsv_count(&p->geom.shell);
  return SATF_OK;
}

satf_status hierarchy_build(satf_renderer *r, satf_progress_fn progress,
                            void *progress_ctx, satf_error *err) {
  const satf_scene *scene = r->scene;
  r->nprotos = scene->n_macro_clusters;
  r->protos = calloc((size_t)r->nprotos, sizeof(proto));
  r->ninsts = (int)satf_scene_cluster_count(scene);
  r->insts = calloc((size_t)r->ninsts, sizeof(inst));
  if (!r->protos || !r->insts)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  r->stats.macro_clusters = r->nprotos;
  /* the hair's own strands: a tracks density's member strands, not the
   * strand count its look-ups assume (1,000 unless the scene says) */
  r->stats.strands = (long)satf_scene_strand_count(scene);
  int ii = 0;
  satf_status st = SATF_OK;
  for (int m = 0; m < r->nprotos && st == SATF_OK; m++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    st = build_proto(r, m, mc, err);
    r->protos[m].first_inst = ii;
    r->protos[m].ninsts = mc->n_instances;
    for (int i = 0; i < mc->n_instances && st == SATF_OK; i++)
      st = build_inst(r, &r->insts[ii++], m, &mc->instances[i], err);
    if (st == SATF_OK && !r->protos[m].sparse)
      st = prepare_proto(r, m, err);
    r->stats.prototypes_shared += mc->n_instances - 1;
    if (progress) /* clusters built so far: the set-up's bulk */
      progress(progress_ctx, (size_t)ii, (size_t)r->ninsts);
  }
  return st == SATF_OK ? map_textures_create(r, err) : st;
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

satf_status hierarchy_check(const satf_renderer *r, const satf_scene *scene,
                            satf_error *err) {
  if (scene->n_macro_clusters != r->nprotos)
    return satf_error_set(
        err, SATF_ERR_ARGUMENT, "%s: %d macro-clusters, the renderer has %d",
        scene_name(scene), scene->n_macro_clusters, r->nprotos);
  for (int m = 0; m < r->nprotos; m++) {
    const satf_scene_macro_cluster *a = &r->scene->macro_clusters[m];
    const satf_scene_macro_cluster *b = &scene->macro_clusters[m];
    if (a->n_instances != b->n_instances ||
        memcmp(&a->prototype.shell, &b->prototype.shell,
               sizeof a->prototype.shell))
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "%s: macro_clusters[%d] changed its instances or "
                            "shells; only geometry and transforms can animate",
                            scene_name(scene), m);
  }
  return SATF_OK;
}

/* Rebuilds prototype m's geometry for a changed cluster; the density, in
 * the cluster's own frame, stays. */
static satf_status rebuild_proto(satf_renderer *r, int m,
                                 const satf_scene_cluster *c, satf_error *err) {
  proto *p = &r->protos[m];
  float *features = p->geom.features;
  satf_neighbor_cache *nb = p->geom.neighbors;
  p->geom.features = NULL;
  p->geom.neighbors = NULL;
  release_geometry(p);
  satf_status st = build_geometry(r, m, c, features, err);
  free(features);
  if (st == SATF_OK)
    p->geom.neighbors = nb;
  else
    satf_neighbor_cache_free(nb);
  /* drawn as a cluster: the directions of its new course. They refine
   * the shading only; one that cannot be made (out of memory) leaves the
   * trajectory's, and the geometry the instances are about to be placed
   * on stays whole (an error here would leave them on the freed one) */
  if (st == SATF_OK && p->ready) {
    satf_error cerr;
    (void)proto_hair(r, p, &c->density, &cerr);
  }
  return st;
}

satf_status hierarchy_update(satf_renderer *r, const satf_scene *scene,
                             int *moved, satf_error *err) {
  satf_status st = SATF_OK;
  const satf_scene *old = r->scene;
  r->scene = scene;
  int ii = 0;
  for (int m = 0; m < r->nprotos && st == SATF_OK; m++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    int changed = !cluster_geometry_equal(&old->macro_clusters[m].prototype,
                                          &mc->prototype);
    if (changed) {
      st = rebuild_proto(r, m, &mc->prototype, err);
      (*moved)++;
    }
    for (int i = 0; i < mc->n_instances && st == SATF_OK; i++, ii++) {
      inst *in = &r->insts[ii];
      if (changed || memcmp(in->m, mc->instances[i].m, sizeof in->m)) {
        memcpy(in->m, mc->instances[i].m, sizeof in->m);
        st = place_inst(r, in, err);
      }
    }
  }
  return st;
}

void hierarchy_release(satf_renderer *r) {
  for (int i = 0; r->insts && i < r->ninsts; i++) {
    inst *in = &r->insts[i];
    if (in->own_features)
      free(in->geom.features);
    satf_neighbor_cache_free(in->own_neighbors);
    free(in->angles);
    free(in->looked_up);
    free(in->texels);
  }
  for (int m = 0; r->protos && m < r->nprotos; m++) {
    proto *p = &r->protos[m];
    release_geometry(p);
    satf_shell_geom_destroy(&p->geom);
    satf_strands_destroy(p->strands);
    satf_vdb_grid_destroy(p->vdb);
  }
  if (r->n_map_arrays > 0)
    glDeleteTextures(r->n_map_arrays, r->map_arrays);
  free(r->map_arrays);
  free(r->tex_order);
  free(r->protos);
  free(r->insts);
}

/* The mean over the procedural densities of strand_width x the
 * prototype's radius at its root. */
float hierarchy_density_width(const satf_renderer *r) {
  double sum = 0.0;
  int n = 0;
  for (int m = 0; m < r->nprotos; m++) {
    const satf_scene_cluster *c = &r->scene->macro_clusters[m].prototype;
    if (c->density.type != SATF_SCENE_DENSITY_PROCEDURAL ||
        !(c->density.strand_width > 0.0f))
      continue;
    sum += (double)c->density.strand_width * c->a.values[0];
    n++;
  }
  return n > 0 ? (float)(sum / n) : 0.0f;
}

float hierarchy_hair_width(const satf_renderer *r) {
  float w = strands_gpu_width(r->sparse);
  return w > 0.0f ? w : hierarchy_density_width(r);
}

/* A shell cluster puts its whole alpha (every layer's, both faces) into
 * the slab of its outer shell's depth (glsl/dom_fs.glsl), so the slab must
 * be of the shells' scale: on the imported shared ponytail, 3,333 of its
 * 3,567 prototypes are single strands drawn as strands, radius 0.09 at
 * the median, which made the slab a third of 0.29 (or a hair's width,
 * dom_place's floor) where its 234 shell clusters average 3.1: their inner
 * layers took the optical depth of the whole cluster (which their records
 * and s-maps already shadow), in dark blotches over the crown. */
float hierarchy_shell_radius(const satf_renderer *r, int *shells) {
  float sum = 0.0f;
  int n = 0;
  for (int m = 0; m < r->nprotos; m++)
    if (!r->protos[m].sparse) {
      sum += r->scene->macro_clusters[m].prototype.a.values[0];
      n++;
    }
  if (shells)
    *shells = n;
  if (n == 0)
    return dom_cluster_radius(r->scene, r->nprotos);
  float c[3], floor_r = SHELL_RADIUS_FLOOR * view_radius(&r->view, c);
  float mean = sum / (float)n;
  return mean > floor_r ? mean : floor_r;
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

int *hierarchy_far_to_near(const satf_renderer *r, const float eye[3]) {
  depth_key *keys = malloc((size_t)r->ninsts * sizeof *keys);
  int *order = malloc((size_t)r->ninsts * sizeof *order);
  if (!keys || !order) {
    free(keys);
    free(order);
    return NULL;
  }
  for (int i = 0; i < r->ninsts; i++) {
    const float *c = r->insts[i].centre;
    float d[3] = {c[0] - eye[0], c[1] - eye[1], c[2] - eye[2]};
    keys[i].d2 = satf_dot3f(d, d);
    memcpy(keys[i].centre, c, sizeof keys[i].centre);
    keys[i].index = i;
  }
  qsort(keys, (size_t)r->ninsts, sizeof *keys, farther_first);
  for (int i = 0; i < r->ninsts; i++)
    order[i] = keys[i].index;
  free(keys);
  return order;
}
