#version 430 core
/* mesh_vs.glsl - opaque meshes (a head), positions and normals in world
 * space. */
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_viewproj;
out vec3 v_world;
out vec3 v_normal;
void main() {
  vec4 w = u_model * vec4(a_pos, 1.0);
  v_world = w.xyz;
  v_normal = u_normal_matrix * a_normal;
  gl_Position = u_viewproj * w;
}
