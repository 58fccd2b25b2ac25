#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + fuzzer coverage) into
# build-fuzz/ and runs each for SECONDS (default 10) on its corpus, kept
# between runs in $SATF_FUZZ_CORPUS/TARGET (default build-fuzz/corpus): what
# a run finds seeds the next. An input that takes over 4 GB or 20 s fails
# the run like a crash does.
# usage: fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-10}
targets=(fuzz_db fuzz_scene fuzz_hair fuzz_tfx fuzz_ply fuzz_data fuzz_obj fuzz_vdb)
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSATF_FUZZ=ON >/dev/null
cmake --build build-fuzz -j "$(nproc)" --target "${targets[@]}"
for t in "${targets[@]}"; do
  bin=$(find build-fuzz/tests -type f -name "$t" -perm -u+x | head -1)
  corpus=${SATF_FUZZ_CORPUS:-build-fuzz/corpus}/$t
  mkdir -p "$corpus"
  echo "fuzz: $t for ${seconds}s"
  "$bin" -max_total_time="$seconds" -rss_limit_mb=4000 -timeout=20 \
    -print_final_stats=0 "$corpus" \
    2>build-fuzz/$t.log || { tail -30 build-fuzz/$t.log; exit 1; }
done
echo "fuzz: ${#targets[@]} targets built and run"
