#version 430 core
/* display_fs.glsl - the linear image to sRGB, for the screen. */
uniform sampler2D u_image;
in vec2 v_uv;
out vec4 o_color;
float srgb(float x) {
  x = clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
void main() {
  vec3 c = texture(u_image, v_uv).rgb;
  o_color = vec4(srgb(c.r), srgb(c.g), srgb(c.b), 1.0);
}
