#version 430 core
/* display_fs.glsl - the linear image, premultiplied over transparent
 * black, composited over the background and converted to sRGB. */
uniform sampler2D u_image;
uniform vec3 u_background;
in vec2 v_uv;
out vec4 o_color;
float srgb(float x) {
  x = clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
void main() {
  vec4 p = texture(u_image, v_uv);
  vec3 c = p.rgb + (1.0 - p.a) * u_background; /* premultiplied "over" */
  o_color = vec4(srgb(c.r), srgb(c.g), srgb(c.b), 1.0);
}
