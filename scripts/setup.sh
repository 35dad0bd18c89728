#!/usr/bin/env bash
# Installs what uavip needs on Debian 12 (scripts/packages.txt; as root, or with sudo),
# then configures and builds. Environment: BUILD_DIR (default build), BUILD_TYPE
# (Release), BUILD_TARGET (default: all), UAVIP_SANITIZE=ON for AddressSanitizer +
# UBSan, UAVIP_WERROR=ON to stop on a warning in uavip's code, SKIP_APT=1 to skip apt-get.
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
    echo "setup: installing ${missing[*]}" >&2
    $SUDO apt-get update -q
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
  fi
fi

BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" \
  -DUAVIP_SANITIZE="${UAVIP_SANITIZE:-OFF}" -DUAVIP_WERROR="${UAVIP_WERROR:-OFF}" >/dev/null
# BUILD_TARGET (e.g. uavip) builds only that target and what it needs.
echo "setup: building ${BUILD_TARGET:-everything} in $BUILD_DIR" >&2
cmake --build "$BUILD_DIR" -j"$(nproc)" ${BUILD_TARGET:+--target "$BUILD_TARGET"}
