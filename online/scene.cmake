# The scene file (JSON via cJSON): include/satf/scene.h, its keyframe
# animation: include/satf/anim.h.
find_package(cJSON CONFIG REQUIRED)
add_library(satf_scene STATIC
  ${CMAKE_CURRENT_SOURCE_DIR}/scene.c
  ${CMAKE_CURRENT_SOURCE_DIR}/scene_anim.c
  ${CMAKE_CURRENT_SOURCE_DIR}/scene_anim_parse.c
  ${CMAKE_CURRENT_SOURCE_DIR}/scene_cluster.c
  ${CMAKE_CURRENT_SOURCE_DIR}/scene_instance.c
  ${CMAKE_CURRENT_SOURCE_DIR}/scene_interp.c
  ${CMAKE_CURRENT_SOURCE_DIR}/scene_json.c
  ${CMAKE_CURRENT_SOURCE_DIR}/scene_parse.c
  ${CMAKE_CURRENT_SOURCE_DIR}/scene_transform.c)
target_link_libraries(satf_scene PUBLIC satf_common cjson m
                      PRIVATE satf_warnings)
if(SATF_FUZZ AND CMAKE_C_COMPILER_ID MATCHES "Clang")
  # Coverage feedback for libFuzzer inside the parser itself.
  target_compile_options(satf_scene PRIVATE -fsanitize=fuzzer-no-link,address)
  target_link_options(satf_scene INTERFACE -fsanitize=address)
endif()
