# Scene file tests. The fuzz target's body (tests/fuzz_scene.c) is also
# compiled into the unit test, which replays a generated corpus through it.
satf_unit_test(test_scene
  SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_scene.c
          ${CMAKE_CURRENT_SOURCE_DIR}/fuzz_scene.c
  LIBS satf_scene satf_common)
target_compile_definitions(test_scene PRIVATE
  SATF_SAMPLES_DIR="${CMAKE_SOURCE_DIR}/samples")

if(SATF_FUZZ AND CMAKE_C_COMPILER_ID MATCHES "Clang")
  add_executable(fuzz_scene ${CMAKE_CURRENT_SOURCE_DIR}/fuzz_scene.c)
  target_compile_options(fuzz_scene PRIVATE -fsanitize=fuzzer,address)
  target_link_options(fuzz_scene PRIVATE -fsanitize=fuzzer,address)
  target_link_libraries(fuzz_scene PRIVATE satf_scene satf_warnings)
endif()

# Keyframe animation of scene files (satf/anim.h) and the Fig. 8 sample.
satf_unit_test(test_anim
  SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_anim.c
  LIBS satf_scene satf_common)
target_compile_definitions(test_anim PRIVATE
  SATF_SAMPLES_DIR="${CMAKE_SOURCE_DIR}/samples")
