#version 430 core
/* depth_fs.glsl - light-space depth only. */
#include "map_fetch.glsl"
in vec2 v_uv;
void main() {}
