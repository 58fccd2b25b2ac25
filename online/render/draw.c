/* draw.c - owns what every drawing path's GPU passes share (draw.h): the
 * frame's start with the lit opaque meshes, the shading programs'
 * uniforms, the hair's depth test and the full-screen triangle. */
#include "draw.h"

#include <string.h>

#include "fiber_gpu.h"
#include "renderer_internal.h"

void draw_set_mat4(GLuint prog, const char *name, const float m[16]) {
  glUniformMatrix4fv(glGetUniformLocation(prog, name), 1, GL_TRUE, m);
}

/* Light count and colours (the directions are per program). */
static void set_light_uniforms(const satf_renderer *r, GLuint p) {
  float col[3 * SATF_SCENE_MAX_LIGHTS];
  view_light_colors(&r->view, col);
  glUniform1i(glGetUniformLocation(p, "u_nlights"), r->view.nlights);
  glUniform3fv(glGetUniformLocation(p, "u_light_color"), r->view.nlights, col);
}

/* The fill light's deep opacity map on texture units 4 (the first and
 * last hair's depths) and 5 (the slabs) for the
 * programs that read it (u_fill_shadow 0: it is not drawn, and the key's
 * textures stand on those units so that every sampler has one). */
static void set_fill_uniforms(const satf_renderer *r, GLuint p) {
  int on = draw_fill_shadows(r);
  const dom_map *d = on ? &r->fill_dom : &r->dom;
  glUniform1i(glGetUniformLocation(p, "u_fill_shadow"), on);
  glUniform1f(glGetUniformLocation(p, "u_fill_slab"), d->slab);
  draw_set_mat4(p, "u_fill_viewproj", d->viewproj);
  glActiveTexture(GL_TEXTURE4);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_color_texture(d->opacity, 1));
  glUniform1i(glGetUniformLocation(p, "u_fill_depth"), 4);
  glActiveTexture(GL_TEXTURE5);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_color_texture(d->opacity, 0));
  glUniform1i(glGetUniformLocation(p, "u_fill_opacity"), 5);
}

/* The AOV and the deep opacity maps: the key light's on texture units 2
 * (the first and last hair's depths) and 3 (the slabs), the fill light's
 * on 4 and 5. */
static void set_dom_uniforms(const satf_renderer *r, GLuint p, satf_aov aov) {
  glUniform1i(glGetUniformLocation(p, "u_cluster_shadow"),
              r->effects.cluster_shadows);
  glUniform1i(glGetUniformLocation(p, "u_aov"), (int)aov);
  glUniform1f(glGetUniformLocation(p, "u_kcluster"), 1.0f);
  glUniform1f(glGetUniformLocation(p, "u_dom_slab"), r->dom.slab);
  draw_set_mat4(p, "u_light_viewproj", r->dom.viewproj);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_color_texture(r->dom.opacity, 1));
  glUniform1i(glGetUniformLocation(p, "u_dom_depth"), 2);
  glActiveTexture(GL_TEXTURE3);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_color_texture(r->dom.opacity, 0));
  glUniform1i(glGetUniformLocation(p, "u_dom_opacity"), 3);
  set_fill_uniforms(r, p);
}

void draw_meshes(const satf_renderer *r, GLuint prog,
                 const float viewproj[16]) {
  glUseProgram(prog);
  draw_set_mat4(prog, "u_viewproj", viewproj);
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

void draw_shading_uniforms(const satf_renderer *r, GLuint p, satf_aov aov) {
  const satf_scene_material *m = &r->scene->material;
  glUseProgram(p);
  set_light_uniforms(r, p);
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
  glUniform1i(glGetUniformLocation(p, "u_slots"), r->lists.slots);
  if (r->fgpu) /* the physical mode's fibre (glsl/fiber.glsl) */
    fiber_gpu_bind(r->fgpu, m, p);
  set_dom_uniforms(r, p, aov);
}

void draw_world_lights(const satf_renderer *r, GLuint p) {
  float vec[4 * SATF_SCENE_MAX_LIGHTS];
  for (int k = 0; k < r->view.nlights; k++)
    view_light_vector(&r->view.lights[k], vec + 4 * k);
  glUniform4fv(glGetUniformLocation(p, "u_light_vec"), r->view.nlights, vec);
  glUniform3fv(glGetUniformLocation(p, "u_eye"), 1, r->view.camera.position);
}

void draw_depth_row(const satf_renderer *r, GLuint p) {
  float look[16], proj[16];
  view_matrices(&r->view, look, proj);
  /* the camera looks down its -Z */
  float row[4] = {-look[8], -look[9], -look[10], -look[11]};
  glUniform4fv(glGetUniformLocation(p, "u_depth_row"), 1, row);
}

void draw_begin_frame(const satf_renderer *r, satf_aov aov,
                      const float viewproj[16]) {
  satf_gl_target_bind(r->out);
  glClearColor(0, 0, 0, 0);
  glClearDepth(1.0);
  glDepthMask(GL_TRUE);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (r->nmeshes == 0)
    return;
  GLuint p = r->prog_mesh;
  glUseProgram(p);
  draw_world_lights(r, p);
  set_light_uniforms(r, p);
  set_dom_uniforms(r, p, aov);
  draw_depth_row(r, p);
  glActiveTexture(GL_TEXTURE0);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  draw_meshes(r, p, viewproj);
  glDisable(GL_DEPTH_TEST);
}

void draw_hair_depth_test(int on) {
  if (on) {
    glEnable(GL_DEPTH_TEST);
    /* LEQUAL: a strand's whole fragment passes at the depth its opaque
     * pre-pass wrote (sparse_opaque_depth) */
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
  } else {
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
  }
}

int draw_fill_shadows(const satf_renderer *r) {
  return r->scene->material.model == SATF_MATERIAL_PHYSICAL &&
         r->fill_dom.depth && r->view.nlights > 1 && r->effects.cluster_shadows;
}

/* r->dom drawn by `hair` (ctx), or kept where that hair drew it last at
 * the place dom_place gives now (draw_dom_lights) */
static void draw_or_keep(satf_renderer *r, float cluster_r, float hair_width,
                         dom_hair_fn hair, void *ctx) {
  dom_map *d = &r->dom;
  dom_place(d, &r->view, cluster_r, hair_width);
  if (d->valid && d->drawn_hair == hair && d->drawn_ctx == ctx &&
      !memcmp(d->drawn_viewproj, d->viewproj, sizeof d->viewproj) &&
      d->drawn_slab == d->slab) {
    d->reuses++;
    return;
  }
  draw_dom(r, cluster_r, hair_width, hair, ctx);
  dom_mark_drawn(d, hair, ctx);
}

void draw_dom_lights(satf_renderer *r, float cluster_r, float hair_width,
                     dom_hair_fn hair, void *ctx) {
  draw_or_keep(r, cluster_r, hair_width, hair, ctx);
  if (!draw_fill_shadows(r))
    return;
  dom_swap(&r->dom, &r->fill_dom);
  draw_or_keep(r, cluster_r, hair_width, hair, ctx);
  dom_swap(&r->dom, &r->fill_dom);
}

void draw_dom(satf_renderer *r, float cluster_r, float hair_width,
              dom_hair_fn hair, void *ctx) {
  dom_map *d = &r->dom;
  dom_place(d, &r->view, cluster_r, hair_width);
  d->valid = 0; /* whoever drew it, a kept map is gone */
  satf_gl_target_bind(d->depth);
  glClearColor(0, 0, 0, 0);
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT); /* its colour is never written */
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  hair(r, ctx, 0);
  draw_meshes(r, r->prog_mesh_depth, d->viewproj);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDisable(GL_DEPTH_TEST);

  satf_gl_target_bind(d->opacity);
  const GLfloat none[4] = {0, 0, 0, 0}, depths[4] = {-1, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, none);
  glClearBufferfv(GL_COLOR, 1, depths);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE);
  glBlendEquationi(1, GL_MAX); /* -first and last hair's depth */
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_depth_texture(d->depth));
  hair(r, ctx, 1);
  if (r->nmeshes > 0) {
    dom_uniforms(d, r->prog_mesh_dom);
    draw_meshes(r, r->prog_mesh_dom, d->viewproj);
  }
  glBlendEquation(GL_FUNC_ADD);
  glDisable(GL_BLEND);
}
