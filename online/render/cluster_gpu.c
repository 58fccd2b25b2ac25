/* cluster_gpu.c - owns the clusters' GPU drawing (SATF Table 1: L): their
 * outermost shells drawn with the layer programs (instanced per
 * prototype), their shading into the per-pixel fragment arrays and the
 * sorted resolve, or drawn far to near with "over" blending. */
#include "renderer_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "depth.h"
#include "draw.h"
#include "satf/common.h"
#include "shaders.h"

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
 * data (cluster_cpu_instance_data); returns its per-draw uniform locations. */
static void use_layer_program(const satf_renderer *r, GLuint prog,
                              const float viewproj[16], GLint loc[LOC_COUNT]) {
  glUseProgram(prog);
  draw_set_mat4(prog, "u_viewproj", viewproj);
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
 * the texture): one draw call for all of them. *bound: the map texture
 * bound, which is bound again only when it changes (NULL: always). */
static void draw_run(const satf_renderer *r, int first, int count,
                     const GLint loc[LOC_COUNT], int coarse, GLuint *bound) {
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
  if (!bound || *bound != in->tex)
    glBindTexture(GL_TEXTURE_2D_ARRAY, in->tex);
  if (bound)
    *bound = in->tex;
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
 * per instance, in list order. The shading passes draw in the order of the
 * map texture arrays (r->tex_order), so that each array is bound once
 * (hierarchy.c: map_textures_create; their fragments are sorted by depth
 * whatever order they come in); the deep opacity map's (coarse), whose
 * blending sums in drawing order, in list order. */
int cluster_gpu_draw(const satf_renderer *r, GLuint prog,
                     const float viewproj[16], int coarse) {
  GLint loc[LOC_COUNT];
  use_layer_program(r, prog, viewproj, loc);
  const int *order = !coarse && r->instanced ? r->tex_order : NULL;
  GLuint bound = 0;
  int binds = 0;
  for (int k = 0; k < r->ninsts;) {
    const int i = order ? order[k] : k;
    const inst *in = &r->insts[i];
    int n = 1;
    if (r->protos[in->proto].sparse) { /* drawn as strands (sparse.c) */
      k++;
      continue;
    }
    while (r->instanced && k + n < r->ninsts &&
           (order ? order[k + n] : k + n) == i + n &&
           r->insts[i + n].proto == in->proto &&
           r->insts[i + n].tex == in->tex &&
           r->insts[i + n].mirrored == in->mirrored &&
           (coarse || r->insts[i + n].lod_proxy == in->lod_proxy))
      n++;
    binds += bound != in->tex;
    draw_run(r, i, n, loc, coarse, &bound);
    k += n;
  }
  glBindVertexArray(0);
  glFrontFace(GL_CCW);
  return binds;
}

/* With pass timing on (satf_renderer_set_pass_timing): waits for the GPU
 * and adds the time since *t0 to r->pass_ms[pass], restarting *t0. */
static void pass_mark(satf_renderer *r, int pass, double *t0) {
  if (!r->pass_timing)
    return;
  glFinish();
  double t = satf_now_seconds();
  if (pass >= 0)
    r->pass_ms[pass] += 1e3 * (t - *t0);
  *t0 = t;
}

/* Every cluster's fragments into the per-pixel arrays (mode: u_list_mode
 * of glsl/shade_fs.glsl). */
static void fill_lists(satf_renderer *r, satf_aov aov, const float viewproj[16],
                       int mode, int opaque) {
  lists_bind(&r->lists, mode);
  /* the nearest passes test against the overflow mask */
  draw_hair_depth_test(r->nmeshes > 0 || opaque || mode > 0);
  glDisable(GL_CULL_FACE);
  GLuint prog = r->lod ? r->prog_shade_lod : r->prog_shade;
  draw_shading_uniforms(r, prog, aov);
  glUniform1i(glGetUniformLocation(prog, "u_list_mode"), mode);
  glEnable(GL_CULL_FACE); /* front faces: each traces the whole cluster */
  glCullFace(GL_BACK);
  double t0 = 0.0;
  pass_mark(r, -1, &t0);
  r->map_binds = cluster_gpu_draw(r, prog, viewproj, 0);
  pass_mark(r, 0, &t0);
  glDisable(GL_CULL_FACE);
  sparse_lists(r, aov, viewproj, mode); /* their strands, sorted with them */
  pass_mark(r, 1, &t0);
  draw_hair_depth_test(0);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                  GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                  GL_TEXTURE_FETCH_BARRIER_BIT);
}

void cluster_gpu_resolve(satf_renderer *r, satf_aov aov,
                         const float viewproj[16], int pool) {
  double t0 = 0.0;
  pass_mark(r, -1, &t0);
  if (aov == SATF_AOV_DEPTH) {
    depth_resolve(r, viewproj);
    pass_mark(r, 2, &t0);
    return;
  }
  satf_gl_target_bind(r->out);
  glEnable(GL_BLEND); /* the hair's composite over background and meshes */
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  /* only pixels the hair can cover need resolving */
  int box[4];
  view_screen_box(&r->view, viewproj, box);
  glEnable(GL_SCISSOR_TEST);
  glScissor(box[0], box[1], box[2], box[3]);
  GLuint prog = pool ? r->prog_resolve_pool : r->prog_resolve;
  glUseProgram(prog);
  glUniform1i(glGetUniformLocation(prog, "u_slots"), r->lists.slots);
  shaders_fullscreen(r->empty_vao);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
  pass_mark(r, 2, &t0);
}

GLuint cluster_gpu_lists(satf_renderer *r, satf_aov aov,
                         const float viewproj[16], int nearest, long *fragments,
                         long *overflow) {
  draw_begin_frame(r, aov, viewproj);
  /* the strands' opaque fragments first: behind them nothing is stored
   * (the ponytail drawn as its strands: 4.2 fragments a pixel, the
   * crown's overflowing the arrays) */
  glBindFramebuffer(GL_FRAMEBUFFER, r->lists.fbo);
  glViewport(0, 0, r->view.width, r->view.height);
  int opaque = sparse_opaque_depth(r, viewproj);
  /* nearest: a first pass finds each pixel's r->lists.slots nearest depths (an
   * arrival-order-free k-buffer), the second stores only fragments no
   * farther than the last of them; both only inside the box of the pixels
   * the plain pass overflowed (the ponytail's ribbons cost their
   * rasterising there, not their shading) */
  if (nearest) {
    const int *b = r->lists.overflow_box;
    lists_mask_overflow(&r->lists);
    glEnable(GL_SCISSOR_TEST);
    glScissor(b[0], b[1], b[2], b[3]);
    fill_lists(r, aov, viewproj, 1, opaque);
    fill_lists(r, aov, viewproj, 2, opaque);
    glDisable(GL_SCISSOR_TEST);
  } else {
    lists_begin(&r->lists);
    fill_lists(r, aov, viewproj, 0, opaque);
  }
  return lists_count(&r->lists, nearest, fragments, overflow);
}

/* SATF eq. 14 by drawing order (see satf_composite in satf/render.h). */
satf_status cluster_gpu_ordered(satf_renderer *r, satf_aov aov,
                                const float viewproj[16], satf_error *err) {
  int *order = hierarchy_far_to_near(r, r->view.camera.position);
  if (!order)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  draw_begin_frame(r, aov, viewproj);
  draw_hair_depth_test(r->nmeshes > 0);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); /* premultiplied "over" */
  glEnable(GL_CULL_FACE);
  GLuint prog = r->lod ? r->prog_shade_ordered_lod : r->prog_shade_ordered;
  sparse_ordered_begin(r, aov, viewproj);
  draw_shading_uniforms(r, prog, aov);
  GLint loc[LOC_COUNT];
  use_layer_program(r, prog, viewproj, loc);
  glCullFace(GL_BACK);
  for (int q = 0; q < r->ninsts; q++) { /* the order forbids batching */
    if (sparse_ordered(r, order[q])) {  /* its strands */
      glUseProgram(prog); /* the two programs share units and buffers */
      continue;
    }
    glEnable(GL_CULL_FACE);
    draw_run(r, order[q], 1, loc, 0, NULL);
  }
  glBindVertexArray(0);
  glFrontFace(GL_CCW);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  draw_hair_depth_test(0);
  free(order);
  return SATF_OK;
}
