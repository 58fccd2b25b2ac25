# MPI and shard tests, included by CMakeLists.txt when CMake
# found MPI: they run with Open MPI's mpirun on this one machine, 3 ranks
# oversubscribed, as root in CI.
set(mpi_dir ${CMAKE_CURRENT_BINARY_DIR}/cli_mpi)
set(mpirun "${MPIEXEC_EXECUTABLE} --oversubscribe --allow-run-as-root -np 3")
set(mpi_env "OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMPI_MCA_rmaps_base_oversubscribe=1")
set(mpi_build $<TARGET_FILE:satf-build> -q --samples 24 --angles 8x6 --width 16 --grid 8 --seed 5)
string(REPLACE ";" " " mpi_build "${mpi_build}")

# The database of one process, of 3 ranks (1 and 2 threads each), of 3
# ranks with more ranks than some have samples, and of 3 and 5 merged
# shards (given in any order): the same bytes; fibre records too.
add_test(NAME mpi_build_identity COMMAND sh -c
  "set -e; d=${mpi_dir}/identity; rm -rf $d; mkdir -p $d; \
   ${mpi_build} --threads 2 -o $d/one.exr; \
   ${mpirun} ${mpi_build} --threads 1 -o $d/mpi1.exr; \
   ${mpirun} ${mpi_build} --threads 2 -o $d/mpi2.exr; \
   cmp $d/one.exr $d/mpi1.exr; cmp $d/one.exr $d/mpi2.exr; \
   ${mpi_build} --samples 2 -o $d/two.exr; \
   ${mpirun} ${mpi_build} --samples 2 -o $d/two_mpi.exr; \
   cmp $d/two.exr $d/two_mpi.exr; \
   for i in 0 1 2; do ${mpi_build} --shard $i/3 -o $d/part3_$i.exr; done; \
   $<TARGET_FILE:satf-db> merge $d/part3_2.exr $d/part3_0.exr $d/part3_1.exr \
     -o $d/merged3.exr | grep -q 'merged 3 shards'; \
   cmp $d/one.exr $d/merged3.exr; \
   for i in 0 1 2 3 4; do ${mpi_build} --threads 1 --shard $i/5 -o $d/part5_$i.exr; done; \
   $<TARGET_FILE:satf-db> merge $d/part5_*.exr -o $d/merged5.exr; \
   cmp $d/one.exr $d/merged5.exr; \
   if cmp -s $d/part3_0.exr $d/part5_0.exr; then exit 1; fi; \
   $<TARGET_FILE:satf-db> verify $d/mpi1.exr; \
   f='--kind fiber --samples 6 --angles 4x4 --width 8 --sub-rays 2'; \
   ${mpi_build} $f -o $d/fib1.exr; \
   ${mpirun} ${mpi_build} $f --threads 1 -o $d/fib3.exr; \
   ${mpi_build} $f --shard 0/2 -o $d/fibp0.exr; \
   ${mpi_build} $f --shard 1/2 -o $d/fibp1.exr; \
   $<TARGET_FILE:satf-db> merge $d/fibp1.exr $d/fibp0.exr -o $d/fibm.exr; \
   cmp $d/fib1.exr $d/fib3.exr; cmp $d/fib1.exr $d/fibm.exr")
set_tests_properties(mpi_build_identity PROPERTIES LABELS "cli;mpi"
                     ENVIRONMENT "${mpi_env}")

# The summary and the progress come from rank 0 alone.
add_test(NAME mpi_build_one_summary COMMAND sh -c
  "set -e; d=${mpi_dir}/summary; rm -rf $d; mkdir -p $d; \
   ${mpirun} $<TARGET_FILE:satf-build> --samples 12 --angles 4 --width 8 \
     --grid 8 -o $d/db.exr > $d/out.txt 2> $d/err.txt; \
   test $(grep -c 'wrote' $d/out.txt) = 1; \
   grep -q '3 ranks x' $d/out.txt; \
   test $(grep -c '^satf-build: 12 sectors' $d/err.txt) = 1")
set_tests_properties(mpi_build_one_summary PROPERTIES LABELS "cli;mpi"
                     ENVIRONMENT "${mpi_env}")

# satf-db verify describes a shard and refuses a truncated one; satf-db
# merge refuses a missing, a duplicated, a foreign (other seed, other shard
# count), a truncated shard and a database given as a shard, naming the
# file, and writes nothing; --shard is refused under mpirun.
add_test(NAME mpi_merge_rejects COMMAND sh -c
  "d=${mpi_dir}/rejects; rm -rf $d; mkdir -p $d; \
   for i in 0 1 2; do ${mpi_build} --shard $i/3 -o $d/p$i.exr || exit 1; done; \
   ${mpi_build} --seed 6 --shard 1/3 -o $d/seed6.exr || exit 1; \
   ${mpi_build} --shard 1/4 -o $d/of4.exr || exit 1; \
   ${mpi_build} -o $d/whole.exr || exit 1; \
   $<TARGET_FILE:satf-db> verify $d/p1.exr | grep -q 'shard 1/3: samples 8..15 of a 24-sample build' || exit 1; \
   head -c 2000 $d/p1.exr > $d/cut.exr; \
   if $<TARGET_FILE:satf-db> verify $d/cut.exr; then exit 1; fi; \
   refuse() { want=$1; shift; \
     if $<TARGET_FILE:satf-db> merge \"$@\" -o $d/out.exr 2> $d/err.txt; then \
       echo \"merge $* was accepted\"; exit 1; fi; \
     grep -q \"$want\" $d/err.txt || { echo \"no '$want' in:\"; cat $d/err.txt; exit 1; }; \
     test ! -e $d/out.exr || { echo 'merge left out.exr'; exit 1; }; }; \
   refuse 'shard 1/3 is missing' $d/p0.exr $d/p2.exr; \
   refuse 'p1.exr: shard 1/3 again' $d/p0.exr $d/p1.exr $d/p1.exr $d/p2.exr; \
   refuse 'seed6.exr: a shard of another build' $d/p0.exr $d/seed6.exr $d/p2.exr; \
   refuse 'of4.exr: shard 1/4' $d/p0.exr $d/of4.exr $d/p2.exr; \
   refuse 'cut.exr' $d/p0.exr $d/cut.exr $d/p2.exr; \
   refuse 'whole.exr: an OpenEXR image, but not an satf database shard' \
     $d/whole.exr; \
   if ${mpirun} ${mpi_build} --shard 0/3 -o $d/x.exr 2> $d/err.txt; then exit 1; fi; \
   grep -q 'under mpirun leave it out' $d/err.txt; \
   if ${mpi_build} --shard 3/3 -o $d/x.exr; then exit 1; fi; \
   test ! -e $d/x.exr")
set_tests_properties(mpi_merge_rejects PROPERTIES LABELS "cli;mpi"
                     ENVIRONMENT "${mpi_env}")

# A rank killed with SIGKILL mid-build ends the job with a failure and no
# database (nor temporary file) at the output path; so does a rank 0 that
# cannot write.
add_test(NAME mpi_build_rank_killed COMMAND sh
         ${CMAKE_CURRENT_SOURCE_DIR}/mpi_killed.sh ${MPIEXEC_EXECUTABLE}
         $<TARGET_FILE:satf-build> ${mpi_dir}/killed)
set_tests_properties(mpi_build_rank_killed PROPERTIES LABELS "cli;mpi"
                     ENVIRONMENT "${mpi_env}" TIMEOUT 120)

# Batch frames across 3 ranks are the one-process frames byte for byte;
# --resume under mpirun renders only what is missing; the contact sheet
# comes from rank 0.
add_test(NAME mpi_frames_identity COMMAND sh -c
  "set -e; d=${mpi_dir}/frames; rm -rf $d; mkdir -p $d/one $d/mpi; \
   ${mpi_build} --samples 16 -o $d/db.exr; \
   r=\"$<TARGET_FILE:satf-render> ${CMAKE_SOURCE_DIR}/samples/anim_8.json \
     --db $d/db.exr --size 96x72 --frames 1-5\"; \
   $r -q -o $d/one/f_%04d.exr; \
   ${mpirun} $r -o $d/mpi/f_%04d.exr --contact-sheet $d/mpi/sheet.png \
     > $d/out.txt; \
   test $(grep -c 'frames 1-5: 5 rendered' $d/out.txt) = 1; \
   for f in 1 2 3 4 5; do cmp $d/one/f_000$f.exr $d/mpi/f_000$f.exr; done; \
   test -s $d/mpi/sheet.png; \
   rm $d/mpi/f_0002.exr $d/mpi/f_0004.exr; \
   ${mpirun} $r -o $d/mpi/f_%04d.exr --resume \
     | grep -q '2 rendered, 3 already complete'; \
   for f in 1 2 3 4 5; do cmp $d/one/f_000$f.exr $d/mpi/f_000$f.exr; done; \
   if ${mpirun} $r -q --bench 2 2> $d/err.txt; then exit 1; fi; \
   grep -q 'ranks share the frames' $d/err.txt")
set_tests_properties(mpi_frames_identity PROPERTIES LABELS "cli;mpi"
                     ENVIRONMENT "${mpi_env}"
                     FIXTURES_REQUIRED satf_head_mesh)
