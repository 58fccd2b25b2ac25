#!/usr/bin/env bash
# The README's gallery: a few samples, the animation's contact sheet, and
# imported hair next to its strand reference (satf-render --strands: the
# source strands drawn as ribbons under the same lights, material and
# shadows), with satf-compare's figures
# and difference image. Generated hair (scripts/gen-strands.py) always; the
# shared ponytail and Bangs_100 too when ../shared/data/hair is present.
# usage: gallery.sh [BUILD_DIR] [DATABASE] [OUT_DIR]
set -euo pipefail
build=${1:-build}
db=${2:-out/satf-default.hrirdb.exr}
out=${3:-docs/gallery}
cd "$(dirname "$0")/.."
bin=$build/bin
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
[ -s out/head.obj ] || python3 scripts/gen-head.py out/head.obj
size=480x360

for s in cluster_6a hair_7a hair_7c hair_7d; do
  "$bin/satf-render" "samples/$s.json" --db "$db" --size $size --samples 4 \
    -q -o "$work/$s.exr" --png "$out/$s.png"
done
# the physical shading of the same hairstyle (the fibre model's default
# material: melanin 0.6), when the fibre database is there
fdb=out/satf-fiber.hrirdb.exr
if [ -s "$fdb" ]; then
  "$bin/satf-render" samples/hair_7a.json --db "$fdb" --shading physical \
    --size $size --samples 4 -q -o "$work/p.exr" \
    --png "$out/hair_7a_physical.png"
fi

# the animated sample, every frame, as a contact sheet
"$bin/satf-render" samples/anim_8.json --db "$db" --frames all --size 320x240 \
  -q -o "$work/anim_%04d.exr" --contact-sheet "$out/anim_8_contact.png"

# One imported hairstyle: clusters, then strands, then the comparison.
# usage: compare NAME IMPORT_ARGS...
compare() {
  local name=$1
  shift
  "$bin/satf-import" "$@" -o "$work/$name.json" --db "$PWD/$db" \
    >"$work/$name.import.txt"
  "$bin/satf-render" "$work/$name.json" --size $size --samples 4 -q \
    -o "$work/$name.exr"
  "$bin/satf-render" "$work/$name.json" --size $size --samples 4 -q \
    --strands -o "$work/$name-strands.exr"
  "$bin/satf-compare" "$work/$name-strands.exr" "$work/$name.exr" \
    --png "$out/$name-vs-strands.png" --smooth-bound 1 | sed "s|$work/||g" |
    tee "$out/$name-vs-strands.txt"
}

python3 scripts/gen-strands.py curls --strands 1500 --seed 7 \
  -o "$work/curls.hair" >/dev/null
compare curls "$work/curls.hair"
python3 scripts/gen-strands.py fur --strands 20000 --seed 7 \
  -o "$work/fur.hair" >/dev/null
compare fur "$work/fur.hair"
shared=../shared/data/hair
if [ -d "$shared" ]; then
  compare ponytail "$shared"/ponytail_*.tfx
  compare bangs "$shared/Bangs_100.hair"
fi
echo "gallery: $(ls "$out" | wc -l) files in $out"
