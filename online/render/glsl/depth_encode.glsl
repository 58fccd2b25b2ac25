/* depth_encode.glsl - SATF_AOV_DEPTH into the RGBA16F target: the
 * distance along the camera's view axis (what Blender 3.4's Cycles Z pass
 * holds: a plane facing the camera reads one depth across the image) as
 * a half and the half of its remainder, so the two add back to about 22
 * bits (satf_renderer_render_image); alpha 1 tells it from the cleared
 * background. u_depth_row . (world, 1) is that distance (depth.c). */
uniform vec4 u_depth_row;
float depth_of(vec3 world) { return dot(u_depth_row, vec4(world, 1.0)); }
vec4 depth_encode(float z) {
  float hi = unpackHalf2x16(packHalf2x16(vec2(z, 0.0))).x;
  return vec4(hi, z - hi, 0.0, 1.0);
}
