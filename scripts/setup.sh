#!/usr/bin/env bash
# Installs what uavip needs on Debian 12 (scripts/packages.txt; as root, or with sudo),
# then configures and builds. Environment: BUILD_DIR (default build), BUILD_TYPE
# (Release), BUILD_TARGET (default: all), UAVIP_SANITIZE=ON for AddressSanitizer +
# UBSan, UAVIP_WERROR=ON to stop on a warning in uavip's code, UAVIP_UNITY_BUILD=OFF to
# compile source by source (default ON: one unit per module, quicker; CMakeLists.txt),
# SKIP_APT=1 to skip apt-get. Prints a `setup:` line at each step.
set -euo pipefail
cd "$(dirname "$0")/.."

# The one package list (CMakeLists.txt reads it too for the Debian package).
mapfile -t PACKAGES < <(sed -e 's/#.*//' -e 's/[[:space:]]//g' -e '/^$/d' scripts/packages.txt)

if [ "${SKIP_APT:-0}" != 1 ]; then
  missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    echo "setup: installing ${#missing[@]} packages (about 2.5 min on a fresh Debian 12): ${missing[*]}" >&2
    echo "setup: apt-get update" >&2
    $SUDO apt-get update -q
    # -qq: dpkg's line per package as it is unpacked and set up, not apt's download
    # table; pipefail keeps apt-get's failure.
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
      -o Dpkg::Use-Pty=0 "${missing[@]}" | { grep -E '^(Unpacking|Setting up) ' || true; }
    echo "setup: installed ${#missing[@]} packages after ${SECONDS} s" >&2
  else
    echo "setup: all ${#PACKAGES[@]} packages of scripts/packages.txt are installed" >&2
  fi
fi

BUILD_DIR=${BUILD_DIR:-build}
# Ninja (ninja-build) keeps both cores busy across the module libraries, where make
# finishes one library before the next; a build directory configured before keeps the
# generator it has.
generator=()
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ] && command -v ninja >/dev/null; then
  generator=(-G Ninja)
fi
echo "setup: configuring $BUILD_DIR (cmake${generator[*]:+ ${generator[*]}})" >&2
cmake "${generator[@]}" -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" \
  -DUAVIP_SANITIZE="${UAVIP_SANITIZE:-OFF}" -DUAVIP_WERROR="${UAVIP_WERROR:-OFF}" \
  -DUAVIP_UNITY_BUILD="${UAVIP_UNITY_BUILD:-ON}" >/dev/null
# BUILD_TARGET (e.g. uavip) builds only that target and what it needs; Ninja's [N/M]
# lines show the progress (benchmarks/README.md, "Build time", for how long it takes).
build_start=$SECONDS
echo "setup: building ${BUILD_TARGET:-everything} in $BUILD_DIR with $(nproc) jobs" >&2
cmake --build "$BUILD_DIR" -j"$(nproc)" ${BUILD_TARGET:+--target "$BUILD_TARGET"}
echo "setup: built ${BUILD_TARGET:-everything} in $((SECONDS - build_start)) s" >&2
