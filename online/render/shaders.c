/* shaders.c - the GLSL of the online renderer under its C names
 * (shaders.h). The text lives in the .glsl files of glsl/, embedded at
 * build time by glsl/embed.cmake as the constants of glsl_text.c (one per
 * file, includes expanded): edit the .glsl files. It also builds a
 * program from them with the limits its arrays are sized by. */
#include "shaders.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/fiber.h"
#include "satf/scene.h"

extern const char glsl_text_lighting[], glsl_text_layer_vs[],
    glsl_text_cluster_vs[], glsl_text_shade_fs[], glsl_text_dom_fs[],
    glsl_text_depth_fs[], glsl_text_fullscreen_vs[], glsl_text_resolve_fs[],
    glsl_text_display_fs[], glsl_text_mesh_vs[], glsl_text_mesh_fs[],
    glsl_text_empty_fs[], glsl_text_dom_mesh_fs[], glsl_text_strand_vs[],
    glsl_text_strand_fs[], glsl_text_strand_dom_fs[], glsl_text_baseline_vs[],
    glsl_text_baseline_fs[], glsl_text_baseline_lighting[],
    glsl_text_accum_fs[], glsl_text_fiber[], glsl_text_fiber_cluster[],
    glsl_text_strand_light_cs[], glsl_text_maps_kk_cs[],
    glsl_text_maps_sums_cs[], glsl_text_maps_fiber_cs[],
    glsl_text_overflow_mask_fs[];

const char *const satf_glsl_lighting = glsl_text_lighting;
const char *const satf_glsl_layer_vs = glsl_text_layer_vs;
const char *const satf_glsl_cluster_vs = glsl_text_cluster_vs;
const char *const satf_glsl_shade_fs = glsl_text_shade_fs;
const char *const satf_glsl_dom_fs = glsl_text_dom_fs;
const char *const satf_glsl_depth_fs = glsl_text_depth_fs;
const char *const satf_glsl_fullscreen_vs = glsl_text_fullscreen_vs;
const char *const satf_glsl_resolve_fs = glsl_text_resolve_fs;
const char *const satf_glsl_overflow_mask_fs = glsl_text_overflow_mask_fs;
const char *const satf_glsl_display_fs = glsl_text_display_fs;
const char *const satf_glsl_accum_fs = glsl_text_accum_fs;
const char *const satf_glsl_mesh_vs = glsl_text_mesh_vs;
const char *const satf_glsl_mesh_fs = glsl_text_mesh_fs;
const char *const satf_glsl_empty_fs = glsl_text_empty_fs;
const char *const satf_glsl_dom_mesh_fs = glsl_text_dom_mesh_fs;
const char *const satf_glsl_baseline_vs = glsl_text_baseline_vs;
const char *const satf_glsl_baseline_fs = glsl_text_baseline_fs;
const char *const satf_glsl_baseline_lighting = glsl_text_baseline_lighting;
const char *const satf_glsl_strand_vs = glsl_text_strand_vs;
const char *const satf_glsl_strand_fs = glsl_text_strand_fs;
const char *const satf_glsl_strand_dom_fs = glsl_text_strand_dom_fs;
const char *const satf_glsl_strand_light_cs = glsl_text_strand_light_cs;
const char *const satf_glsl_maps_kk_cs = glsl_text_maps_kk_cs;
const char *const satf_glsl_maps_sums_cs = glsl_text_maps_sums_cs;
const char *const satf_glsl_maps_fiber_cs = glsl_text_maps_fiber_cs;
const char *const satf_glsl_fiber = glsl_text_fiber;
const char *const satf_glsl_fiber_cluster = glsl_text_fiber_cluster;

/* src with `lines` inserted after its #version line. */
static char *with_defines(const char *src, const char *lines) {
  const char *nl = strchr(src, '\n');
  size_t head = nl ? (size_t)(nl - src) + 1 : 0;
  char *out = malloc(strlen(src) + strlen(lines) + 1);
  if (out) {
    memcpy(out, src, head);
    strcpy(out + head, lines);
    strcat(out, src + head);
  }
  return out;
}

/* The limits the shaders' arrays are sized by, then `extra`. */
static void limits(char *out, size_t size, const char *extra) {
  snprintf(out, size,
           "#define SATF_MAX_LIGHTS %d\n#define SATF_MAX_FRAGMENTS %d\n"
           "#define STRAND_LIGHT_VEC4 %d\n#define SATF_FIBER_AZ_ROWS %d\n"
           "#define SATF_FIBER_AZ_COLS %d\n#define SATF_FIBER_MP_NODES %d\n%s",
           SATF_SCENE_MAX_LIGHTS, SATF_MAX_FRAGMENTS, STRAND_LIGHT_VEC4,
           SATF_FIBER_AZ_ROWS, SATF_FIBER_AZ_COLS, SATF_FIBER_MP_NODES, extra);
}

/* Compiles one program. Its shaders' arrays are sized by the C limits,
 * defined after their #version lines with `extra` (glsl/). */
satf_status shaders_program(const char *label, const char *vs, const char *fs,
                            const char *extra, GLuint *out, satf_error *err) {
  char defines[512];
  limits(defines, sizeof defines, extra);
  /* both stages see them (cluster_vs.glsl shades per vertex in the
   * physical mode) */
  char *text = with_defines(fs, defines), *vtext = with_defines(vs, defines);
  satf_status st = text && vtext
                       ? satf_gl_program_build(label, vtext, text, out, err)
                       : satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  free(text);
  free(vtext);
  return st;
}

satf_status shaders_compute(const char *label, const char *cs,
                            const char *extra, GLuint *out, satf_error *err) {
  char defines[512];
  limits(defines, sizeof defines, extra);
  char *text = with_defines(cs, defines);
  satf_status st = text ? satf_gl_program_build_compute(label, text, out, err)
                        : satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  free(text);
  return st;
}

void shaders_fullscreen(GLuint vao) {
  glBindVertexArray(vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}
