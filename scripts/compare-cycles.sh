#!/usr/bin/env bash
# satf's shading against Blender Cycles' Principled Hair (path traced) on
# the shared ponytail: the physical mode and the paper's kk mode, front-lit
# (the importer's key and fill lights) and back-lit, at 640x480 with the
# same camera, lights and material (melanin 0.6, redness 0, roughness 0.3,
# radial roughness 0.3, offset 2, ior 1.55), Cycles drawing the strands at
# the width satf's clusters assume. Prints satf-compare's figures (those of
# ../shared/tools/fidelity.py) and writes reference | satf | difference
# PNGs into OUT_DIR (the README's gallery). Also the strand reference
# (`satf-render --strands`, the same fibre shading on the source strands)
# and a lighter brown (melanin 0.2) front-lit. The strand reference is
# drawn at Cycles' one strand width (twice its radius), as the clusters
# are (the import's --strand-width): against hair of another width SSIM
# measures the widths, not the shading.
# SAMPLES is satf's anti-aliasing (--samples; Cycles filters every pixel
# over its SPP samples): 8 adds 0.02 to the strand reference's SSIM and
# 0.01 to the clusters'. Cycles takes minutes a
# frame: with REF_DIR its frames are kept there and reused by later runs
# of the same strand radius and SPP (delete them when the camera, lights or
# material change). A measuring tool, not a test: it needs `apt-get install
# blender` and the data in ../shared/data/hair.
# usage: compare-cycles.sh [BUILD_DIR] [OUT_DIR] [SPP] [REF_DIR] [SAMPLES]
set -euo pipefail
build=${1:-build}
out=${2:-docs/gallery}
spp=${3:-32}
refs=${4:-}
samples=${5:-1}
cd "$(dirname "$0")/.."
data=../shared/data/hair
peer=../shared/tools/peer_cycles.py
for need in blender "$data/ponytail_tail.tfx" "$peer" out/satf-fiber.hrirdb.exr \
  out/satf-default.hrirdb.exr; do
  if ! command -v "$need" >/dev/null 2>&1 && [ ! -e "$need" ]; then
    echo "compare-cycles: $need is missing (blender: apt-get install blender;" \
      "databases: bash scripts/main.sh)" >&2
    exit 1
  fi
done
bin=$build/bin
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
material=(--redness 0 --roughness 0.3 --radial-roughness 0.3)
[ -n "$refs" ] && mkdir -p "$refs"
refs=${refs:-$work}
# TressFX gives no thickness: satf-import gives each strand twice its
# neighbours' spacing (p10-p90 0.34-1.18 on the ponytail), Cycles draws one
# radius; the scene takes their median for every strand (--strand-width), so
# both renderers draw the same strands
width=$("$bin/satf-import" "$data"/ponytail_*.tfx -o "$work/probe.json" \
  --no-strands 2>/dev/null | sed -n 's/^  strand width *\([0-9.e+-]*\) .*/\1/p')
"$bin/satf-import" "$data"/ponytail_*.tfx -o "$work/pony.json" -q \
  --shading physical --melanin 0.6 "${material[@]}" --strand-width "$width"
# black background (the EXRs are premultiplied over black anyway), and a
# back-lit copy with one light travelling from behind the hair to the camera;
# the strands' median width for Cycles' radius
radius=$(python3 - "$work" <<'PY'
import glob, json, math, struct, sys
w = sys.argv[1]
s = json.load(open(w + "/pony.json"))
s["background"] = [0, 0, 0]
json.dump(s, open(w + "/front.json", "w"))
c = s["camera"]
d = [a - b for a, b in zip(c["position"], c["target"])]
n = math.sqrt(sum(x * x for x in d))
s["lights"] = [{"type": "directional", "color": [1, 1, 1], "intensity": 1,
                "direction": [d[0] / n, d[1] / n - 0.15, d[2] / n]}]
json.dump(s, open(w + "/back.json", "w"))
f = json.load(open(w + "/front.json"))
f["material"]["melanin"] = 0.2
json.dump(f, open(w + "/front_blond.json", "w"))
b = open(glob.glob(w + "/pony.strands-*.hair")[0], "rb").read()
nh, npt, flags = struct.unpack_from("<3I", b, 4)
off = 128 + (2 * nh if flags & 1 else 0) + 12 * npt
th = sorted(struct.unpack_from(f"<{npt}f", b, off)) if flags & 4 else [1.0]
print(th[len(th) // 2] / 2)
PY
)
for light in front back front_blond; do
  melanin=0.6
  [ "$light" = front_blond ] && melanin=0.2
  # a kept frame is reused only for the same strand radius and SPP (the
  # import decides the strands' widths)
  key="radius $radius spp $spp"
  if [ ! -e "$refs/cycles_$light.exr" ] ||
    [ "$(cat "$refs/cycles_$light.txt" 2>/dev/null)" != "$key" ]; then
    blender -b --factory-startup --python "$peer" -- "$data"/ponytail_*.tfx \
      --scene "$work/$light.json" --exr --out "$refs/cycles_$light.exr" \
      --spp "$spp" --threads 2 --radius "$radius" --melanin "$melanin" \
      "${material[@]}" >/dev/null
    echo "$key" >"$refs/cycles_$light.txt"
  fi
  "$bin/satf-render" "$work/$light.json" --db out/satf-fiber.hrirdb.exr -q \
    --samples "$samples" -o "$work/physical_$light.exr"
  "$bin/satf-render" "$work/$light.json" --strands --shading physical -q \
    --strand-width "$(python3 -c "print(2 * $radius)")" \
    --samples "$samples" -o "$work/strands_$light.exr"
  modes=(physical strands)
  if [ "$light" != front_blond ]; then
    "$bin/satf-render" "$work/$light.json" --db out/satf-default.hrirdb.exr -q \
      --shading kk --samples "$samples" -o "$work/kk_$light.exr"
    modes+=(kk)
  fi
  for mode in "${modes[@]}"; do
    echo "== $mode, ${light%_blond}-lit, melanin $melanin, against Cycles ($spp spp," \
      "strand radius $radius), satf $samples samples"
    "$bin/satf-compare" "$refs/cycles_$light.exr" "$work/${mode}_$light.exr" \
      --png "$out/cycles_${mode}_$light.png"
  done
done
