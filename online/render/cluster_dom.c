/* cluster_dom.c - owns the clusters' shadows (SATF Table 1: S): their
 * deep opacity map (dom.c) drawn from their coarse outer shells and the
 * sparse clusters' strands, and the rule that keeps the map drawn last
 * while the light, the hair and the maps' alpha it read stand. */
#include "renderer_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "draw.h"
#include "mat4.h"
#include "satf/math.h"

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
    dom_uniforms(&r->dom, r->prog_dom);
  cluster_gpu_draw(r, opacity ? r->prog_dom : r->prog_depth, r->dom.viewproj,
                   1);
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
      a[k] = r->view.camera.position[k] - in->centre[k];
      b[k] = r->dom.eye[k] - in->centre[k];
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

float cluster_dom_hair_move(const satf_renderer *r) {
  int n = dom_hair_points(r, NULL);
  if (!r->dom.valid || n != r->dom.npoints)
    return INFINITY;
  float *now = malloc(4 * (size_t)(n > 0 ? n : 1) * sizeof(float));
  if (!now || dom_hair_points(r, now) != n) {
    free(now);
    return INFINITY;
  }
  /* in the map's own light view (orthographic: x, y in [-1, 1] across
   * DOM_SIZE texels, window depth z / 2 + 1 / 2 in slabs of
   * dom_light_slab) */
  const float *m = r->dom.drawn_viewproj;
  float row[3] = {m[0], m[1], m[2]};
  float texels = 0.5f * (float)DOM_SIZE;
  float radius_texels = sqrtf(satf_dot3f(row, row)) * texels;
  float most = 0.0f;
  for (int i = 0; i < n; i++) {
    const float *a = r->dom.points + 4 * (size_t)i, *b = now + 4 * (size_t)i;
    float pa[3], pb[3];
    satf_mat4_point(m, a, pa);
    satf_mat4_point(m, b, pb);
    float dx = fabsf(pb[0] - pa[0]), dy = fabsf(pb[1] - pa[1]);
    float across =
        (dx > dy ? dx : dy) * texels + fabsf(b[3] - a[3]) * radius_texels;
    float along = 0.5f * fabsf(pb[2] - pa[2]) / r->dom.drawn_slab;
    float move = across > along ? across : along;
    most = move > most ? move : most;
  }
  free(now);
  return most;
}

/* Whether the map drawn last still stands for this frame: the eye rule
 * below, and the light and the hair. The exact rule (r->dom.move_tol < 0):
 * the light's view and slabs are those it was drawn with and the hair has
 * not moved (satf_renderer_set_scene clears dom_valid). Else the key light
 * is the same and no cluster moved more than r->dom.move_tol texels or
 * slabs since; the map keeps the view it was drawn with (the scene bounds
 * follow the hair, and with them the exact rule's view). */
static int dom_keep(satf_renderer *r) {
  if (!r->dom.valid || r->dom.drawn_hair != dom_clusters ||
      (r->dom.maps_stale && !(dom_eye_turn(r) < r->dom.eye_tol)))
    return 0;
  if (r->dom.move_tol < 0.0f)
    return !memcmp(r->dom.drawn_viewproj, r->dom.viewproj,
                   sizeof r->dom.drawn_viewproj) &&
           r->dom.drawn_slab == r->dom.slab;
  float lv[4];
  view_light_vector(&r->view.lights[r->dom.light_index], lv);
  if (memcmp(lv, r->dom.light, sizeof lv) ||
      !(cluster_dom_hair_move(r) <= r->dom.move_tol))
    return 0;
  memcpy(r->dom.viewproj, r->dom.drawn_viewproj, sizeof r->dom.drawn_viewproj);
  r->dom.slab = r->dom.drawn_slab;
  return 1;
}

/* r->dom, drawn again or kept (cluster_dom_update) */
static void update_map(satf_renderer *r) {
  /* the map reads the light's view, the hair's transforms and shells and
   * the maps' alpha (and the meshes): while none has changed since it was
   * drawn it is what drawing it again would give. The alpha follows the
   * eye's azimuth (the records are looked up for the eye), but the map
   * wants the opacity the light sees, for which the alpha seen from one
   * eye stands in no better than from another: the map is kept while the
   * eye turns by less than r->dom.eye_tol from where it was drawn
   * (measured with bench_dom, a map kept from an eye turned 5 to 180
   * degrees: SSIM >= 0.994 and mean |luminance change| <= 0.0025 on every
   * sample, the imported ponytail and 40K-strand fur; the most, fur at 90
   * degrees, is 11% of what the cluster shadows change there).
   * Moving hair: the map is kept while no control point moved more than
   * r->dom.move_tol (DOM_MOVE_TOL: a texel, the percentage-closer filter's
   * own reach, glsl/dom_lookup.glsl) from where it was drawn. anim_8's
   * hair moves 1.7-2.9 texels a frame: kept every other frame with 3, S
   * halves, but the shadow edges lag by a frame (SSIM >= 0.966, mean
   * |luminance change| <= 7.9% of the cluster shadows'; bench_dom --anim,
   * docs/performance.md), so the default keeps only hair that (nearly) stands
   * still */
  float cluster_r = hierarchy_shell_radius(r, NULL);
  dom_place(&r->dom, &r->view, cluster_r, hierarchy_hair_width(r));
  if (dom_keep(r)) {
    r->dom.reuses++;
    return;
  }
  draw_dom(r, cluster_r, hierarchy_hair_width(r), dom_clusters, NULL);
  dom_mark_drawn(&r->dom, dom_clusters, NULL);
  memcpy(r->dom.eye, r->view.camera.position, sizeof r->dom.eye);
  view_light_vector(&r->view.lights[r->dom.light_index], r->dom.light);
  r->dom.maps_stale = 0;
  int n = dom_hair_points(r, NULL);
  float *pts =
      realloc(r->dom.points, 4 * (size_t)(n > 0 ? n : 1) * sizeof(float));
  if (pts) {
    r->dom.points = pts;
    r->dom.npoints = dom_hair_points(r, pts);
  } else {
    r->dom.npoints = -1; /* not measured: drawn again next frame */
  }
}

/* Deep opacity map (Yuksel & Keyser 2008) from the key light (dom.c
 * places it): the first hair's depth, then optical depth summed into four
 * slabs behind it; the same from the fill light where draw_fill_shadows,
 * by the same rule. */
void cluster_dom_update(satf_renderer *r) {
  update_map(r);
  if (!draw_fill_shadows(r))
    return;
  dom_swap(&r->dom, &r->fill_dom);
  update_map(r);
  dom_swap(&r->dom, &r->fill_dom);
}
