# Tests of the online renderer (part "renderer"): the production GLSL
# lighting on the driver, the SATF maps on the CPU, whole frames through
# satf_renderer, and the satf-render / satf-view command lines. GL tests run
# on Mesa's llvmpipe through EGL's surfaceless platform (no display).
# They build their own small database, so they need the offline part.
if(NOT TARGET satf_render OR NOT TARGET satf_offline)
  return()
endif()
satf_unit_test(test_lighting SOURCES test_lighting.c LIBS satf_render
               LABELS "render;gl")
satf_unit_test(test_maps SOURCES test_maps.c LIBS satf_render satf_offline
               LABELS render)
satf_unit_test(test_render SOURCES test_render.c
               LIBS satf_render satf_offline satf_exr LABELS "render;gl")
set_tests_properties(test_lighting test_maps test_render PROPERTIES TIMEOUT 120)
# satf_render carries C++ (the OpenVDB and OpenMesh shims)
set_target_properties(test_lighting test_maps test_render PROPERTIES
                      LINKER_LANGUAGE CXX)

include(${CMAKE_CURRENT_LIST_DIR}/cli_render.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/sequence.cmake)
