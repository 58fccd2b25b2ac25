/* depth.c - owns SATF_AOV_DEPTH's composite (depth.h): the per-pixel
 * fragment arrays filled by a path's callback, grown or kept to their
 * nearest fragments as the cluster path's exact composite does, and
 * resolved to the depth of half coverage. */
#include "depth.h"

#include "draw.h"
#include "mat4.h"
#include "renderer_internal.h"
#include "shaders.h"

static void fill_pass(satf_renderer *r, const float viewproj[16],
                      depth_fill_fn fill, void *ctx, int mode) {
  lists_bind(&r->lists, mode);
  /* the nearest passes test against the overflow mask */
  draw_hair_depth_test(r->nmeshes > 0 || mode > 0);
  glDisable(GL_CULL_FACE);
  fill(r, ctx, viewproj, mode);
  draw_hair_depth_test(0);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                  GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                  GL_TEXTURE_FETCH_BARRIER_BIT);
}

satf_status depth_lists(satf_renderer *r, const float viewproj[16],
                        depth_fill_fn fill, void *ctx, satf_error *err) {
  draw_begin_frame(r, SATF_AOV_DEPTH, viewproj);
  long count = 0, over = 0, ignore = 0;
  lists_begin(&r->lists);
  fill_pass(r, viewproj, fill, ctx, 0);
  GLuint most = lists_count(&r->lists, 0, &count, &over);
  int grown = 0;
  satf_status st = lists_grow(&r->lists, (int)most + 4, &grown, err);
  if (st != SATF_OK)
    return st;
  if (grown) {
    lists_begin(&r->lists);
    fill_pass(r, viewproj, fill, ctx, 0);
    lists_count(&r->lists, 0, &count, &over);
  }
  if (over > 0) {
    if ((st = lists_alloc_keys(&r->lists, err)) != SATF_OK)
      return st;
    const int *b = r->lists.overflow_box;
    lists_mask_overflow(&r->lists);
    glEnable(GL_SCISSOR_TEST);
    glScissor(b[0], b[1], b[2], b[3]);
    fill_pass(r, viewproj, fill, ctx, 1);
    fill_pass(r, viewproj, fill, ctx, 2);
    glDisable(GL_SCISSOR_TEST);
    lists_count(&r->lists, 1, &count, &ignore);
  }
  depth_resolve(r, viewproj);
  return satf_gl_check("depth", err);
}

void depth_resolve(const satf_renderer *r, const float viewproj[16]) {
  satf_gl_target_bind(r->out);
  glDisable(GL_BLEND); /* a depth replaces what lies behind */
  glDisable(GL_DEPTH_TEST);
  int box[4];
  view_screen_box(&r->view, viewproj, box);
  glEnable(GL_SCISSOR_TEST);
  glScissor(box[0], box[1], box[2], box[3]);
  GLuint p = r->prog_resolve_depth;
  glUseProgram(p);
  glUniform1i(glGetUniformLocation(p, "u_slots"), r->lists.slots);
  /* the fragments' window depths back to world space through the
   * sample's own (jittered) matrix */
  float inv[16];
  satf_mat4_invert(viewproj, inv);
  draw_set_mat4(p, "u_inv_viewproj", inv);
  glUniform2f(glGetUniformLocation(p, "u_size"), (float)r->view.width,
              (float)r->view.height);
  draw_depth_row(r, p);
  shaders_fullscreen(r->empty_vao);
  glDisable(GL_SCISSOR_TEST);
}
