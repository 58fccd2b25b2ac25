#!/bin/sh
# mpi_killed.sh MPIRUN SATF-BUILD DIR - a rank of an MPI build
# killed with SIGKILL mid-build must end the job with a non-zero status and
# leave no database and no temporary file at the output path. Rank 1 is
# found among the children of this script's own mpirun (never by name).
# Then an output rank 0 cannot write (a directory in the way) must fail
# the job before it builds, with the path named.
set -e
mpirun=$1; build=$(realpath "$2"); dir=$3
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir"
# the default build: a minute or more on this machine, killed after ~1 s
"$mpirun" --oversubscribe --allow-run-as-root -np 3 "$build" --threads 1 \
  -o db.exr > out.txt 2> err.txt &
job=$!
# rank 1: the child of this job's mpirun whose environment says so
rank1=""
i=0
while [ -z "$rank1" ] && [ $i -lt 200 ]; do
  for pid in $(ps -o pid= --ppid "$job"); do
    if tr '\0' '\n' < "/proc/$pid/environ" 2>/dev/null |
       grep -qx 'OMPI_COMM_WORLD_RANK=1'; then
      rank1=$pid
    fi
  done
  i=$((i + 1))
  [ -n "$rank1" ] || sleep 0.05
done
[ -n "$rank1" ] || { echo "rank 1 never started"; kill $job; exit 1; }
sleep 1
kill -9 "$rank1"
status=0
wait $job || status=$?
[ $status -ne 0 ] || { echo "the job succeeded although rank 1 was killed"; exit 1; }
if [ -e db.exr ]; then echo "a database was left at the output path"; exit 1; fi
if ls ./*.tmp* >/dev/null 2>&1; then echo "temporary files left:"; ls ./*.tmp*; exit 1; fi
echo "rank 1 (pid $rank1) killed: job status $status, no database"

# an output that cannot be written: a directory stands at the output path
mkdir in-the-way.exr
status=0
"$mpirun" --oversubscribe --allow-run-as-root -np 3 "$build" -q --samples 6 \
  --angles 4 --width 8 --grid 8 -o in-the-way.exr 2> err.txt || status=$?
[ $status -ne 0 ] || { echo "the job succeeded although rank 0 could not write"; exit 1; }
grep -q 'in-the-way.exr' err.txt || { cat err.txt; exit 1; }
test -d in-the-way.exr
if ls ./*.tmp* >/dev/null 2>&1; then echo "temporary files left:"; ls ./*.tmp*; exit 1; fi
echo "rank 0 could not write: job status $status"
