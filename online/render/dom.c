/* dom.c - owns the deep opacity map's state (dom.h): its targets, its
 * placement along the key light and its uniforms in the programs that draw
 * into it (draw.c draws it). */
#include "dom.h"

#include <stdlib.h>
#include <string.h>

satf_status dom_create(dom_map *d, satf_error *err) {
  satf_status st =
      satf_gl_target_create(DOM_SIZE, DOM_SIZE, 1, NULL, &d->depth, err);
  /* the slabs' optical depths, and (-first, last) hair's depth per texel
   * (glsl/dom_write.glsl) */
  const satf_gl_format formats[2] = {SATF_GL_RGBA32F, SATF_GL_RGBA32F};
  if (st == SATF_OK)
    st =
        satf_gl_target_create(DOM_SIZE, DOM_SIZE, 2, formats, &d->opacity, err);
  if (st != SATF_OK)
    return st;
  GLuint tex[2] = {satf_gl_target_depth_texture(d->depth),
                   satf_gl_target_color_texture(d->opacity, 0)};
  for (int k = 0; k < 2; k++) {
    glBindTexture(GL_TEXTURE_2D, tex[k]);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  return satf_gl_check("renderer set-up", err);
}

void dom_release(dom_map *d) {
  satf_gl_target_destroy(d->depth);
  satf_gl_target_destroy(d->opacity);
  d->depth = d->opacity = NULL;
  free(d->points);
  d->points = NULL;
}

/* The map (Yuksel & Keyser 2008) counts the hair in four slabs behind the
 * first hair and lumps all that lies beyond into the fourth, which a
 * look-up spreads to the texel's last hair (dom_behind.glsl); the physical
 * mode looks it up one slab nearer the light so a strand does not count
 * itself (strand_fs.glsl). A hair is an occluder one diameter deep: slabs
 * thinner than that put the four inside the first hair, so every point
 * past it counts the whole column (its own strand and the hair beyond it)
 * and its direct light e^-n loses at least e^-1. Clusters split into
 * single strands (import_refine.c) have a strand's radius, which made the
 * slabs a sixth of a strand (the ponytail back-lit: direct light through
 * the map 0.70 of Cycles' unblocked fraction, the frame 0.60 of Cycles'
 * luminance; at one diameter 0.93). */
float dom_cluster_radius(const satf_scene *scene, int nprotos) {
  float sum = 0.0f;
  for (int m = 0; m < nprotos; m++)
    sum += scene->macro_clusters[m].prototype.a.values[0];
  return sum / (float)(nprotos > 0 ? nprotos : 1);
}

void dom_place(dom_map *d, const view *v, float cluster_r, float hair_width) {
  float rad = 0.0f;
  view_light_map(v, d->light_index, d->viewproj, &rad);
  float slab = 0.66f * cluster_r * 0.5f;
  d->slab = (slab > hair_width ? slab : hair_width) / (2.0f * rad);
}

void dom_mark_drawn(dom_map *d, dom_hair_fn hair, const void *ctx) {
  memcpy(d->drawn_viewproj, d->viewproj, sizeof d->drawn_viewproj);
  d->drawn_slab = d->slab;
  d->drawn_hair = hair;
  d->drawn_ctx = ctx;
  d->valid = 1;
}

void dom_swap(dom_map *a, dom_map *b) {
  b->eye_tol = a->eye_tol;
  b->move_tol = a->move_tol;
  dom_map t = *a;
  *a = *b;
  *b = t;
}

void dom_uniforms(const dom_map *d, GLuint prog) {
  glUseProgram(prog);
  glUniform1i(glGetUniformLocation(prog, "u_dom_depth"), 1);
  glUniform1f(glGetUniformLocation(prog, "u_dom_slab"), d->slab);
}
