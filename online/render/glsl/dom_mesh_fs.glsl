#version 430 core
/* dom_mesh_fs.glsl - meshes in the deep opacity map: opaque, so a large
 * optical depth in the slab where the light meets them. */
uniform sampler2D u_dom_depth;
uniform float u_dom_slab;
#include "dom_write.glsl"
void main() { dom_write(8.0); }
