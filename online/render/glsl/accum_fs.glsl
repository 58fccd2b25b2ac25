#version 430 core
/* accum_fs.glsl - one jittered sample of a frame, weighted, added into
 * the anti-aliasing accumulator (samples.c); with weight 1, the
 * accumulator copied back into the frame. */
uniform sampler2D u_image;
uniform float u_weight;
out vec4 o_color;
void main() {
  o_color = u_weight * texelFetch(u_image, ivec2(gl_FragCoord.xy), 0);
}
