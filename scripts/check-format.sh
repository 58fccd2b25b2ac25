#!/usr/bin/env bash
# Checks that every C and C++ source file tracked by git is
# formatted as .clang-format says (clang-format --dry-run --Werror).
# With --fix, formats them in place instead.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=(--dry-run --Werror)
[ "${1:-}" = "--fix" ] && mode=(-i)
mapfile -t files < <(git ls-files '*.c' '*.h' '*.cpp')
clang-format "${mode[@]}" "${files[@]}"
echo "format: ${#files[@]} files checked"
