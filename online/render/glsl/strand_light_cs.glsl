#version 430 core
/* strand_light_cs.glsl - the physical strands' light per point
 * (strand_fiber.glsl over the whole fibre, h in [-1, 1]), once a frame
 * for every point, into the buffer strand_vs.glsl reads (ribbons.c). In
 * the vertex shader it was evaluated four times a point (each point is two
 * vertices, drawn in two passes), on llvmpipe's one vertex thread; here
 * once, on all its threads. The renderer defines SATF_MAX_LIGHTS. */
layout(local_size_x = 64) in;
/* the ribbons' vertex buffer (ribbons.c strand_vertex: x, y, z, width,
 * tangent x, y, z, t, strand; 9 words), two vertices a point */
layout(std430, binding = 5) readonly buffer satf_strand_vertices {
  float g_vertex[];
};
/* per point (STRAND_LIGHT_VEC4 of them): StrandLight's key and rest over
 * the fibre's two halves, h in [-1, 0] and [0, 1], then its global and
 * af; the rest holds the fill light's radiance too, shadowed here, at the
 * point, through the fill's map (strand_fiber_dual): the fill is the
 * softer, weaker light, and looked up per fragment as the key is it cost
 * a quarter of the physical strands' frame on llvmpipe */
layout(std430, binding = 6) writeonly buffer satf_strand_light {
  vec4 g_light[];
};
uniform int u_npoints;
uniform vec3 u_eye;
uniform int u_nlights;
uniform vec4 u_light_vec[SATF_MAX_LIGHTS]; /* world; w: 0 direction, 1 position */
uniform vec3 u_light_color[SATF_MAX_LIGHTS];
uniform int u_cluster_shadow, u_fill_shadow, u_aov;
uniform sampler2D u_fill_depth, u_fill_opacity;
uniform mat4 u_fill_viewproj;
uniform float u_fill_slab;
#define DOM_FILL 1
uniform sampler2D u_dom_depth;
uniform sampler2D u_dom_opacity;
uniform mat4 u_light_viewproj;
uniform float u_dom_slab;
uniform float u_kcluster;
#include "fiber_cluster.glsl"
#include "dom_behind.glsl"
/* the lobes' azimuthal scattering averaged over each half of the fibre
 * (satf_fiber_azimuthal_table, fiber_gpu.c): two texture reads a lobe and
 * light where summing it at 16 offsets h took the physical strands' light
 * 69 of 69 ms on 40K-strand fur (llvmpipe) */
uniform sampler2DArray u_fiber_azimuthal;
uniform sampler2D u_fiber_mp;
#define STRAND_FIBER_TABLE 1
#define STRAND_FIBER_MP_TABLE 1
const int STRAND_FIBER_MAX_H = 1; /* the view's angles, at h = 0 */
#include "strand_fiber.glsl"

void main() {
  int k = int((gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) *
                  gl_WorkGroupSize.x + gl_LocalInvocationID.x);
  if (k >= u_npoints) return;
  int b = 18 * k; /* its first vertex */
  vec3 p = vec3(g_vertex[b], g_vertex[b + 1], g_vertex[b + 2]);
  vec3 tan = vec3(g_vertex[b + 4], g_vertex[b + 5], g_vertex[b + 6]);
  /* strand_fs.glsl's tangent and eye direction, here at the point */
  vec3 t = tan / max(length(tan), 1e-30), v = normalize(u_eye - p);
  StrandLight lo, hi;
  strand_fiber(t, v, p, -1.0, 1.0, STRAND_FIBER_MAX_H, u_aov, lo, hi);
  vec3 fill_lo = vec3(0.0), fill_hi = vec3(0.0);
  if (u_fill_shadow != 0) {
    /* one slab nearer the light, as strand_fs.glsl looks the key up */
    float dom = fill_point_transmittance(p, u_fill_slab);
    fill_lo = strand_fiber_dual(lo.fill, lo.fill_global, lo.fill_af, dom);
    fill_hi = strand_fiber_dual(hi.fill, hi.fill_global, hi.fill_af, dom);
  }
  int o = STRAND_LIGHT_VEC4 * k;
  g_light[o] = vec4(lo.key, 0.0);
  g_light[o + 1] = vec4(hi.key, 0.0);
  g_light[o + 2] = vec4(lo.rest + fill_lo, 0.0);
  g_light[o + 3] = vec4(hi.rest + fill_hi, 0.0);
  g_light[o + 4] = vec4(lo.global, 0.0);
  g_light[o + 5] = vec4(lo.af, 0.0);
}
