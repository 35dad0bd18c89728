#!/usr/bin/env bash
# Checks that every C++ file of src/, include/, planners/, benchmarks/ and tests/ is as
# clang-format-14 would write it (.clang-format); lists the differences and exits 1
# otherwise. Fix with: clang-format-14 -i FILE.
# Usage: bash scripts/format_check.sh   (SKIP_APT=1 to skip apt-get)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${SKIP_APT:-0}" != 1 ] && ! command -v clang-format-14 >/dev/null; then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends clang-format-14
fi
mapfile -t files < <(git ls-files -- 'src/*.cpp' 'src/*.h' 'include/*.h' 'planners/*.cpp' 'planners/*.h' \
  'benchmarks/*.cpp' 'benchmarks/*.h' 'tests/*.cpp' 'tests/*.h')
clang-format-14 --dry-run --Werror "${files[@]}"
echo "format: ${#files[@]} files as clang-format-14 writes them"
