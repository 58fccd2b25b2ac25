# Animation playback through the renderer (online/sequence.c).
if(NOT TARGET satf_render OR NOT TARGET satf_offline)
  return()
endif()
satf_unit_test(test_sequence SOURCES test_sequence.c
               LIBS satf_render satf_offline LABELS "render;gl")
set_target_properties(test_sequence PROPERTIES LINKER_LANGUAGE CXX)
set_tests_properties(test_sequence PROPERTIES TIMEOUT 120)

# satf-render --frames: argument errors, then a short batch with a contact
# sheet and a resumed rerun that must skip every frame.
set(seq_dir ${CMAKE_CURRENT_BINARY_DIR}/cli_sequence)
add_test(NAME cli_frames_bad_range COMMAND satf-render
         ${CMAKE_SOURCE_DIR}/samples/anim_8.json --frames 3-x -o ${seq_dir}/f_%04d.exr)
set_tests_properties(cli_frames_bad_range PROPERTIES WILL_FAIL TRUE LABELS cli)
add_test(NAME cli_frames_bad_pattern COMMAND satf-render
         ${CMAKE_SOURCE_DIR}/samples/anim_8.json --frames 1-2 -o ${seq_dir}/f.exr)
set_tests_properties(cli_frames_bad_pattern PROPERTIES WILL_FAIL TRUE LABELS cli)
add_test(NAME cli_resume_needs_frames COMMAND satf-render
         ${CMAKE_SOURCE_DIR}/samples/anim_8.json --resume -o x.exr)
set_tests_properties(cli_resume_needs_frames PROPERTIES WILL_FAIL TRUE LABELS cli)
if(TARGET satf-build)
  add_test(NAME cli_frames_resume COMMAND sh -c
    "set -e; mkdir -p ${seq_dir}; d=${seq_dir}/db.exr; \
     $<TARGET_FILE:satf-build> -q --samples 16 --angles 8 --width 16 --grid 8 -o $d; \
     $<TARGET_FILE:satf-render> ${CMAKE_SOURCE_DIR}/samples/anim_8.json --db $d \
       --size 96x72 --frames 1-3 -o ${seq_dir}/f_%04d.exr \
       --contact-sheet ${seq_dir}/sheet.png -q; \
     test -s ${seq_dir}/f_0003.exr; test -s ${seq_dir}/sheet.png; \
     $<TARGET_FILE:satf-render> ${CMAKE_SOURCE_DIR}/samples/anim_8.json --db $d \
       --size 96x72 --frames 1-3 -o ${seq_dir}/f_%04d.exr --resume \
       | grep -q '0 rendered, 3 already complete'")
  set_tests_properties(cli_frames_resume PROPERTIES LABELS cli)
endif()
