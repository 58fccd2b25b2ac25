#!/bin/sh
# The Blender add-on end to end: Blender (headless) exports a generated
# groom through the add-on (test_addon.py holds it to Blender's numbers),
# satf-import makes the scene, satf-render renders it to an EXR whose
# layers and camera OpenImageIO reads and whose view layer and passes
# Blender's compositor offers (check_exr.py). Skipped (77) without Blender.
# usage: addon.sh SOURCE_DIR BUILD_BIN WORK_DIR
set -eu
src=$1 bin=$2 d=$3
command -v blender > /dev/null || { echo "no blender: skipped"; exit 77; }
rm -rf "$d"
mkdir -p "$d"
export PATH="$bin:$PATH"
start=$(date +%s)
blender -b --factory-startup --python-exit-code 1 \
  --python "$src/tests/blender/test_addon.py" -- "$src/tools/blender" "$d" \
  > "$d/blender.log" 2>&1 || { tail -20 "$d/blender.log"; exit 1; }
grep 'test_addon: 60 strands' "$d/blender.log"
grep 'test_addon: a Curves object' "$d/blender.log"
# a tiny database of its own: a fresh clone has none in out/ or installed
"$bin/satf-build" -q --samples 24 --angles 8x8 --width 16 --grid 8 \
  -o "$d/tiny.hrirdb.exr"
"$bin/satf-render" "$d/groom.json" --db "$d/tiny.hrirdb.exr" -o "$d/groom.exr" \
  --aov --size 160x120 -q
oiiotool --info -v "$d/groom.exr" > "$d/info"
grep -q 'satf.Combined.R' "$d/info"
grep -q 'satf.Depth.Z' "$d/info"
grep -q 'worldToCamera' "$d/info"
grep -q 'worldToNDC' "$d/info"
blender -b --factory-startup --python-exit-code 1 \
  --python "$src/tests/blender/check_exr.py" -- "$d/groom.exr" \
  > "$d/exr.log" 2>&1 || { tail -20 "$d/exr.log"; exit 1; }
if grep -q 'matches no enum' "$d/exr.log"; then
  cat "$d/exr.log"
  exit 1
fi
echo "addon: Blender to EXR in $(( $(date +%s) - start )) s"
