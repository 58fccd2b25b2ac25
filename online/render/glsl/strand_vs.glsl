#version 430 core
/* strand_vs.glsl - the strand reference path (strands.c): each segment of
 * a strand is a camera-facing quad, expanded here in screen space. Its
 * half-width is half the strand's projected width plus the reach of the
 * pixel filter (half a pixel for the box, strand_cover.glsl): a strand thinner
 * than a pixel is drawn a pixel wide and its alpha is its true coverage,
 * so thin hair is anti-aliased, not aliased lines. Every point of a
 * strand is two vertices (even index: the -side, odd: the +side); the
 * quads meeting at a point share them, so a strand has no gaps or
 * overlaps at its joints. */
/* the opaque pre-pass (strand_dom_fs.glsl with WHOLE_DEPTH) and the
 * fragment arrays' pass must place a fragment at the same depth */
invariant gl_Position;
layout(location = 0) in vec4 a_pos;     /* world x, y, z; width (diameter) */
layout(location = 1) in vec3 a_tangent; /* the strand's direction here */
layout(location = 2) in float a_t;      /* arc length from the root / length */
layout(location = 3) in uint a_strand;
uniform mat4 u_viewproj;
uniform vec2 u_viewport;  /* pixels */
uniform float u_px_scale; /* pixels per scene unit at clip w = 1 */
uniform int u_pixel_filter; /* strand_cover.glsl */
out vec3 v_world;
out vec3 v_tangent;
out float v_t;
flat out uint v_strand;
noperspective out float v_across; /* pixels from the strand's centre line */
noperspective out float v_width;  /* the strand's true width, pixels */
#ifndef PHYSICAL
#define PHYSICAL 0
#endif
#if PHYSICAL
/* The fibre model's light at this point, over the whole fibre (h in
 * [-1, 1]), less the deep opacity map's shadow (strand_fiber.glsl;
 * strand_light_cs.glsl evaluates it once a frame per point), for
 * strand_fs.glsl to interpolate along the strand. A strand at most a few
 * pixels wide shows each pixel the fibre's whole width or most of it, so
 * h's average is what a pixel sees; evaluated per fragment it made the
 * physical strands 4-6 times slower than Kajiya-Kay's. Our approximation:
 * the light's variation along a segment is linear between its points (the
 * tangent, eye and light directions already are), and a pixel that sees
 * part of the fibre gets its two halves' averages weighed by how much of
 * each it covers (strand_fs.glsl samples the offsets themselves on wide
 * strands). */
layout(std430, binding = 6) readonly buffer satf_strand_light {
  vec4 g_light[];
};
/* StrandLight's key and rest over the fibre's halves h < 0 and h > 0 (the
 * rest with the fill's shadowed light, strand_light_cs.glsl) */
out vec3 v_key_lo, v_key_hi, v_rest_lo, v_rest_hi, v_global, v_af;
#endif

vec2 to_pixels(vec4 c) { return c.xy / c.w * 0.5 * u_viewport; }

void main() {
  float side = (gl_VertexID & 1) != 0 ? 1.0 : -1.0;
  vec4 c = u_viewproj * vec4(a_pos.xyz, 1.0);
  vec4 ca = u_viewproj * vec4(a_pos.xyz - 0.5 * a_tangent, 1.0);
  vec4 cb = u_viewproj * vec4(a_pos.xyz + 0.5 * a_tangent, 1.0);
  v_world = a_pos.xyz;
  v_tangent = a_tangent;
  v_t = a_t;
  v_strand = a_strand;
  if (min(c.w, min(ca.w, cb.w)) <= 1e-6) {
    /* behind the eye: outside the clip volume, so the quad is dropped */
    gl_Position = vec4(0.0, 0.0, -2.0, 1.0);
    v_across = v_width = 0.0;
#if PHYSICAL
    v_key_lo = v_key_hi = v_rest_lo = v_rest_hi = v_global = v_af = vec3(0.0);
#endif
    return;
  }
  vec2 dir = to_pixels(cb) - to_pixels(ca);
  float len = length(dir);
  /* a strand seen end-on has no screen direction: any side will do */
  dir = len > 1e-4 ? dir / len : vec2(1.0, 0.0);
  vec2 across = vec2(-dir.y, dir.x);
  float width = a_pos.w * u_px_scale / c.w;
  /* every pixel centre the filter reaches (distance < width/2 + its
   * radius, strand_cover.glsl), with a little room so none is lost to the
   * edge rule */
  float half_px = 0.5 * width + (u_pixel_filter == 1 ? 1.55 : 0.55);
  c.xy += across * side * half_px * 2.0 / u_viewport * c.w;
  v_across = side * half_px;
  v_width = width;
  gl_Position = c;
#if PHYSICAL
  /* the point's (two vertices a point) */
  int k = STRAND_LIGHT_VEC4 * (gl_VertexID >> 1);
  v_key_lo = g_light[k].rgb;
  v_key_hi = g_light[k + 1].rgb;
  v_rest_lo = g_light[k + 2].rgb;
  v_rest_hi = g_light[k + 3].rgb;
  v_global = g_light[k + 4].rgb;
  v_af = g_light[k + 5].rgb;
#endif
}
