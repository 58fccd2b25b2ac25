/* resources.c - owns the renderer's GL resources that are not per cluster:
 * the shader programs, the output target (resized with the image; the
 * fragment arrays of lists.c follow it), the scene's opaque meshes and the
 * instance buffers; it creates the deep opacity map's targets (dom.c). */
#include "renderer_internal.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mat4.h"
#include "shaders.h"

static satf_status build_programs(satf_renderer *r, satf_error *err) {
  /* the light loop runs a compile-time count so it unrolls */
  char lights[64], ordered[96], lights_lod[80], ordered_lod[112];
  snprintf(lights, sizeof lights, "#define NLIGHTS %d\n#define PHYSICAL %d\n",
           r->view.nlights, r->fiber != NULL);
  snprintf(ordered, sizeof ordered, "%s#define EXACT 0\n", lights);
  /* the level of detail's shells are compiled in only where --lod is on
   * (glsl/shade_fs.glsl: llvmpipe pays for them at every layer point) */
  snprintf(lights_lod, sizeof lights_lod, "%s#define LOD 1\n", lights);
  snprintf(ordered_lod, sizeof ordered_lod, "%s#define LOD 1\n", ordered);
  strcat(lights, "#define LOD 0\n");
  strcat(ordered, "#define LOD 0\n");
  char physical[32];
  snprintf(physical, sizeof physical, "#define PHYSICAL %d\n",
           r->fiber != NULL);
  const struct {
    const char *label, *vs, *fs, *extra;
    GLuint *out;
  } progs[] = {
      {"shade", satf_glsl_cluster_vs, satf_glsl_shade_fs, lights,
       &r->prog_shade},
      {"shade (ordered)", satf_glsl_cluster_vs, satf_glsl_shade_fs, ordered,
       &r->prog_shade_ordered},
      {"shade (lod)", satf_glsl_cluster_vs, satf_glsl_shade_fs, lights_lod,
       &r->prog_shade_lod},
      {"shade (ordered, lod)", satf_glsl_cluster_vs, satf_glsl_shade_fs,
       ordered_lod, &r->prog_shade_ordered_lod},
      {"depth", satf_glsl_layer_vs, satf_glsl_depth_fs, "", &r->prog_depth},
      {"dom", satf_glsl_layer_vs, satf_glsl_dom_fs, physical, &r->prog_dom},
      {"resolve", satf_glsl_fullscreen_vs, satf_glsl_resolve_fs, "",
       &r->prog_resolve},
      {"resolve (pool)", satf_glsl_fullscreen_vs, satf_glsl_resolve_fs,
       "#define POOL 1\n", &r->prog_resolve_pool},
      {"resolve (depth)", satf_glsl_fullscreen_vs, satf_glsl_resolve_fs,
       "#define DEPTH 1\n", &r->prog_resolve_depth},
      {"display", satf_glsl_fullscreen_vs, satf_glsl_display_fs, "",
       &r->prog_display},
      {"mesh", satf_glsl_mesh_vs, satf_glsl_mesh_fs, "", &r->prog_mesh},
      {"mesh depth", satf_glsl_mesh_vs, satf_glsl_empty_fs, "",
       &r->prog_mesh_depth},
      {"mesh opacity", satf_glsl_mesh_vs, satf_glsl_dom_mesh_fs, "",
       &r->prog_mesh_dom}};
  satf_status st = SATF_OK;
  for (size_t i = 0; i < sizeof progs / sizeof *progs && st == SATF_OK; i++)
    st = shaders_program(progs[i].label, progs[i].vs, progs[i].fs,
                         progs[i].extra, progs[i].out, err);
  return st;
}

satf_status resources_alloc_screen(satf_renderer *r, satf_error *err) {
  /* half floats: what the EXR keeps, and faster to blend on llvmpipe */
  const satf_gl_format out_format = SATF_GL_RGBA16F;
  if (r->out)
    satf_gl_target_destroy(r->out);
  r->out = NULL;
  satf_status st = satf_gl_target_create(r->view.width, r->view.height, 1,
                                         &out_format, &r->out, err);
  if (st == SATF_OK)
    st = lists_attach(&r->lists, r->view.width, r->view.height,
                      satf_gl_target_depth_texture(r->out), err);
  return st;
}

/* Grows the scene bounds by a mesh's transformed bounding box, so the
 * camera and the light's map cover it. */
static void grow_bounds(satf_renderer *r, const satf_mesh *mesh,
                        const float m[16]) {
  float lo[3], hi[3];
  satf_mesh_bounds(mesh, lo, hi);
  for (int c = 0; c < 8; c++) {
    float p[3] = {c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1],
                  c & 4 ? hi[2] : lo[2]},
          w[3];
    satf_mat4_point(m, p, w);
    view_grow(&r->view, w, w);
  }
}

/* A mesh's vertices (position, normal) and triangles on the GPU. */
static void upload_mesh(mesh_gpu *g, const satf_mesh *mesh) {
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
}

/* The scene's opaque meshes (OpenMesh reads OBJ and PLY), grown into the
 * scene bounds. */
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
      return satf_error_set(err, st, "%s: meshes[%d]: %s", scene_name(scene), i,
                            merr.message);
    memcpy(g->m, sm->m, sizeof g->m);
    memcpy(g->color, sm->color, sizeof g->color);
    satf_mat4_normal_matrix(g->m, g->nmat);
    grow_bounds(r, mesh, g->m);
    upload_mesh(g, mesh);
    satf_mesh_destroy(mesh);
  }
  return satf_gl_check("meshes", err);
}

/* The instances' transforms and views for instanced draws (filled per
 * frame by cluster_cpu_instance_data). */
static satf_status alloc_instance_data(satf_renderer *r, satf_error *err) {
  size_t n = (size_t)(r->ninsts > 0 ? r->ninsts : 1);
  glGenBuffers(1, &r->inst_models);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->inst_models);
  glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(n * 16 * sizeof(float)),
               NULL, GL_DYNAMIC_DRAW);
  glGenBuffers(1, &r->inst_shading);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->inst_shading);
  glBufferData(GL_SHADER_STORAGE_BUFFER,
               (GLsizeiptr)(n * CLUSTER_VIEW_FLOATS * sizeof(float)), NULL,
               GL_DYNAMIC_DRAW);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  return satf_gl_check("instance buffers", err);
}

satf_status resources_build(satf_renderer *r, satf_error *err) {
  satf_status st = build_meshes(r, err);
  if (st == SATF_OK)
    st = build_programs(r, err);
  if (st == SATF_OK) {
    glGenVertexArrays(1, &r->empty_vao);
    st = resources_alloc_screen(r, err);
  }
  if (st == SATF_OK)
    st = dom_create(&r->dom, err);
  /* the fill light's, for the physical mode (draw_fill_shadows) */
  r->fill_dom.light_index = 1;
  if (st == SATF_OK && r->scene->material.model == SATF_MATERIAL_PHYSICAL)
    st = dom_create(&r->fill_dom, err);
  if (st == SATF_OK)
    st = alloc_instance_data(r, err);
  return st;
}

void resources_release(satf_renderer *r) {
  for (int i = 0; r->meshes && i < r->nmeshes; i++) {
    glDeleteVertexArrays(1, &r->meshes[i].vao);
    glDeleteBuffers(1, &r->meshes[i].vbo);
    glDeleteBuffers(1, &r->meshes[i].ibo);
  }
  free(r->meshes);
  GLuint progs[13] = {r->prog_shade,       r->prog_shade_ordered,
                      r->prog_shade_lod,   r->prog_shade_ordered_lod,
                      r->prog_depth,       r->prog_dom,
                      r->prog_resolve,     r->prog_display,
                      r->prog_mesh,        r->prog_mesh_depth,
                      r->prog_mesh_dom,    r->prog_resolve_depth,
                      r->prog_resolve_pool};
  for (int i = 0; i < 13; i++)
    if (progs[i])
      glDeleteProgram(progs[i]);
  if (r->empty_vao)
    glDeleteVertexArrays(1, &r->empty_vao);
  GLuint bufs[2] = {r->inst_models, r->inst_shading};
  glDeleteBuffers(2, bufs);
  lists_release(&r->lists);
  satf_gl_target_destroy(r->out);
}
