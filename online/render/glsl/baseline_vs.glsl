#version 430 core
/* baseline_vs.glsl - Scheuermann 2004 (paper 002): a cluster's shell layers
 * as textured polygon patches in world space (vertex layout: baseline.c).
 * invariant: the opaque pass primes depth with one program and the next
 * pass tests it for equality with another. */
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_tangent;
layout(location = 3) in vec2 a_uv;
layout(location = 4) in float a_ao; /* per-vertex ambient occlusion */
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_viewproj;
out vec3 v_world;
out vec3 v_normal;
out vec3 v_tangent;
out vec2 v_uv;
out float v_ao;
invariant gl_Position;
void main() {
  vec4 w = u_model * vec4(a_pos, 1.0);
  v_world = w.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_tangent = mat3(u_model) * a_tangent;
  v_uv = a_uv;
  v_ao = a_ao;
  gl_Position = u_viewproj * w;
}
