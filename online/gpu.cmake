# gpu part: OpenGL contexts, GL helpers and frame output.
#   satf_image - float frame with named channels, EXR + PNG writers (no GL)
#   satf_gl    - headless EGL context + GL helpers (+ satf_image)
#   satf_glfw  - GLFW window context, for the interactive viewer only
# GL entry points resolve through libglvnd's libOpenGL (online/gl.h).
find_package(OpenGL REQUIRED COMPONENTS OpenGL EGL)
find_package(PNG REQUIRED)
find_package(glfw3 CONFIG REQUIRED)

add_library(satf_image STATIC image.c)
target_link_libraries(satf_image PUBLIC satf_exr satf_common PNG::PNG m
                      PRIVATE satf_warnings)

add_library(satf_gl STATIC gl_context_egl.c gl_util.c)
target_link_libraries(satf_gl PUBLIC satf_image OpenGL::OpenGL OpenGL::EGL
                      PRIVATE satf_warnings)

add_library(satf_glfw STATIC gl_context_glfw.c)
target_link_libraries(satf_glfw PUBLIC satf_gl glfw PRIVATE satf_warnings)
