#version 430 core
/* layer_vs.glsl - the outermost shell only, for the light's passes; the
 * instances of a draw as in cluster_vs.glsl. */
layout(location = 0) in vec3 a_pos;
layout(location = 3) in vec2 a_uv;
layout(std430, binding = 3) readonly buffer satf_models { mat4 g_model[]; };
uniform int u_first, u_first_layer, u_inst_layers;
uniform mat4 u_viewproj;
out vec2 v_uv;
flat out int v_layer0;
void main() {
  v_uv = a_uv;
  v_layer0 = u_first_layer + gl_InstanceID * u_inst_layers;
  gl_Position = u_viewproj * (g_model[u_first + gl_InstanceID] *
                              vec4(a_pos, 1.0));
}
