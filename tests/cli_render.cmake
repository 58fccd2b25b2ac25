# Command-line tests of satf-render and satf-view (part "renderer").
#
# satf_render_cli(NAME CODE REGEX ARGS...): runs satf-render ARGS, passes
# when it exits with CODE and its output (stdout + stderr) matches the
# extended regular expression REGEX.
set(satf_cli_dir ${CMAKE_CURRENT_BINARY_DIR}/cli_render)
file(MAKE_DIRECTORY ${satf_cli_dir})
set(satf_expect_sh [=[
code=$1; re=$2; shift 2
out=$("$@" 2>&1); rc=$?
printf '%s\n' "$out"
if [ "$rc" -ne "$code" ]; then echo "exit status $rc, expected $code"; exit 1; fi
if ! printf '%s\n' "$out" | grep -E -q -- "$re"; then echo "output does not match: $re"; exit 1; fi
]=])
function(satf_render_cli name code regex)
  add_test(NAME ${name} COMMAND sh -c "${satf_expect_sh}" sh ${code} "${regex}"
           $<TARGET_FILE:satf-render> ${ARGN})
  set_tests_properties(${name} PROPERTIES LABELS "cli;render")
endfunction()

# Inputs written at configure time: a malformed scene, a valid one, and a
# file that is not a database.
file(WRITE ${satf_cli_dir}/malformed.json "{\"macro_clusters\": [\n  {\"prototype\": }\n")
file(WRITE ${satf_cli_dir}/tiny.json
  "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0, -2, 0], [0, 2, 0]],"
  " \"a\": 0.6, \"shell\": {\"layers\": 3, \"st\": 8, \"su\": 8}}}],"
  " \"camera\": {\"position\": [0, 0, 10], \"target\": [0, 0, 0]}}\n")
file(WRITE ${satf_cli_dir}/not-a-db.exr "this is not an OpenEXR file\n")
set(satf_cli_db ${satf_cli_dir}/tiny.hrirdb.exr)

satf_render_cli(cli_render_help 0 "usage: satf-render SCENE\\.json" --help)
satf_render_cli(cli_render_no_scene 2 "no scene given" -o ${satf_cli_dir}/x.exr)
satf_render_cli(cli_render_unknown_option 2 "unknown option '--frobnicate'"
                ${satf_cli_dir}/tiny.json --frobnicate)
satf_render_cli(cli_render_nothing_to_do 2 "nothing to do"
                ${satf_cli_dir}/tiny.json)
satf_render_cli(cli_render_bad_size 2 "--size: expected WIDTHxHEIGHT, got '640'"
                ${satf_cli_dir}/tiny.json --size 640 -o ${satf_cli_dir}/x.exr)
satf_render_cli(cli_render_size_range 2 "--size: 0 is out of range"
                ${satf_cli_dir}/tiny.json --size 0x480 -o ${satf_cli_dir}/x.exr)
satf_render_cli(cli_render_size_garbage 2 "--size: expected an integer"
                ${satf_cli_dir}/tiny.json --size 64xabc -o ${satf_cli_dir}/x.exr)
satf_render_cli(cli_render_missing_value 2 "--db needs a value"
                ${satf_cli_dir}/tiny.json -o ${satf_cli_dir}/x.exr --db)
satf_render_cli(cli_render_missing_scene 1 "no-such-scene\\.json"
                ${satf_cli_dir}/no-such-scene.json -o ${satf_cli_dir}/x.exr)
satf_render_cli(cli_render_malformed_scene 1 "malformed\\.json:2:[0-9]+: "
                ${satf_cli_dir}/malformed.json -o ${satf_cli_dir}/x.exr)
satf_render_cli(cli_render_no_database 1 "no database"
                ${satf_cli_dir}/tiny.json -o ${satf_cli_dir}/x.exr)
satf_render_cli(cli_render_missing_database 1 "no-such-db\\.exr"
                ${satf_cli_dir}/tiny.json --db ${satf_cli_dir}/no-such-db.exr
                -o ${satf_cli_dir}/x.exr)
satf_render_cli(cli_render_not_a_database 1 "not-a-db\\.exr: .*OpenEXR"
                ${satf_cli_dir}/tiny.json --db ${satf_cli_dir}/not-a-db.exr
                -o ${satf_cli_dir}/x.exr)

# A tiny database shared by the round trips (a fixture: built first).
add_test(NAME cli_render_build_db
         COMMAND satf-build -q --samples 24 --angles 8x8 --width 16 --grid 8
                 -o ${satf_cli_db})
set_tests_properties(cli_render_build_db PROPERTIES LABELS "cli;render"
                     FIXTURES_SETUP satf_render_db)

# Full round trip on a sample scene: EXR with AOVs and a PNG, both written.
add_test(NAME cli_render_roundtrip COMMAND sh -c
  "set -e; d=${satf_cli_dir}; rm -f $d/rt.exr $d/rt.png; \
   $<TARGET_FILE:satf-render> ${CMAKE_SOURCE_DIR}/samples/cluster_6c.json \
     --db ${satf_cli_db} --size 160x120 -o $d/rt.exr --png $d/rt.png --aov; \
   test -s $d/rt.exr; test -s $d/rt.png; \
   head -c 4 $d/rt.exr | od -An -tx1 | grep -q '76 2f 31 01'; \
   head -c 8 $d/rt.png | od -An -tx1 | grep -q '89 50 4e 47 0d 0a 1a 0a'")
set_tests_properties(cli_render_roundtrip PROPERTIES LABELS "cli;render"
                     FIXTURES_REQUIRED satf_render_db)
# Every effect switch of Fig. 4 at once, PNG only.
add_test(NAME cli_render_ablations COMMAND sh -c
  "set -e; d=${satf_cli_dir}; rm -f $d/ab.png; \
   $<TARGET_FILE:satf-render> ${satf_cli_dir}/tiny.json --db ${satf_cli_db} \
     --size 64x48 --png $d/ab.png --no-satf --no-secondary --no-self-shadow \
     --no-cluster-shadows -q; \
   test -s $d/ab.png")
set_tests_properties(cli_render_ablations PROPERTIES LABELS "cli;render"
                     FIXTURES_REQUIRED satf_render_db)

# The viewer's window against the headless renderer: the same scene and size
# must give the same picture (the viewer's frame goes through its sRGB
# display pass and an 8-bit back buffer, hence 2/255).
find_program(SATF_XVFB_RUN xvfb-run)
find_package(PNG)
if(SATF_XVFB_RUN AND PNG_FOUND)
  add_executable(png_compare png_compare.c)
  target_link_libraries(png_compare PRIVATE PNG::PNG satf_warnings)
  add_test(NAME cli_view_matches_render COMMAND sh -c
    "set -e; d=${satf_cli_dir}; s=${CMAKE_SOURCE_DIR}/samples/cluster_6c.json; \
     rm -f $d/view.png $d/render.png; \
     ${SATF_XVFB_RUN} -a $<TARGET_FILE:satf-view> $s --db ${satf_cli_db} \
       --size 160x120 --screenshot $d/view.png --frames 2; \
     $<TARGET_FILE:satf-render> $s --db ${satf_cli_db} --size 160x120 \
       --png $d/render.png -q; \
     $<TARGET_FILE:png_compare> $d/view.png $d/render.png 2")
  set_tests_properties(cli_view_matches_render PROPERTIES
                       LABELS "xvfb;render;cli" FIXTURES_REQUIRED satf_render_db)
  if(SATF_SANITIZE)
    # glfwTerminate unloads Mesa's GLX driver, whose still-referenced
    # allocations LeakSanitizer then reports from "<unknown module>".
    set_tests_properties(cli_view_matches_render PROPERTIES
                         ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
  endif()
endif()
