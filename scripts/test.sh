#!/usr/bin/env bash
# Set-up + the whole test suite (ctest). UAVIP_SANITIZE=ON runs it under ASan + UBSan
# in build-asan.
set -euo pipefail
cd "$(dirname "$0")/.."
# The Release build stops on a warning in uavip's code (UAVIP_WERROR=ON); the sanitizer
# build does not: GCC 12 warns about code it has instrumented for ASan.
if [ "${UAVIP_SANITIZE:-OFF}" = ON ]; then
  export UAVIP_WERROR=${UAVIP_WERROR:-OFF}
  export BUILD_DIR=${BUILD_DIR:-build-asan} BUILD_TYPE=${BUILD_TYPE:-RelWithDebInfo}
  # third-party leaks only (tests/lsan.supp)
  export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
fi
export UAVIP_WERROR=${UAVIP_WERROR:-ON}
bash scripts/setup.sh
# The mission page's browser test (tests/io/mission_page_browser_test.cpp) opens the page
# in Debian's headless chromium: installed here for the tests only (not by demo.sh).
if [ "${SKIP_APT:-0}" != 1 ] && ! dpkg-query -W -f='${Status}' chromium 2>/dev/null | grep -q 'install ok installed'; then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  echo "test: installing chromium" >&2
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends chromium
fi
# The heavy test PhotoCheckWallSmall runs COLMAP and OpenCV: benchmarks/packages.txt,
# installed for the tests only (photo_check.sh skips apt-get itself when SKIP_APT=1).
[ "${UAVIP_SANITIZE:-OFF}" = ON ] || bash benchmarks/photo_check.sh --install-only
BUILD_DIR=${BUILD_DIR:-build}
# The install test (label install) builds a consumer against the installed tree; it runs
# in the Release suite only (an instrumented tree needs an instrumented consumer).
exclude=()
# The heavy tests (label heavy: real clouds, the bridge) run in the Release suite only.
[ "${UAVIP_SANITIZE:-OFF}" = ON ] && exclude=(-LE 'install|heavy')
ctest --test-dir "$BUILD_DIR" --output-on-failure -j"$(nproc)" "${exclude[@]}"
