#!/bin/sh
# The Blender add-on end to end: Blender (headless) exports a generated
# groom through the add-on (test_addon.py holds it to Blender's numbers),
# satf-import makes the scene, satf-render renders it to an EXR whose
# layers and camera OpenImageIO reads. Skipped (77) without Blender.
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
"$bin/satf-render" "$d/groom.json" -o "$d/groom.exr" --aov --size 160x120 -q
oiiotool --info -v "$d/groom.exr" > "$d/info"
grep -q 'satf.Combined.R' "$d/info"
grep -q 'worldToCamera' "$d/info"
echo "addon: Blender to EXR in $(( $(date +%s) - start )) s"
