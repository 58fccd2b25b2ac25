#version 430 core
/* layer_vs.glsl - the outermost shell only, for the light's passes. */
layout(location = 0) in vec3 a_pos;
layout(location = 3) in vec2 a_uv;
uniform mat4 u_model;
uniform mat4 u_viewproj;
out vec2 v_uv;
void main() {
  v_uv = a_uv;
  gl_Position = u_viewproj * (u_model * vec4(a_pos, 1.0));
}
