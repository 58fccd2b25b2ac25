#!/bin/sh
# import_killed.sh SATF-IMPORT INPUT DIR - publishing under real kills:
# satf-import is killed with SIGKILL at 16 moments from 45% to 120% of a
# full run's duration, re-importing over the same scene each time (other
# seeds, so other side files). After every kill the scene on disk must name
# only side files that exist; a last full run leaves no temporary files.
set -e
imp=$1; in=$2; dir=$3
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir"
# Every side file the scene names exists and holds the bytes its name was
# published for (the 8 hex digits before the extension are their FNV-1a).
check() {
  for f in $(grep -o '"[^"]*\.\(vdb\|hair\)"' s.json | tr -d '"' | sort -u); do
    test -s "$f" || { echo "after a kill at $1 ms: s.json names $f, which is missing"; exit 1; }
    python3 -c '
import sys
name = sys.argv[1]
h = 2166136261
for b in open(name, "rb").read():
    h = ((h ^ b) * 16777619) & 0xffffffff
sys.exit(0 if name.rsplit(".", 1)[0].endswith("-%08x" % h) else 1)' "$f" ||
      { echo "after a kill at $1 ms: $f does not hold the bytes it was published with"; exit 1; }
  done
}
t0=$(date +%s%N)
"$imp" "$in" -o s.json --vdb h.vdb --follow 3 --clusters 5 -q --seed 1
t1=$(date +%s%N)
full=$(( (t1 - t0) / 1000000 ))
i=0
while [ $i -lt 16 ]; do
  i=$((i + 1))
  ms=$(( full * (40 + 5 * i) / 100 ))
  "$imp" "$in" -o s.json --vdb h.vdb --follow 3 --clusters 5 -q --seed $((i + 1)) &
  pid=$!
  sleep "$(printf '%d.%03d' $((ms / 1000)) $((ms % 1000)))"
  kill -9 $pid 2>/dev/null || true
  wait $pid 2>/dev/null || true
  check $ms
done
"$imp" "$in" -o s.json --vdb h.vdb --follow 3 --clusters 5 -q --seed 99
check end
if ls ./*.tmp-* >/dev/null 2>&1; then echo "temporary files left:"; ls ./*.tmp-*; exit 1; fi
echo "full run $full ms; 16 kills; every scene named only existing files"
