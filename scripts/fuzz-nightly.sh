#!/usr/bin/env bash
# The nightly fuzz run: every libFuzzer target for SECONDS (default 600,
# at least 60) on corpora kept in CORPUS_DIR (default ~/.cache/satf-fuzz),
# so each night starts from what the nights before found; then the corpus
# sizes. CI runs scripts/fuzz.sh for a few seconds instead.
# usage: fuzz-nightly.sh [SECONDS] [CORPUS_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
if [ "$seconds" -lt 60 ]; then
  echo "fuzz-nightly: runs each target at least 60 s (got $seconds)" >&2
  exit 2
fi
export SATF_FUZZ_CORPUS=${2:-${HOME:-.}/.cache/satf-fuzz}
mkdir -p "$SATF_FUZZ_CORPUS"
nice bash scripts/fuzz.sh "$seconds"
for d in "$SATF_FUZZ_CORPUS"/*/; do
  echo "fuzz-nightly: $(basename "$d"): $(find "$d" -type f | wc -l) inputs"
done
