#version 430 core
/* layer_vs.glsl - the outermost shell only, for the light's passes; the
 * instances of a draw as in cluster_vs.glsl. */
layout(location = 0) in vec3 a_pos;
layout(location = 3) in vec2 a_uv;
layout(location = 4) in vec3 a_centre;
layout(std430, binding = 3) readonly buffer satf_models { mat4 g_model[]; };
uniform int u_first, u_first_layer, u_inst_layers;
uniform mat4 u_viewproj;
out vec2 v_uv;
out float v_centre_z; /* the axis point's window depth (dom_fs.glsl) */
flat out int v_layer0;
void main() {
  v_uv = a_uv;
  v_layer0 = u_first_layer + gl_InstanceID * u_inst_layers;
  mat4 m = u_viewproj * g_model[u_first + gl_InstanceID];
  gl_Position = m * vec4(a_pos, 1.0);
  vec4 c = m * vec4(a_centre, 1.0);
  v_centre_z = c.z / c.w * 0.5 + 0.5;
}
