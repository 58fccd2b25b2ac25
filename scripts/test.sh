#!/usr/bin/env bash
# The tests: installs what is missing, builds, runs the unit tests under
# AddressSanitizer + UndefinedBehaviorSanitizer, then the whole suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh build-asan -DSATF_SANITIZE=ON
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan -L unit -LE slow --output-on-failure -j 2
bash scripts/build.sh build
ctest --test-dir build --output-on-failure -j 2
