#!/bin/sh
# Physical hair under an import's default lights is exposed like Cycles'
# under the same lights: generated sparse strands (scripts/gen-strands.py
# sparse, seed 1: 150 strands lying on a scalp, like Bangs_100) imported
# with the physical material (melanin 0.6), rendered by satf-render's
# default path and by the strand path at 160x120, and compared with
# data/cycles_sparse_160x120.exr: Blender 3.4 Cycles' Principled Hair, 64
# spp, rendering the strands file this import writes at the file's
# thickness (radius 0.15) with the scene's camera and lights
# (../shared/tools/peer_cycles.py --scene, over black, no meshes):
#   blender -b --factory-startup --python peer_cycles.py -- STRANDS.hair \
#     --scene S.json --exr --spp 64 --res 160x120 --melanin 0.6 \
#     --redness 0 --roughness 0.3 --radial-roughness 0.3 --radius 0.15
# Measured: luminance ratio 1.01 and 1.00, chroma 1.7 degrees, IoU 0.80
# (1.19 and 6 degrees with Zinke's back-scattering from hair that is not
# there: strand_fiber.glsl). Held: luminance within 15%, IoU >= 0.75,
# chroma <= 4 degrees. The same frame lit by lights at half their
# intensity must fail.
# usage: exposure.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -eu
build=$1 src=$2 d=$3
bin=$build/bin
rm -rf "$d"
mkdir -p "$d"
ref=$src/tests/tools/data/cycles_sparse_160x120.exr
"$bin/satf-build" -q --kind fiber --samples 12 --angles 12x12 --width 8 \
  --grid 8 --sub-rays 2 -o "$d/fiber.exr" 2>"$d/build.err"
python3 "$src/scripts/gen-strands.py" sparse --seed 1 -q -o "$d/h.hair"
"$bin/satf-import" "$d/h.hair" -o "$d/s.json" --db "$d/fiber.exr" -q \
  --shading physical --melanin 0.6 --redness 0 --roughness 0.3 \
  --radial-roughness 0.3
# the reference's set-up: over black, no meshes; and the lights halved
python3 - "$d" <<'PY'
import json, sys
d = sys.argv[1]
s = json.load(open(d + "/s.json"))
s["background"] = [0, 0, 0]
s.pop("meshes", None)
json.dump(s, open(d + "/black.json", "w"))
for light in s["lights"]:
    light["intensity"] = 0.5 * light.get("intensity", 1.0)
json.dump(s, open(d + "/half.json", "w"))
PY
render() {
  scene=$1
  shift
  "$bin/satf-render" "$d/$scene.json" --size 160x120 -q "$@"
}
keep="--max-lum-error 0.15 --min-iou 0.75 --max-chroma 4"
render black -o "$d/default.exr"
render black --strands -o "$d/strands.exr"
render half -o "$d/half.exr"
# shellcheck disable=SC2086
"$bin/satf-compare" "$ref" "$d/default.exr" $keep
# shellcheck disable=SC2086
"$bin/satf-compare" "$ref" "$d/strands.exr" $keep
# shellcheck disable=SC2086
if "$bin/satf-compare" "$ref" "$d/half.exr" $keep >"$d/half.out"; then
  echo "exposure.sh: the frame under half the light passed" >&2
  exit 1
fi
grep -q FAILED "$d/half.out"
