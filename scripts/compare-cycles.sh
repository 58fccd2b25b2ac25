#!/usr/bin/env bash
# satf against Blender Cycles' Principled Hair (path traced) on what the
# hair looks like: Cycles renders exactly the strands satf imported (the
# strands file satf-import writes beside the scene, followers included) at
# a hair fibre's radius, 5e-4 of the strands' bounding-box diagonal (the
# default of ../shared/tools/peer_cycles.py), with the same camera and
# lights and the physical shading on both sides (melanin 0.6, redness 0,
# roughness 0.3, radial roughness 0.3). The hairs: the shared ponytail and
# Bangs_100, and generated fur (40K strands of 4 points), curls and a
# straight curtain (20K strands). For the generated ones the ceiling is
# Cycles rendering the same generator with --seed 2 against the --seed 1
# frame (for the ponytail: its TressFX followers placed with satf-import
# --seed 2): different random strands of the same statistics, what no
# method but drawing the same strands can beat (SSIM4 is the figure to
# read).
# Prints satf-compare's figures (IoU, SSIM, SSIM4, luminance, chroma; those
# of ../shared/tools/fidelity.py) and the import's shells line and time,
# and writes reference | satf | difference PNGs into OUT_DIR (the README's
# gallery): cycles_HAIR.png. Also satf's own strand path (`satf-render
# --strands`, every fibre drawn as a strand) against the same Cycles frame
# and against satf's shells: the first measures the picture, the second
# the shells alone. The ponytail is also rendered back-lit, and with the
# paper's kk shading (the default database), as before.
# RES and SPP default to the reference's 640x480 and 64 spp; Cycles takes
# minutes a frame on two cores: with REF_DIR its frames are kept there and
# reused by later runs of the same strands file, size and SPP (delete them
# when the camera, lights or material change). A measuring tool, not a
# test: it needs `apt-get install blender` and ../shared/data/hair
# (SATF_SHARED names another place for ../shared).
# usage: compare-cycles.sh [BUILD_DIR] [OUT_DIR] [SPP] [REF_DIR] [SAMPLES]
#        [RES] [HAIRS]   (HAIRS: a space-separated subset of
#        "ponytail bangs fur curls straight")
# Environment: SATF_RENDER_ARGS, more options for satf's cluster renders
# (e.g. "--composite exact" to measure that mode); SATF_IMPORT_ARGS, more
# options for satf-import (e.g. "--quality high" or "--clusters 600": how
# the clustering changes the picture; the strands file, so Cycles' frame,
# stays the same).
set -euo pipefail
build=${1:-build}
out=${2:-docs/gallery}
spp=${3:-64}
refs=${4:-}
samples=${5:-1}
res=${6:-640x480}
hairs=${7:-ponytail bangs fur curls straight}
read -r -a extra <<<"${SATF_RENDER_ARGS:-}"
read -r -a import_extra <<<"${SATF_IMPORT_ARGS:-}"
cd "$(dirname "$0")/.."
shared=${SATF_SHARED:-../shared} # where the shared data and tools are
data=$shared/data/hair
peer=$shared/tools/peer_cycles.py
kk=
case " $hairs " in *" ponytail "*) kk=out/satf-default.hrirdb.exr ;; esac
for need in blender "$data/ponytail_tail.tfx" "$data/Bangs_100.hair" "$peer" \
  out/satf-fiber.hrirdb.exr $kk; do
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

# cycles NAME SCENE STRANDS MELANIN: Cycles' frame of STRANDS under SCENE's
# camera and lights into $refs/NAME.exr, kept while the strands file, size
# and SPP stay the same
cycles() {
  local key
  key="$(cksum <"$3" | cut -d' ' -f1) $res $spp $4"
  if [ ! -e "$refs/$1.exr" ] || [ "$(cat "$refs/$1.txt" 2>/dev/null)" != "$key" ]; then
    blender -b --factory-startup --python "$peer" -- "$3" --scene "$2" --exr \
      --out "$refs/$1.exr" --spp "$spp" --res "$res" --threads 2 \
      --melanin "$4" "${material[@]}" | grep '^cycles:' || true
    echo "$key" >"$refs/$1.txt"
  fi
}

# scene_copy IN OUT [back]: IN over black without meshes (the EXRs are
# premultiplied over black anyway); "back": one light travelling from behind
# the hair to the camera; prints the strands file's absolute path
scene_copy() {
  python3 - "$@" <<'PY'
import json, math, os, sys
src, dst = sys.argv[1], sys.argv[2]
s = json.load(open(src))
s["background"] = [0, 0, 0]
s.pop("meshes", None)
base = os.path.dirname(os.path.abspath(src))
for k in ("strands", "database", "vdb"):
    if isinstance(s.get(k), str) and not os.path.isabs(s[k]):
        s[k] = os.path.join(base, s[k])
if len(sys.argv) > 3 and sys.argv[3] == "back":
    c = s["camera"]
    d = [a - b for a, b in zip(c["position"], c["target"])]
    n = math.sqrt(sum(x * x for x in d))
    s["lights"] = [{"type": "directional", "color": [1, 1, 1], "intensity": 1,
                    "direction": [d[0] / n, d[1] / n - 0.15, d[2] / n]}]
json.dump(s, open(dst, "w"))
print(s["strands"])
PY
}

compare() { # compare TITLE REF TEST PNG
  echo "== $1"
  "$bin/satf-compare" "$2" "$3" ${4:+--png "$4"} | grep -E 'IoU|SSIM|ratio|chroma'
}

for hair in $hairs; do
  seed2=
  case $hair in
  ponytail) inputs=("$data"/ponytail_*.tfx) ;;
  bangs) inputs=("$data/Bangs_100.hair") ;;
  fur | curls | straight)
    gen=(fur --strands 40000 --points 4)
    [ "$hair" = curls ] && gen=(curls)
    [ "$hair" = straight ] && gen=(straight --strands 20000 --points 32)
    python3 scripts/gen-strands.py "${gen[@]}" -q -o "$work/$hair.hair"
    python3 scripts/gen-strands.py "${gen[@]}" -q --seed 2 -o "$work/$hair.seed2.hair"
    inputs=("$work/$hair.hair")
    seed2=$work/$hair.seed2.hair
    ;;
  *) echo "compare-cycles: unknown hair $hair" >&2 && exit 2 ;;
  esac
  "$bin/satf-import" "${inputs[@]}" -o "$work/$hair.json" --shading physical \
    --melanin 0.6 "${material[@]}" ${import_extra[@]+"${import_extra[@]}"} 2>/dev/null |
    grep -E '^  (strands  |shells|followers|strand width|time)' || true
  strands=$(scene_copy "$work/$hair.json" "$work/${hair}_front.json")
  cycles "cycles_$hair" "$work/${hair}_front.json" "$strands" 0.6
  if [ "$hair" = ponytail ]; then # its followers placed with another seed
    mkdir -p "$work/seed2"
    "$bin/satf-import" "${inputs[@]}" -o "$work/seed2/$hair.json" --seed 2 \
      -q ${import_extra[@]+"${import_extra[@]}"}
    seed2=$(scene_copy "$work/seed2/$hair.json" "$work/seed2/${hair}_front.json")
  fi
  start=$(date +%s%N)
  "$bin/satf-render" "$work/${hair}_front.json" --db out/satf-fiber.hrirdb.exr \
    -q --size "$res" --samples "$samples" ${extra[@]+"${extra[@]}"} \
    -o "$work/${hair}_satf.exr"
  echo "satf-render: $(((($(date +%s%N) - start) / 1000000))) ms, set-up included"
  "$bin/satf-render" "$work/${hair}_front.json" --strands --shading physical \
    -q --size "$res" --samples "$samples" -o "$work/${hair}_strands.exr"
  compare "$hair: satf against Cycles ($res, $spp spp, fibre radius 5e-4 of the diagonal)" \
    "$refs/cycles_$hair.exr" "$work/${hair}_satf.exr" "$out/cycles_$hair.png"
  compare "$hair: satf's strand path against Cycles" \
    "$refs/cycles_$hair.exr" "$work/${hair}_strands.exr" "$out/cycles_${hair}_strands.png"
  compare "$hair: satf against its own strand path (the shells alone)" \
    "$work/${hair}_strands.exr" "$work/${hair}_satf.exr" ""
  if [ -n "$seed2" ]; then
    cycles "cycles_${hair}_seed2" "$work/${hair}_front.json" "$seed2" 0.6
    compare "$hair: ceiling, Cycles --seed 2 against --seed 1" \
      "$refs/cycles_$hair.exr" "$refs/cycles_${hair}_seed2.exr" ""
  fi
done

# the ponytail back-lit (physical), and front-lit with the paper's kk
# shading of the default database
case " $hairs " in *" ponytail "*)
  strands=$(scene_copy "$work/ponytail.json" "$work/ponytail_back.json" back)
  cycles cycles_ponytail_back "$work/ponytail_back.json" "$strands" 0.6
  "$bin/satf-render" "$work/ponytail_back.json" --db out/satf-fiber.hrirdb.exr \
    -q --size "$res" --samples "$samples" ${extra[@]+"${extra[@]}"} \
    -o "$work/ponytail_back.exr"
  compare "ponytail back-lit: satf against Cycles" "$refs/cycles_ponytail_back.exr" \
    "$work/ponytail_back.exr" "$out/cycles_ponytail_back.png"
  "$bin/satf-render" "$work/ponytail_front.json" --db out/satf-default.hrirdb.exr \
    -q --shading kk --size "$res" --samples "$samples" ${extra[@]+"${extra[@]}"} \
    -o "$work/ponytail_kk.exr"
  compare "ponytail, kk shading: satf against Cycles" "$refs/cycles_ponytail.exr" \
    "$work/ponytail_kk.exr" "$out/cycles_ponytail_kk.png"
  ;;
esac
