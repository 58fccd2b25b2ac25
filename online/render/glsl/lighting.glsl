/* lighting.glsl - SATF eq. 9-11: Kajiya-Kay diffuse and the two shifted
 * highlights. Included by shade_fs.glsl; tests evaluate these functions
 * alone (satf_glsl_lighting), so this file has no #version line:
 * float kk_diffuse(vec3 t, vec3 l); float kk_specular(vec3 t, vec3 l,
 * vec3 v, float exponent); vec3 shifted(vec3 t, vec3 n, float s);
 * vec3 facing_normal(vec3 t, vec3 v). */
float sin_between(vec3 a, vec3 b) {
  float c = dot(a, b);
  return sqrt(max(0.0, 1.0 - c * c));
}
/* SATF eq. 9: Kajiya-Kay diffuse */
float kk_diffuse(vec3 t, vec3 l) { return sin_between(t, l); }
/* SATF eq. 10-11 with the tangent shifted along the cluster normal
 * (paper 002: T' = normalize(T + s N)). The extracted eq. 10 reads
 * (t.l)(t.v) + sin sin; with v pointing to the viewer that peaks at
 * retro-reflection, so we use the mirror form sin sin - (t.l)(t.v)
 * (Kajiya-Kay measure the eye vector towards the surface). */
float kk_specular_cosine(vec3 t, vec3 l, vec3 v) {
  return sin_between(t, l) * sin_between(t, v) - dot(t, l) * dot(t, v);
}
float kk_specular(vec3 t, vec3 l, vec3 v, float e) {
  return pow(max(kk_specular_cosine(t, l, v), 0.0), e);
}
vec3 shifted(vec3 t, vec3 n, float s) { return normalize(t + s * n); }
/* The normal eq. 10-11 shift along: the strand's normal facing the viewer,
 * v without its part along the strand (0 where v runs along it). Both
 * paths take it (strand_fs.glsl, shade_fs.glsl): a fibre's cuticle tilts
 * its highlight cone along the fibre whatever side it is seen from, and
 * this normal moves the highlight along the strand as the viewer sees it. */
vec3 facing_normal(vec3 t, vec3 v) {
  vec3 n = v - dot(v, t) * t;
  float len = length(n);
  return len > 1e-6 ? n / len : vec3(0.0);
}
