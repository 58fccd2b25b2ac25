# import: strand hair files (.hair, .tfx) into satf scenes (satf/strands.h,
# satf/import.h) and the satf-import command.
add_library(satf_import STATIC
  ${CMAKE_CURRENT_LIST_DIR}/strands_hair.c
  ${CMAKE_CURRENT_LIST_DIR}/strands_tfx.c
  ${CMAKE_CURRENT_LIST_DIR}/import_cluster.c
  ${CMAKE_CURRENT_LIST_DIR}/import_fit.c
  ${CMAKE_CURRENT_LIST_DIR}/import_macro.c
  ${CMAKE_CURRENT_LIST_DIR}/import_density.c
  ${CMAKE_CURRENT_LIST_DIR}/import_scene.c)
target_link_libraries(satf_import PUBLIC satf_geometry satf_vdb satf_scene
                      satf_common cjson m PRIVATE satf_warnings)
if(SATF_FUZZ AND CMAKE_C_COMPILER_ID MATCHES "Clang")
  # Coverage feedback for libFuzzer inside the readers.
  target_compile_options(satf_import PRIVATE -fsanitize=fuzzer-no-link,address)
  target_link_options(satf_import INTERFACE -fsanitize=address)
endif()

add_executable(satf-import ${CMAKE_CURRENT_LIST_DIR}/satf_import_main.c)
target_link_libraries(satf-import PRIVATE satf_import satf_warnings)
