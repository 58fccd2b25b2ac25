/* passes.c - owns the renderer's GPU passes (SATF Table 1: L, S): the deep
 * opacity map from the key light, the opaque meshes, the clusters' shading
 * into per-pixel fragment arrays and their sorted resolve, or the clusters
 * drawn far to near with "over" blending; and the uniforms they set. */
#include "renderer_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mat4.h"
#include "satf/math.h"

static void set_mat4(GLuint prog, const char *name, const float m[16]) {
  glUniformMatrix4fv(glGetUniformLocation(prog, name), 1, GL_TRUE, m);
}

/* Light count and colours (the directions are per program). */
static void set_light_uniforms(const satf_renderer *r, GLuint p) {
  float col[3 * SATF_SCENE_MAX_LIGHTS];
  frame_light_colors(r, col);
  glUniform1i(glGetUniformLocation(p, "u_nlights"), r->nlights);
  glUniform3fv(glGetUniformLocation(p, "u_light_color"), r->nlights, col);
}

/* The AOV and the deep opacity map on texture units 2 and 3. */
static void set_dom_uniforms(const satf_renderer *r, GLuint p, satf_aov aov) {
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
}

/* Per-draw uniform locations of a layer program. */
enum {
  LOC_ST,
  LOC_MAP_WIDTH,
  LOC_LAYERS,
  LOC_CORE,
  LOC_FIRST,
  LOC_FIRST_LAYER,
  LOC_INST_LAYERS,
  LOC_COUNT
};

/* Sets the per-pass uniforms of a layer program and binds the instances'
 * data (frame_instance_data); returns its per-draw uniform locations. */
static void use_layer_program(const satf_renderer *r, GLuint prog,
                              const float viewproj[16], GLint loc[LOC_COUNT]) {
  glUseProgram(prog);
  set_mat4(prog, "u_viewproj", viewproj);
  glUniform1i(glGetUniformLocation(prog, "u_maps"), 0);
  static const char *const names[LOC_COUNT] = {
      "u_st",    "u_map_width",   "u_layers",     "u_core",
      "u_first", "u_first_layer", "u_inst_layers"};
  for (int k = 0; k < LOC_COUNT; k++)
    loc[k] = glGetUniformLocation(prog, names[k]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, r->inst_models);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, r->inst_shading);
  glActiveTexture(GL_TEXTURE0);
}

/* Draws instances first .. first + count - 1 of one prototype, which share
 * a map texture and a winding (cluster_vs.glsl takes each one's transform,
 * eye and lights from the instance buffers and its maps from its layers of
 * the texture): one draw call for all of them. */
static void draw_run(const satf_renderer *r, int first, int count,
                     const GLint loc[LOC_COUNT], int coarse) {
  const inst *in = &r->insts[first];
  const proto *p = &r->protos[in->proto];
  const satf_shell_params *sh = &in->geom.shell;
  glUniform1i(loc[LOC_ST], sh->st);
  glUniform1i(loc[LOC_MAP_WIDTH], sh->su * r->w);
  glUniform1i(loc[LOC_LAYERS], sh->layers);
  glUniform1f(loc[LOC_CORE], sh->core);
  glUniform1i(loc[LOC_FIRST], first);
  glUniform1i(loc[LOC_FIRST_LAYER], in->layer0);
  glUniform1i(loc[LOC_INST_LAYERS], sh->layers);
  glBindTexture(GL_TEXTURE_2D_ARRAY, in->tex);
  /* the proxy's outward faces wind counter-clockwise, clockwise once a
   * mirror has turned them (culling keeps the outward ones) */
  glFrontFace(in->mirrored ? GL_CW : GL_CCW);
  glBindVertexArray(p->proxy_vao);
  /* the light passes' coarse proxy, else the instance's (lod.c) */
  int q = coarse ? LOD_PROXY_DOM : in->lod_proxy;
  glDrawElementsInstanced(GL_TRIANGLES, p->lod_count[q], GL_UNSIGNED_INT,
                          (void *)((size_t)p->lod_first[q] * sizeof(uint32_t)),
                          count);
}

/* The outermost shell of every cluster: each fragment accounts for all the
 * shells behind it (glsl/shade_fs.glsl). Instances of a prototype in one
 * texture array and of one winding go in one draw (SATF's macro-clusters:
 * thousands of clusters, a handful of calls); with r->instanced 0 one draw
 * per instance, in list order. */
static void draw_clusters(const satf_renderer *r, GLuint prog,
                          const float viewproj[16], int coarse) {
  GLint loc[LOC_COUNT];
  use_layer_program(r, prog, viewproj, loc);
  for (int i = 0; i < r->ninsts;) {
    const inst *in = &r->insts[i];
    int n = 1;
    if (r->protos[in->proto].sparse) { /* drawn as strands (sparse.c) */
      i++;
      continue;
    }
    while (r->instanced && i + n < r->ninsts &&
           r->insts[i + n].proto == in->proto &&
           r->insts[i + n].tex == in->tex &&
           r->insts[i + n].mirrored == in->mirrored &&
           (coarse || r->insts[i + n].lod_proxy == in->lod_proxy))
      n++;
    draw_run(r, i, n, loc, coarse);
    i += n;
  }
  glBindVertexArray(0);
  glFrontFace(GL_CCW);
}

/* The opaque meshes with `prog` (per-mesh model and normal matrices). */
void draw_meshes(const satf_renderer *r, GLuint prog,
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

void passes_fullscreen(const satf_renderer *r) {
  glBindVertexArray(r->empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}

void passes_dom_uniforms(const satf_renderer *r, GLuint prog) {
  glUseProgram(prog);
  glUniform1i(glGetUniformLocation(prog, "u_dom_depth"), 1);
  glUniform1f(glGetUniformLocation(prog, "u_dom_slab"), r->dom_slab);
}

void passes_dom_with(satf_renderer *r, passes_dom_hair_fn hair, void *ctx) {
  frame_light_view(r);
  r->dom_valid = 0; /* whoever drew it, the clusters' map is gone */
  satf_gl_target_bind(r->dom_depth);
  glClearColor(0, 0, 0, 0);
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT); /* its colour is never written */
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  hair(r, ctx, 0);
  draw_meshes(r, r->prog_mesh_depth, r->light_viewproj);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDisable(GL_DEPTH_TEST);

  satf_gl_target_bind(r->dom_opacity);
  glClear(GL_COLOR_BUFFER_BIT);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, satf_gl_target_depth_texture(r->dom_depth));
  hair(r, ctx, 1);
  if (r->nmeshes > 0) {
    passes_dom_uniforms(r, r->prog_mesh_dom);
    draw_meshes(r, r->prog_mesh_dom, r->light_viewproj);
  }
  glDisable(GL_BLEND);
}

/* The clusters' outermost shells, coarse: their depth, or their alpha
 * summed into the slabs (glsl/dom_fs.glsl). Every face, both passes:
 * drawing only the faces towards the light would halve the fragments, but
 * the proxies are open at their ends (the first hair's depth changed by
 * 9% of what the cluster shadows change on test_perf_paths' scene) and the
 * light crosses the shell twice (the near face's alpha weighted twice put
 * the far face's opacity in the near face's slab: 26%). */
static void dom_clusters(satf_renderer *r, void *ctx, int opacity) {
  (void)ctx;
  if (opacity)
    passes_dom_uniforms(r, r->prog_dom);
  draw_clusters(r, opacity ? r->prog_dom : r->prog_depth, r->light_viewproj, 1);
  sparse_dom(r, opacity);
}

/* The largest angle, seen from any cluster drawn with maps, between the
 * eye now and the eye the deep opacity map was drawn for. */
static float dom_eye_turn(const satf_renderer *r) {
  float most = 0.0f;
  for (int i = 0; i < r->ninsts; i++) {
    const inst *in = &r->insts[i];
    if (r->protos[in->proto].sparse)
      continue;
    float a[3], b[3];
    for (int k = 0; k < 3; k++) {
      a[k] = r->camera.position[k] - in->centre[k];
      b[k] = r->dom_eye[k] - in->centre[k];
    }
    if (!(satf_normalize3f(a) > 0.0f && satf_normalize3f(b) > 0.0f))
      return INFINITY; /* an eye at the cluster: any azimuth */
    float c = satf_dot3f(a, b);
    float angle = acosf(c < -1.0f ? -1.0f : c > 1.0f ? 1.0f : c);
    most = angle > most ? angle : most;
  }
  return most;
}

/* Each cluster's control points in world space and its radius there (the
 * larger of A and B at the point, times the transform's longest axis), 4
 * floats a point into out (NULL: only counted); the count, -1 without
 * memory. The twist is left out: it turns a cross-section about its
 * centre, which moves the cluster's outline by less than A - B. */
static int dom_hair_points(const satf_renderer *r, float *out) {
  int n = 0;
  for (int i = 0; i < r->ninsts; i++) {
    const inst *in = &r->insts[i];
    const satf_scene_cluster *c =
        &r->scene->macro_clusters[in->proto].prototype;
    int np = c->n_points;
    if (!out) {
      n += np;
      continue;
    }
    float *ab = malloc(2 * (size_t)np * sizeof(float)), scale = 0.0f;
    if (!ab)
      return -1;
    hierarchy_resample_curve(&c->a, np, ab);
    hierarchy_resample_curve(&c->b, np, ab + np);
    for (int k = 0; k < 3; k++) {
      float axis[3] = {in->m[k], in->m[4 + k], in->m[8 + k]};
      float len = sqrtf(satf_dot3f(axis, axis));
      scale = len > scale ? len : scale;
    }
    for (int j = 0; j < np; j++, n++) {
      float *o = out + 4 * (size_t)n;
      satf_mat4_point(in->m, c->trajectory + 3 * j, o);
      o[3] = scale * (ab[j] > ab[np + j] ? ab[j] : ab[np + j]);
    }
    free(ab);
  }
  return n;
}

float passes_dom_hair_move(const satf_renderer *r) {
  int n = dom_hair_points(r, NULL);
  if (!r->dom_valid || n != r->dom_npoints)
    return INFINITY;
  float *now = malloc(4 * (size_t)(n > 0 ? n : 1) * sizeof(float));
  if (!now || dom_hair_points(r, now) != n) {
    free(now);
    return INFINITY;
  }
  /* in the map's own light view (orthographic: x, y in [-1, 1] across
   * DOM_SIZE texels, window depth z / 2 + 1 / 2 in slabs of
   * dom_light_slab) */
  const float *m = r->dom_viewproj;
  float row[3] = {m[0], m[1], m[2]};
  float texels = 0.5f * (float)DOM_SIZE;
  float radius_texels = sqrtf(satf_dot3f(row, row)) * texels;
  float most = 0.0f;
  for (int i = 0; i < n; i++) {
    const float *a = r->dom_points + 4 * (size_t)i, *b = now + 4 * (size_t)i;
    float pa[3], pb[3];
    satf_mat4_point(m, a, pa);
    satf_mat4_point(m, b, pb);
    float dx = fabsf(pb[0] - pa[0]), dy = fabsf(pb[1] - pa[1]);
    float across =
        (dx > dy ? dx : dy) * texels + fabsf(b[3] - a[3]) * radius_texels;
    float along = 0.5f * fabsf(pb[2] - pa[2]) / r->dom_light_slab;
    float move = across > along ? across : along;
    most = move > most ? move : most;
  }
  free(now);
  return most;
}

/* Whether the map drawn last still stands for this frame: the eye rule
 * below, and the light and the hair. The exact rule (r->dom_move_tol < 0):
 * the light's view and slabs are those it was drawn with and the hair has
 * not moved (satf_renderer_set_scene clears dom_valid). Else the key light
 * is the same and no cluster moved more than r->dom_move_tol texels or
 * slabs since; the map keeps the view it was drawn with (the scene bounds
 * follow the hair, and with them the exact rule's view). */
static int dom_keep(satf_renderer *r) {
  if (!r->dom_valid ||
      (r->dom_maps_stale && !(dom_eye_turn(r) < r->dom_eye_tol)))
    return 0;
  if (r->dom_move_tol < 0.0f)
    return !memcmp(r->dom_viewproj, r->light_viewproj,
                   sizeof r->dom_viewproj) &&
           r->dom_light_slab == r->dom_slab;
  float lv[4];
  frame_light_vector(&r->lights[0], lv);
  if (memcmp(lv, r->dom_light, sizeof lv) ||
      !(passes_dom_hair_move(r) <= r->dom_move_tol))
    return 0;
  memcpy(r->light_viewproj, r->dom_viewproj, sizeof r->dom_viewproj);
  r->dom_slab = r->dom_light_slab;
  return 1;
}

/* Deep opacity map (Yuksel & Keyser 2008) from the key light (frame.c
 * places it): the first hair's depth, then optical depth summed into four
 * slabs behind it. */
void passes_dom(satf_renderer *r) {
  /* the map reads the light's view, the hair's transforms and shells and
   * the maps' alpha (and the meshes): while none has changed since it was
   * drawn it is what drawing it again would give. The alpha follows the
   * eye's azimuth (the records are looked up for the eye), but the map
   * wants the opacity the light sees, for which the alpha seen from one
   * eye stands in no better than from another: the map is kept while the
   * eye turns by less than r->dom_eye_tol from where it was drawn
   * (measured with bench_dom, a map kept from an eye turned 5 to 180
   * degrees: SSIM >= 0.994 and mean |luminance change| <= 0.0025 on every
   * sample, the imported ponytail and 40K-strand fur; the most, fur at 90
   * degrees, is 11% of what the cluster shadows change there).
   * Moving hair: the map is kept while no control point moved more than
   * r->dom_move_tol (DOM_MOVE_TOL: a texel, the percentage-closer filter's
   * own reach, glsl/dom_lookup.glsl) from where it was drawn. anim_8's
   * hair moves 1.7-2.9 texels a frame: kept every other frame with 3, S
   * halves, but the shadow edges lag by a frame (SSIM >= 0.966, mean
   * |luminance change| <= 7.9% of the cluster shadows'; bench_dom --anim,
   * README), so the default keeps only hair that (nearly) stands still */
  frame_light_view(r);
  if (dom_keep(r)) {
    r->dom_reuses++;
    return;
  }
  passes_dom_with(r, dom_clusters, NULL);
  memcpy(r->dom_viewproj, r->light_viewproj, sizeof r->dom_viewproj);
  memcpy(r->dom_eye, r->camera.position, sizeof r->dom_eye);
  frame_light_vector(&r->lights[0], r->dom_light);
  r->dom_light_slab = r->dom_slab;
  r->dom_maps_stale = 0;
  int n = dom_hair_points(r, NULL);
  float *pts =
      realloc(r->dom_points, 4 * (size_t)(n > 0 ? n : 1) * sizeof(float));
  if (pts) {
    r->dom_points = pts;
    r->dom_npoints = dom_hair_points(r, pts);
  } else {
    r->dom_npoints = -1; /* not measured: drawn again next frame */
  }
  r->dom_valid = 1;
}

/* Material, effects and lights of a shading program. */
void set_shading_uniforms(const satf_renderer *r, GLuint p, satf_aov aov) {
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
  glUniform1i(glGetUniformLocation(p, "u_slots"), r->slots);
  if (r->fgpu) /* the physical mode's fibre (glsl/fiber.glsl) */
    fiber_gpu_bind(r->fgpu, m, p);
  set_dom_uniforms(r, p, aov);
}

void passes_world_lights(const satf_renderer *r, GLuint p) {
  float vec[4 * SATF_SCENE_MAX_LIGHTS];
  for (int k = 0; k < r->nlights; k++)
    frame_light_vector(&r->lights[k], vec + 4 * k);
  glUniform4fv(glGetUniformLocation(p, "u_light_vec"), r->nlights, vec);
  glUniform3fv(glGetUniformLocation(p, "u_eye"), 1, r->camera.position);
}

/* Clears the frame to transparent black (every pass is premultiplied over
 * it; the background is composited by whoever shows the image) and draws
 * the opaque meshes, leaving their depth for the hair to test against. */
void begin_frame(const satf_renderer *r, satf_aov aov,
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
  passes_world_lights(r, p);
  set_light_uniforms(r, p);
  set_dom_uniforms(r, p, aov);
  glActiveTexture(GL_TEXTURE0);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  draw_meshes(r, p, viewproj);
  glDisable(GL_DEPTH_TEST);
}

/* Hair tests against the meshes' depth without writing it. */
void hair_depth_test(int on) {
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

/* Every cluster's fragments into the per-pixel arrays (mode: u_list_mode
 * of glsl/shade_fs.glsl). */
static void fill_lists(const satf_renderer *r, satf_aov aov,
                       const float viewproj[16], int mode, int opaque) {
  GLuint zero = 0, empty = 0xFFFFFFFFu;
  if (mode == 0) /* the nearest passes redo only pixels it overflowed */
    glClearTexImage(r->counts_tex, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glBindImageTexture(0, r->counts_tex, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
  glBindImageTexture(1, r->frags_tex, 0, GL_TRUE, 0, GL_READ_WRITE,
                     GL_RGBA32UI);
  if (mode == 1) /* no key yet: every slot farther than any fragment */
    glClearTexImage(r->keys_tex, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &empty);
  if (mode > 0)
    glBindImageTexture(2, r->keys_tex, 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
  glBindFramebuffer(GL_FRAMEBUFFER, r->list_fbo);
  glViewport(0, 0, r->width, r->height);
  hair_depth_test(r->nmeshes > 0 || opaque);
  glDisable(GL_CULL_FACE);
  GLuint prog = r->lod ? r->prog_shade_lod : r->prog_shade;
  set_shading_uniforms(r, prog, aov);
  glUniform1i(glGetUniformLocation(prog, "u_list_mode"), mode);
  glEnable(GL_CULL_FACE); /* front faces: each traces the whole cluster */
  glCullFace(GL_BACK);
  draw_clusters(r, prog, viewproj, 0);
  glDisable(GL_CULL_FACE);
  sparse_lists(r, aov, viewproj, mode); /* their strands, sorted with them */
  hair_depth_test(0);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                  GL_TEXTURE_FETCH_BARRIER_BIT);
}

/* The arrays sorted and composited (SATF eq. 14) over the frame. */
static void resolve_lists(const satf_renderer *r, const float viewproj[16]) {
  satf_gl_target_bind(r->out);
  glEnable(GL_BLEND); /* the hair's composite over background and meshes */
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  /* only pixels the hair can cover need resolving */
  int box[4];
  frame_screen_box(r, viewproj, box);
  glEnable(GL_SCISSOR_TEST);
  glScissor(box[0], box[1], box[2], box[3]);
  glUseProgram(r->prog_resolve);
  glUniform1i(glGetUniformLocation(r->prog_resolve, "u_slots"), r->slots);
  passes_fullscreen(r);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
}

GLuint passes_lists(satf_renderer *r, satf_aov aov, const float viewproj[16],
                    int nearest, long *fragments, long *overflow) {
  begin_frame(r, aov, viewproj);
  /* the strands' opaque fragments first: behind them nothing is stored
   * (the ponytail drawn as its strands: 4.2 fragments a pixel, the
   * crown's overflowing the arrays) */
  glBindFramebuffer(GL_FRAMEBUFFER, r->list_fbo);
  glViewport(0, 0, r->width, r->height);
  int opaque = sparse_opaque_depth(r, viewproj);
  /* nearest: a first pass finds each pixel's r->slots nearest depths (an
   * arrival-order-free k-buffer), the second stores only fragments no
   * farther than the last of them; both only inside the box of the pixels
   * the plain pass overflowed (the ponytail's ribbons cost their
   * rasterising there, not their shading) */
  if (nearest) {
    const int *b = r->overflow_box;
    glEnable(GL_SCISSOR_TEST);
    glScissor(b[0], b[1], b[2], b[3]);
    fill_lists(r, aov, viewproj, 1, opaque);
    fill_lists(r, aov, viewproj, 2, opaque);
    glDisable(GL_SCISSOR_TEST);
  } else {
    fill_lists(r, aov, viewproj, 0, opaque);
  }
  resolve_lists(r, viewproj);
  /* the deepest pixel decides whether the arrays were large enough */
  size_t n = (size_t)r->width * (size_t)r->height;
  GLuint *counts = malloc(n * sizeof(GLuint)), most = 0;
  *fragments = 0;
  *overflow = 0;
  int box[4] = {0, 0, r->width, r->height}; /* x0, y0, x1, y1 */
  if (counts) {
    glBindTexture(GL_TEXTURE_2D, r->counts_tex);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, counts);
    box[0] = r->width, box[1] = r->height, box[2] = box[3] = 0;
    for (size_t i = 0; i < n; i++) {
      most = counts[i] > most ? counts[i] : most;
      *fragments += counts[i] < (GLuint)r->slots ? counts[i] : (GLuint)r->slots;
      if (counts[i] <= (GLuint)r->slots)
        continue;
      ++*overflow;
      int x = (int)(i % (size_t)r->width), y = (int)(i / (size_t)r->width);
      box[0] = x < box[0] ? x : box[0], box[1] = y < box[1] ? y : box[1];
      box[2] = x + 1 > box[2] ? x + 1 : box[2];
      box[3] = y + 1 > box[3] ? y + 1 : box[3];
    }
    free(counts);
  }
  if (!nearest) { /* the counts are the plain pass's in both */
    r->overflow_box[0] = box[0], r->overflow_box[1] = box[1];
    r->overflow_box[2] = box[2] > box[0] ? box[2] - box[0] : 0;
    r->overflow_box[3] = box[3] > box[1] ? box[3] - box[1] : 0;
  }
  return most;
}

/* SATF eq. 14 by drawing order (see satf_composite in satf/render.h). */
satf_status passes_ordered(satf_renderer *r, satf_aov aov,
                           const float viewproj[16], satf_error *err) {
  int *order = frame_far_to_near(r);
  if (!order)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  begin_frame(r, aov, viewproj);
  hair_depth_test(r->nmeshes > 0);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); /* premultiplied "over" */
  glEnable(GL_CULL_FACE);
  GLuint prog = r->lod ? r->prog_shade_ordered_lod : r->prog_shade_ordered;
  sparse_ordered_begin(r, aov, viewproj);
  set_shading_uniforms(r, prog, aov);
  GLint loc[LOC_COUNT];
  use_layer_program(r, prog, viewproj, loc);
  glCullFace(GL_BACK);
  for (int q = 0; q < r->ninsts; q++) { /* the order forbids batching */
    if (sparse_ordered(r, order[q])) {  /* its strands */
      glUseProgram(prog); /* the two programs share units and buffers */
      continue;
    }
    glEnable(GL_CULL_FACE);
    draw_run(r, order[q], 1, loc, 0);
  }
  glBindVertexArray(0);
  glFrontFace(GL_CCW);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  hair_depth_test(0);
  free(order);
  return SATF_OK;
}
