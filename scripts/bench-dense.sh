#!/usr/bin/env bash
# Dense hair benchmark: generates (or imports) dense hairstyles and times
# each through the cluster path and through --strands, in the paper's
# Kajiya-Kay shading and in the physical shading, at 640x480; prints one
# table (Table 1's stages, FPS, fragments, HSVs, clusters, shells) and
# writes it to OUT/bench-dense.tsv.
#
# usage: bench-dense.sh [BUILD_DIR] [OUT_DIR] [FRAMES]
#   BUILD_DIR  default build
#   OUT_DIR    default out/dense (generated strands, scenes, the table)
#   FRAMES     frames per --bench run (default 5; the strand path of the
#              100K curtain takes about half a minute a frame on llvmpipe)
# Environment: SATF_DENSE_SCALE (default 1) multiplies every strand count,
# for a quick run (0.1: a tenth of each); SATF_DENSE_KINDS (default
# "straight fur ponytail") picks the scenes; SATF_DENSE_PATHS (default
# "clusters strands") and SATF_DENSE_SHADINGS (default "kk physical");
# SATF_DENSE_ARGS, more satf-render options for every run (e.g. "--maps
# cpu" on a machine with a GPU, whose default is the GPU's maps).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-out/dense}
frames=${3:-5}
scale=${SATF_DENSE_SCALE:-1}
kinds=${SATF_DENSE_KINDS:-straight fur ponytail}
paths=${SATF_DENSE_PATHS:-clusters strands}
shadings=${SATF_DENSE_SHADINGS:-kk physical}
read -r -a extra <<<"${SATF_DENSE_ARGS:-}"
db=out/satf-default.hrirdb.exr
fdb=out/satf-fiber.hrirdb.exr
for f in "$build/bin/satf-import" "$build/bin/satf-render" "$db" "$fdb"; do
  [ -e "$f" ] || {
    echo "bench-dense: $f is missing: run bash scripts/main.sh first" >&2
    exit 1
  }
done
mkdir -p "$out"
n() { python3 -c "print(max(1, int(round($1 * $scale))))"; }

# the hair of one kind: a generated .hair, or the shared ponytail with
# followers (TressFX guides, 4,933 of them: 9 followers each come to about
# 49K strands)
import_kind() {
  local kind=$1 scene=$out/$1.json log=$out/$1.import.txt src=()
  case $kind in
  straight)
    python3 scripts/gen-strands.py straight -q --strands "$(n 100000)" \
      --points 32 -o "$out/straight.hair"
    src=("$out/straight.hair")
    ;;
  fur)
    python3 scripts/gen-strands.py fur -q --strands "$(n 200000)" \
      --points 4 -o "$out/fur.hair"
    src=("$out/fur.hair")
    ;;
  ponytail)
    local d=../shared/data/hair
    if [ ! -e $d/ponytail_back.tfx ]; then
      echo "bench-dense: $d is absent: the ponytail is skipped" >&2
      return 1
    fi
    src=($d/ponytail_front_top.tfx $d/ponytail_side.tfx $d/ponytail_back.tfx
      $d/ponytail_tail.tfx --follow "$(python3 -c "print(max(0, int(round(9 * $scale))))")")
    ;;
  *)
    echo "bench-dense: unknown kind $kind" >&2
    return 1
    ;;
  esac
  local t0 t1
  t0=$(date +%s.%N)
  "$build/bin/satf-import" "${src[@]}" -o "$scene" --db "$db" >"$log" 2>&1
  t1=$(date +%s.%N)
  python3 -c "print(f'{$t1 - $t0:.1f}')" >"$out/$kind.import_s"
}

# one --bench run: prints the row's fields, tab-separated
bench() {
  local scene=$1 path=$2 shading=$3 args=() txt
  [ "$path" = strands ] && args+=(--strands)
  if [ "$shading" = physical ]; then
    args+=(--db "$fdb" --shading physical)
  else
    args+=(--db "$db" --shading kk)
  fi
  txt=$("$build/bin/satf-render" "$scene" "${args[@]}" ${extra[@]+"${extra[@]}"} --size 640x480 \
    --bench "$frames" -q 2>&1) || {
    echo "bench-dense: $scene $path $shading failed:" >&2
    echo "$txt" >&2
    return 1
  }
  # row 2: name C# L# S#(K) H#(K) I C M L S FPS; row 3: fragments N ...
  echo "$txt" | awk -v path="$path" -v shading="$shading" '
    NR == 2 { c = $2; h = $5; i = $6; cc = $7; m = $8; l = $9; s = $10;
              fps = $11 }
    /^fragments/ { frags = $2 }
    END { printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n", path,
          shading, c, h, i, cc, m, l, s, fps, frags }'
}

table=$out/bench-dense.tsv
printf 'hair\tstrands\timport_s\tshells\tpath\tshading\tclusters\tHSVs_K\tI_ms\tC_ms\tM_ms\tL_ms\tS_ms\tFPS\tfragments\n' >"$table"
for kind in $kinds; do
  echo "bench-dense: $kind: importing" >&2
  import_kind "$kind" || continue
  log=$out/$kind.import.txt
  strands=$(awk '$1 == "strands" { print $2; exit }' "$log")
  shells=$(awk '$1 == "shells" { print $2; exit }' "$log")
  for path in $paths; do
    for shading in $shadings; do
      echo "bench-dense: $kind: $path, $shading, $frames frames" >&2
      row=$(bench "$out/$kind.json" "$path" "$shading") || continue
      printf '%s\t%s\t%s\t%s\t%s\n' "$kind" "${strands:-?}" \
        "$(cat "$out/$kind.import_s")" "${shells:--}" "$row" >>"$table"
    done
  done
done
column -t -s $'\t' "$table" 2>/dev/null || cat "$table"
echo "bench-dense: the table is in $table" >&2
