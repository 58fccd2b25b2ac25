/* gl.h - the single include for OpenGL in satf.
 *
 * OpenGL 3.3+/4.x core entry points are declared by the Khronos core-profile
 * header with prototypes enabled, and resolved at link time against
 * libglvnd's libOpenGL (CMake target OpenGL::OpenGL). libOpenGL forwards
 * every call through libGLdispatch to whichever context is current on the
 * calling thread, so the same code runs on a headless EGL context
 * (gl_context_egl.c) and on a GLX context made by GLFW
 * (gl_context_glfw.c), with no loader and no function-pointer tables.
 *
 * Headers: GL/glcorearb.h comes from Debian's libgl-dev, libOpenGL.so from
 * libopengl-dev, EGL headers and libEGL.so from libegl-dev. Only core
 * functions exported by libOpenGL (up to 4.5) may be called directly;
 * extension-only functions need eglGetProcAddress/glfwGetProcAddress. */
#ifndef SATF_ONLINE_GL_H
#define SATF_ONLINE_GL_H

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>

#endif
