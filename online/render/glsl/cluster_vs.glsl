#version 430 core
/* cluster_vs.glsl - the outermost shell with the cluster's local frame at
 * each vertex: the trajectory point C(t), the ellipse's axes n1, n2 (the
 * normal-plane frame turned by the twist theta), the trajectory's unit
 * tangent and |dT/dt|, and A, B, theta, all in the prototype's frame (vertex
 * layout: hierarchy.c). One draw covers a run of a prototype's instances
 * (cluster_gpu.c): instance u_first + gl_InstanceID, whose transform is in the
 * instance buffer and whose maps start at texture layer v_layer0. */
layout(location = 0) in vec3 a_pos;
layout(location = 2) in vec3 a_tangent;
layout(location = 3) in vec2 a_uv;
layout(location = 4) in vec3 a_centre;
layout(location = 5) in vec3 a_n1;
layout(location = 6) in vec3 a_n2;
layout(location = 7) in vec4 a_shape;  /* A, B, theta, |dT/dt| */
layout(location = 8) in vec3 a_axis;   /* unit tangent of T */
layout(std430, binding = 3) readonly buffer satf_models { mat4 g_model[]; };
uniform int u_first, u_first_layer, u_inst_layers;
uniform mat4 u_viewproj;
flat out int v_instance;
flat out int v_layer0;
out vec3 v_local;
out vec3 v_world;
out vec3 v_hair;
out float v_t;
out vec3 v_centre;
out vec3 v_n1;
out vec3 v_n2;
out vec4 v_shape;
out vec3 v_axis;
#ifndef PHYSICAL
#define PHYSICAL 0
#endif
#if PHYSICAL
#include "fiber_cluster.glsl"
/* the eye and lights in the prototype's frame, per instance (shade_fs) */
struct satf_view { vec4 eye; vec4 light[SATF_MAX_LIGHTS]; };
layout(std430, binding = 4) readonly buffer satf_views { satf_view g_view[]; };
uniform int u_cluster_shadow;
out vec3 v_global; /* the key light's global scattering BCSDF */
out vec3 v_back;   /* its local back-scattering */
/* the same of the fill light where its deep opacity map shadows it, and
 * the map's transmittance where its light enters the cluster (shade_fs.glsl
 * reads the key's so per fragment; the fill, softer and weaker, per
 * vertex: per fragment it cost 15% of the ponytail's frame on llvmpipe) */
uniform int u_fill_shadow;
out vec3 v_fill_global, v_fill_back;
out float v_fill_dom;
uniform sampler2D u_dom_depth, u_dom_opacity, u_fill_depth, u_fill_opacity;
uniform mat4 u_light_viewproj, u_fill_viewproj;
uniform float u_dom_slab, u_fill_slab, u_kcluster;
#define DOM_FILL 1
#include "dom_behind.glsl"
#include "shell_entry.glsl"
#endif
void main() {
  v_instance = u_first + gl_InstanceID;
  v_layer0 = u_first_layer + gl_InstanceID * u_inst_layers;
  vec4 w = g_model[v_instance] * vec4(a_pos, 1.0);
  v_local = a_pos;
  v_world = w.xyz;
  v_hair = a_tangent;
  v_t = a_uv.y;
  v_centre = a_centre;
  v_n1 = a_n1;
  v_n2 = a_n2;
  v_shape = a_shape;
  v_axis = a_axis;
#if PHYSICAL
  v_global = v_back = vec3(0.0);
  if (u_cluster_shadow != 0) {
    vec4 l = g_view[v_instance].light[0];
    v_global = key_global(normalize(a_tangent),
                          normalize(g_view[v_instance].eye.xyz - a_pos),
                          normalize(l.xyz - l.w * a_pos), v_back);
  }
  v_fill_global = v_fill_back = vec3(0.0);
  v_fill_dom = 1.0;
#if NLIGHTS > 1
  if (u_fill_shadow != 0) {
    vec4 l = g_view[v_instance].light[1];
    vec3 lp = normalize(l.xyz - l.w * a_pos);
    v_fill_global = key_global(normalize(a_tangent),
                               normalize(g_view[v_instance].eye.xyz - a_pos),
                               lp, v_fill_back);
    /* where the light's ray towards the vertex enters the cluster, as
     * shade_fs.glsl's key_light_dom reads the key's map */
    float A = a_shape.x, B = a_shape.y;
    vec3 n1 = normalize(a_n1), n2 = normalize(a_n2), q = a_pos - a_centre;
    vec2 P = vec2(dot(q, n1) / A, dot(q, n2) / B);
    vec3 entry = shell_entry(a_pos, P, lp, n1, n2, A, B);
    v_fill_dom = fill_point_transmittance(
        (g_model[v_instance] * vec4(entry, 1.0)).xyz, 0.0);
  }
#endif
#endif
  gl_Position = u_viewproj * w;
}
