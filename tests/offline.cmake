satf_unit_test(test_sector SOURCES test_sector.c LIBS satf_offline)
satf_unit_test(test_trace SOURCES test_trace.c LIBS satf_offline)

# Command-line validation: each must exit non-zero with a message.
# One case per entry; "|" separates the arguments of a case.
set(satf_build_bad
  "--samples|0" "--samples|abc" "--samples|12x" "--angles|0" "--angles|8x0"
  "--width|1" "--grid|3" "--seed|-4" "--threads|-1" "--extinction|nan"
  "--bogus" "--samples")
set(i 0)
foreach(case IN LISTS satf_build_bad)
  math(EXPR i "${i}+1")
  string(REPLACE "|" ";" args "${case}")
  add_test(NAME cli_build_rejects_${i}
           COMMAND satf-build ${args} -o ${CMAKE_CURRENT_BINARY_DIR}/never.exr)
  set_tests_properties(cli_build_rejects_${i} PROPERTIES WILL_FAIL TRUE LABELS cli)
endforeach()
add_test(NAME cli_build_needs_output COMMAND satf-build --samples 2)
set_tests_properties(cli_build_needs_output PROPERTIES WILL_FAIL TRUE LABELS cli)
add_test(NAME cli_build_help COMMAND satf-build --help)
set_tests_properties(cli_build_help PROPERTIES PASS_REGULAR_EXPRESSION
                     "--samples N.*--threads N" LABELS cli)
