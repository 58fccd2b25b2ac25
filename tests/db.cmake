satf_unit_test(test_features SOURCES test_features.c LIBS satf_db)
satf_unit_test(test_db SOURCES test_db.c LIBS satf_offline)
satf_unit_test(test_db_file SOURCES test_db_file.c fuzz_db.c LIBS satf_offline)
target_compile_definitions(test_db_file PRIVATE SATF_FUZZ_NO_MAIN)
if(SATF_FUZZ)
  add_executable(fuzz_db fuzz_db.c)
  target_compile_options(fuzz_db PRIVATE -fsanitize=fuzzer,address)
  target_link_options(fuzz_db PRIVATE -fsanitize=fuzzer,address)
  target_link_libraries(fuzz_db PRIVATE satf_db)
endif()

add_test(NAME cli_db_help COMMAND satf-db --help)
set_tests_properties(cli_db_help PROPERTIES PASS_REGULAR_EXPRESSION "verify FILE" LABELS cli)
add_test(NAME cli_db_missing_file COMMAND satf-db info ${CMAKE_CURRENT_BINARY_DIR}/no-such.exr)
set_tests_properties(cli_db_missing_file PROPERTIES WILL_FAIL TRUE LABELS cli)
add_test(NAME cli_db_unknown_command COMMAND satf-db frobnicate x)
set_tests_properties(cli_db_unknown_command PROPERTIES WILL_FAIL TRUE LABELS cli)
# Build a tiny database, then verify, inspect, export and query it.
add_test(NAME cli_db_roundtrip COMMAND sh -c
  "set -e; d=${CMAKE_CURRENT_BINARY_DIR}/cli_tiny.exr; \
   $<TARGET_FILE:satf-build> -q --samples 6 --angles 4x3 --width 8 --grid 8 -o $d; \
   $<TARGET_FILE:satf-db> verify $d; \
   $<TARGET_FILE:satf-db> info $d | grep -q '6 sectors'; \
   $<TARGET_FILE:satf-db> atlas $d -o ${CMAKE_CURRENT_BINARY_DIR}/cli_atlas.exr; \
   $<TARGET_FILE:satf-db> lookup $d --rho 0.3,0.5,0.5 --view 10 --light 20 | grep -c . | grep -qx 9; \
   head -c -200 $d > $d.cut; \
   if $<TARGET_FILE:satf-db> verify $d.cut 2>/dev/null; then exit 1; fi")
set_tests_properties(cli_db_roundtrip PROPERTIES LABELS cli)

# Benchmark, not a test: run build/tests/bench_db [SAMPLES].
add_executable(bench_db bench_db.c)
target_link_libraries(bench_db PRIVATE satf_offline satf_warnings)
