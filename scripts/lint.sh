#!/usr/bin/env bash
# clang-tidy-14 with .clang-tidy (bugprone, performance, functions of at most 80 lines)
# on the C++ sources the last commit changed (a changed header brings its source:
# include/uavip/M/N.h -> src/M/N.cpp, planners/N.h -> planners/N.cpp), with the flags
# of LINT_DIR/compile_commands.json (default build-lint: configured here, nothing built,
# with the unity build off so that every source has its own entry).
# Any finding is an error (exit 1).
# Usage: bash scripts/lint.sh [FILE.cpp ...]   (SKIP_APT=1 to skip apt-get)
set -euo pipefail
cd "$(dirname "$0")/.."
LINT_DIR=${LINT_DIR:-build-lint}
if [ "${SKIP_APT:-0}" != 1 ] && ! command -v clang-tidy-14 >/dev/null; then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends clang-tidy-14
fi
cmake -S . -B "$LINT_DIR" -DCMAKE_BUILD_TYPE=Release -DUAVIP_UNITY_BUILD=OFF >/dev/null
db="$LINT_DIR/compile_commands.json"

if [ $# -gt 0 ]; then
  changed=("$@")
else
  mapfile -t changed < <(git diff --name-only --diff-filter=d HEAD~1 HEAD)
fi
files=()
for f in "${changed[@]}"; do
  case $f in
    include/uavip/*.h) f="src/${f#include/uavip/}"; f="${f%.h}.cpp" ;;
    planners/*.h) f="${f%.h}.cpp" ;;
  esac
  # Only sources this build compiles (the fuzz targets build under UAVIP_FUZZ).
  [[ $f == *.cpp && -f $f ]] && grep -qF "\"file\": \"$PWD/$f\"" "$db" && files+=("$f")
done
mapfile -t files < <(printf '%s\n' "${files[@]}" | sort -u | sed '/^$/d')
if [ ${#files[@]} -eq 0 ]; then
  echo "lint: no C++ source changed in the last commit"
  exit 0
fi
echo "lint: clang-tidy on ${files[*]}" >&2
clang-tidy-14 -p "$LINT_DIR" --quiet "${files[@]}"
echo "lint: ${#files[@]} file(s) clean"
