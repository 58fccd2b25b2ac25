#version 430 core
/* dom_mesh_fs.glsl - meshes in the deep opacity map: opaque, so a large
 * optical depth in the slab where the light meets them. */
uniform sampler2D u_dom_depth;
uniform float u_dom_slab;
out vec4 o_opacity;
void main() {
  float d0 = texelFetch(u_dom_depth, ivec2(gl_FragCoord.xy), 0).r;
  float s = max(gl_FragCoord.z - d0, 0.0) / u_dom_slab;
  vec4 o = vec4(0.0);
  o[int(min(s, 3.0))] = 8.0;
  o_opacity = o;
}
