# Strand import tests. The fuzz targets' bodies (fuzz_hair.c, fuzz_tfx.c)
# are also compiled into test_strands under other names, which replays
# truncations and byte flips of valid files through them.
satf_unit_test(test_strands
  SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_strands.c
          ${CMAKE_CURRENT_SOURCE_DIR}/fuzz_hair.c
          ${CMAKE_CURRENT_SOURCE_DIR}/fuzz_tfx.c
  LIBS satf_import LABELS import)
target_compile_definitions(test_strands PRIVATE
  SATF_FUZZ_HAIR_ENTRY=fuzz_hair_one SATF_FUZZ_TFX_ENTRY=fuzz_tfx_one
  SATF_SHARED_DATA_DIR="${CMAKE_SOURCE_DIR}/../shared/data")
# test_strands writes rt3.tfx, the input of the command-line tests below.
set_tests_properties(test_strands PROPERTIES FIXTURES_SETUP import_input)
satf_unit_test(test_import SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_import.c
               LIBS satf_import LABELS import)

add_test(NAME cli_import_help COMMAND satf-import --help)
set_tests_properties(cli_import_help PROPERTIES
  PASS_REGULAR_EXPRESSION "INPUT... -o SCENE.json" LABELS "cli;import")
add_test(NAME cli_import_missing_file COMMAND satf-import
  ${CMAKE_CURRENT_BINARY_DIR}/no-such.hair -o ${CMAKE_CURRENT_BINARY_DIR}/x.json)
set_tests_properties(cli_import_missing_file PROPERTIES WILL_FAIL TRUE
  LABELS "cli;import")
add_test(NAME cli_import_bad_clusters COMMAND satf-import x.tfx -o x.json
  --clusters 0)
set_tests_properties(cli_import_bad_clusters PROPERTIES WILL_FAIL TRUE
  LABELS "cli;import")
# Import the TressFX file test_strands wrote, with follow strands, a VDB and
# a head mesh (a tetrahedron written here), which the scene lists.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/head.obj
  "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
add_test(NAME cli_import_roundtrip COMMAND sh -c
  "set -e; d=${CMAKE_CURRENT_BINARY_DIR}; \
   $<TARGET_FILE:satf-import> $d/rt3.tfx -o $d/cli_import.json \
     --vdb $d/cli_import.vdb --follow 3 --clusters 5 --mesh $d/head.obj \
     > $d/cli_import.out 2>&1; \
   grep -q '\"meshes\"' $d/cli_import.json; \
   grep -q 'head.obj' $d/cli_import.json; \
   grep -q 'strands          160' $d/cli_import.out; \
   grep -q 'clusters         5' $d/cli_import.out; \
   grep -q cli_import.vdb $d/cli_import.json; \
   test -s $d/cli_import.vdb")
set_tests_properties(cli_import_roundtrip PROPERTIES
  FIXTURES_REQUIRED import_input LABELS "cli;import")

if(SATF_FUZZ AND CMAKE_C_COMPILER_ID MATCHES "Clang")
  foreach(fmt hair tfx)
    add_executable(fuzz_${fmt} ${CMAKE_CURRENT_SOURCE_DIR}/fuzz_${fmt}.c)
    target_compile_options(fuzz_${fmt} PRIVATE -fsanitize=fuzzer,address)
    target_link_options(fuzz_${fmt} PRIVATE -fsanitize=fuzzer,address)
    target_link_libraries(fuzz_${fmt} PRIVATE satf_import satf_warnings)
  endforeach()
endif()
add_test(NAME cli_import_missing_mesh COMMAND satf-import
  ${CMAKE_CURRENT_BINARY_DIR}/rt3.tfx -o ${CMAKE_CURRENT_BINARY_DIR}/never.json
  --mesh ${CMAKE_CURRENT_BINARY_DIR}/no-such-head.ply)
set_tests_properties(cli_import_missing_mesh PROPERTIES WILL_FAIL TRUE
  LABELS "cli;import")
# A per-frame strand sequence becomes an animated scene: frame 1 defines the
# clusters and every frame is re-fitted onto them as keys (4 clusters x 3
# frames).
add_test(NAME cli_import_sequence COMMAND sh -c
  "set -e; d=${CMAKE_CURRENT_BINARY_DIR}; \
   cp $d/rt3.tfx $d/seq_0001.tfx; cp $d/rt3.tfx $d/seq_0002.tfx; \
   cp $d/rt3.tfx $d/seq_0003.tfx; \
   $<TARGET_FILE:satf-import> $d/seq_%04d.tfx --frames 1-3 --fps 12 \
     --clusters 4 -o $d/seq.json -q; \
   grep -q '\"animation\"' $d/seq.json; \
   test $(grep -c '\"frame\"' $d/seq.json) -eq 12")
set_tests_properties(cli_import_sequence PROPERTIES LABELS "cli;import"
                     DEPENDS test_strands)
add_test(NAME cli_import_sequence_needs_pattern COMMAND satf-import
  ${CMAKE_CURRENT_BINARY_DIR}/rt3.tfx --frames 1-3 -o never.json)
set_tests_properties(cli_import_sequence_needs_pattern PROPERTIES
                     WILL_FAIL TRUE LABELS "cli;import")
