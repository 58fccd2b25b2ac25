#version 430 core
/* empty_fs.glsl - depth only. */
void main() {}
