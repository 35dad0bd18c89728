#!/usr/bin/env bash
# Installs the uavip build BUILD_DIR into a temporary prefix (cmake --install), then checks
# the installed tree: every quoted include of an installed header resolves inside it; the
# CLI plans an installed scenario and names the configured prefix's scenario folder; and
# tests/install/consumer, a project of its own, configures with find_package(uavip),
# builds against uavip::planners and runs (it plans around a wall and checks the path).
# The ctest test InstallConsumer (label install) runs it.
# Usage: bash tests/install/run_consumer_test.sh BUILD_DIR      (KEEP=1 keeps the temp dir)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$(cd "${1:?usage: run_consumer_test.sh BUILD_DIR}" && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/uavip-install-test.XXXXXX")
if [ "${KEEP:-0}" = 1 ]; then echo "install test: keeping $work"; else trap 'rm -rf "$work"' EXIT; fi
prefix=$work/prefix

fail() { echo "install test: FAILED: $*" >&2; exit 1; }
# Runs a step with its output in a log, shown only when it fails.
step() {
  local log=$work/$1.log; shift
  "$@" >"$log" 2>&1 || { cat "$log" >&2; fail "$*"; }
}
cache() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }

step install cmake --install "$build" --prefix "$prefix"

# Headers: nothing from src/, and every "…" include found in include/ or include/uavip/
# (the two include directories of the installed targets).
[ -f "$prefix/include/uavip/core/geometry.h" ] || fail "no include/uavip/core/geometry.h"
[ -f "$prefix/include/uavip/planners/registry.h" ] || fail "no include/uavip/planners/registry.h"
missing=0
while IFS= read -r line; do
  header=${line%%:*}
  inc=$(sed -n 's/.*#include "\([^"]*\)".*/\1/p' <<<"${line#*:}")
  if [ ! -f "$prefix/include/$inc" ] && [ ! -f "$prefix/include/uavip/$inc" ]; then
    echo "install test: ${header#"$prefix"/} includes \"$inc\", which is not installed" >&2
    missing=1
  fi
done < <(grep -rH '^#include "' "$prefix/include")
[ "$missing" = 0 ] || fail "installed headers include files that are not installed"

# CLI and scenarios: the binary names the configured prefix's scenario directory.
"$prefix/bin/uavip" --help >/dev/null || fail "installed uavip --help"
[ -f "$prefix/share/uavip/scenarios/single_cube.yaml" ] || fail "no share/uavip/scenarios/single_cube.yaml"
grep -qaF "$(cache CMAKE_INSTALL_PREFIX)/share/uavip/scenarios" "$prefix/bin/uavip" ||
  fail "installed uavip does not name $(cache CMAKE_INSTALL_PREFIX)/share/uavip/scenarios"
step cli "$prefix/bin/uavip" run "$prefix/share/uavip/scenarios/single_plane.yaml" --no-views -o "$work/run"
[ -s "$work/run/mission.json" ] || fail "installed uavip run wrote no mission.json"

# The consumer project, with the compilers and build type of BUILD_DIR.
build_type=$(cache CMAKE_BUILD_TYPE)
step configure cmake -S "$here/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_C_COMPILER="$(cache CMAKE_C_COMPILER)" -DCMAKE_CXX_COMPILER="$(cache CMAKE_CXX_COMPILER)" \
  -DCMAKE_BUILD_TYPE="${build_type:-Release}"
grep -q "^uavip_DIR:PATH=$prefix/" "$work/consumer/CMakeCache.txt" || fail "find_package(uavip) did not use $prefix"
step build cmake --build "$work/consumer" -j2
"$work/consumer/uavip_consumer" || fail "uavip_consumer"
echo "install test: ok (installed $(find "$prefix" -type f | wc -l) files)"
