#!/usr/bin/env bash
# Renders every sample scene into OUT (EXR with AOVs + PNG), an animated
# sample as a short sequence with a contact sheet, and prints the paper's
# Table 1 row for each sample (a short benchmark: an orbiting camera, or the
# animation itself).
# With a fibre database (FIBER_DATABASE, default out/satf-fiber.hrirdb.exr
# when it exists) the still samples are also rendered with the physical
# shading (NAME_physical.png) and their Table 1 rows printed in that mode.
# usage: render-samples.sh BUILD_DIR DATABASE OUT_DIR [FIBER_DATABASE]
set -euo pipefail
build=${1:-build}
db=${2:-out/satf-default.hrirdb.exr}
out=${3:-out}
fdb=${4:-out/satf-fiber.hrirdb.exr}
cd "$(dirname "$0")/.."
mkdir -p "$out"
# The head-based samples name "../out/head.obj" (relative to samples/),
# whatever OUT_DIR is: write it when it is missing.
[ -s out/head.obj ] || python3 scripts/gen-head.py out/head.obj
render=$build/bin/satf-render
frames=${SATF_BENCH_FRAMES:-20}
for scene in samples/*.json; do
  name=$(basename "$scene" .json)
  if grep -q '"animation"' "$scene"; then
    mkdir -p "$out/$name"
    "$render" "$scene" --db "$db" --frames ${SATF_ANIM_FRAMES:-1-24} \
      -o "$out/$name/frame_%04d.exr" --contact-sheet "$out/${name}_contact.png"
  else
    "$render" "$scene" --db "$db" -o "$out/$name.exr" --png "$out/$name.png" --aov
    if [ -s "$fdb" ]; then
      "$render" "$scene" --db "$fdb" --shading physical -q \
        -o "$out/${name}_physical.exr" --png "$out/${name}_physical.png"
    fi
  fi
done
echo
echo "Table 1 (SATF, Xu et al. 2006) on this machine, 640x480, $frames frames each"
echo "(under each row: fragments of the exact composite, look-ups of a frame"
echo "after a move and of a still one):"
first=1
modes="exact ordered"
[ -s "$fdb" ] && modes="$modes physical"
for mode in $modes; do
  for scene in samples/*.json; do
    # satf-render --bench prints the header, the row, then the fragments line
    if [ "$mode" = physical ]; then
      row=$("$render" "$scene" --db "$fdb" --shading physical --bench "$frames" -q)
    else
      row=$("$render" "$scene" --db "$db" --composite "$mode" --bench "$frames" -q)
    fi
    if [ $first = 1 ]; then # the machine, then the header
      echo "$row" | grep '^GL ' || true
      echo "$row" | sed -n 1p | sed 's/^/composite  /'
      first=0
    fi
    echo "$row" | sed -n 2p | sed "s/^/$(printf '%-10s' $mode) /"
    echo "$row" | sed -n 3p | sed 's/^/             /'
  done
done
