#!/usr/bin/env bash
# Renders every sample scene into OUT (EXR with AOVs + PNG) and prints the
# paper's Table 1 row for each (a short orbiting-camera benchmark).
# usage: render-samples.sh BUILD_DIR DATABASE OUT_DIR
set -euo pipefail
build=${1:-build}
db=${2:-out/satf-default.hrirdb.exr}
out=${3:-out}
cd "$(dirname "$0")/.."
mkdir -p "$out"
render=$build/online/satf-render
frames=${SATF_BENCH_FRAMES:-20}
for scene in samples/*.json; do
  name=$(basename "$scene" .json)
  "$render" "$scene" --db "$db" -o "$out/$name.exr" --png "$out/$name.png" --aov
done
echo
echo "Table 1 (paper 001) on this machine, 640x480, $frames frames of an orbiting camera:"
first=1
for mode in exact ordered; do
  for scene in samples/*.json; do
    row=$("$render" "$scene" --db "$db" --composite "$mode" --bench "$frames")
    if [ $first = 1 ]; then echo "$row" | head -1 | sed 's/^/composite  /'; first=0; fi
    echo "$row" | tail -1 | sed "s/^/$(printf '%-10s' $mode) /"
  done
done
