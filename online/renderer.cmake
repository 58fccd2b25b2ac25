add_library(satf_render STATIC
  ${CMAKE_CURRENT_LIST_DIR}/density.c ${CMAKE_CURRENT_LIST_DIR}/maps.c
  ${CMAKE_CURRENT_LIST_DIR}/mat4.c ${CMAKE_CURRENT_LIST_DIR}/shaders.c
  ${CMAKE_CURRENT_LIST_DIR}/renderer.c ${CMAKE_CURRENT_LIST_DIR}/frontend.c
  ${CMAKE_CURRENT_LIST_DIR}/sequence.c)
target_link_libraries(satf_render PUBLIC satf_db satf_geometry satf_scene
                      satf_vdb satf_gl PRIVATE satf_warnings)
set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/maps.c
                            PROPERTIES COMPILE_OPTIONS "-O3")

add_executable(satf-render ${CMAKE_CURRENT_LIST_DIR}/satf_render_main.c)
target_link_libraries(satf-render PRIVATE satf_render satf_warnings)
set_target_properties(satf-render PROPERTIES LINKER_LANGUAGE CXX)

add_executable(satf-view ${CMAKE_CURRENT_LIST_DIR}/satf_view_main.c)
target_link_libraries(satf-view PRIVATE satf_render satf_glfw satf_warnings)
set_target_properties(satf-view PROPERTIES LINKER_LANGUAGE CXX)
