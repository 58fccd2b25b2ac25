#!/bin/sh
# Frames the scene does not have (anim_8 has 1-48), or a range that runs
# backwards, are refused before anything is written.
# Usage: frames_outside.sh BIN_DIR SOURCE_DIR WORK_DIR
set -eu
bin=$1 src=$2 d=$3
rm -rf "$d"; mkdir -p "$d"
"$bin/satf-build" -q --samples 16 --angles 8 --width 16 --grid 8 -o "$d/db.exr"
for f in -5--1 47-49 5-3; do
  if "$bin/satf-render" "$src/samples/anim_8.json" --db "$d/db.exr" \
    --size 32x24 --frames "$f" -o "$d/f_%04d.exr" -q 2>"$d/err"; then
    echo "--frames $f accepted"
    exit 1
  fi
  grep -q "within the scene's frames 1-48" "$d/err" || { cat "$d/err"; exit 1; }
done
if ls "$d" | grep -q '^f_'; then
  echo "frames were written"; exit 1
fi
