#version 430 core
/* mesh_fs.glsl - opaque meshes: Lambert shading under the scene's lights,
 * the key light attenuated by the hair's deep opacity map. The renderer
 * defines SATF_MAX_LIGHTS. */
in vec3 v_world;
in vec3 v_normal;
uniform vec3 u_albedo;
uniform vec3 u_eye;
uniform int u_nlights;
uniform vec4 u_light_vec[SATF_MAX_LIGHTS];
uniform vec3 u_light_color[SATF_MAX_LIGHTS];
uniform int u_cluster_shadow;
uniform sampler2D u_dom_depth;
uniform sampler2D u_dom_opacity;
uniform mat4 u_light_viewproj;
uniform float u_dom_slab;
uniform float u_kcluster;
uniform int u_aov;
out vec4 o_color;
#include "dom_lookup.glsl"
#include "depth_encode.glsl"
void main() {
  /* an opaque surface: its own depth (SATF_AOV_DEPTH) */
  if (u_aov == 6) { o_color = depth_encode(depth_of(v_world)); return; }
  if (u_aov != 0) { o_color = vec4(0.0, 0.0, 0.0, 1.0); return; }
  vec3 n = normalize(v_normal);
  if (dot(n, u_eye - v_world) < 0.0) n = -n; /* either side */
  vec3 c = 0.12 * u_albedo; /* sky fill, so unlit sides read */
  for (int k = 0; k < u_nlights; k++) {
    vec3 dl = u_light_vec[k].xyz - u_light_vec[k].w * v_world;
    float fall = u_light_vec[k].w > 0.0 ? 1.0 / max(dot(dl, dl), 1e-6) : 1.0;
    float sh = k == 0 && u_cluster_shadow != 0 ?
               cluster_transmittance(v_world + 0.02 * n) : 1.0;
    c += u_light_color[k] * fall * sh * max(dot(n, normalize(dl)), 0.0) *
         u_albedo;
  }
  o_color = vec4(c, 1.0);
}
