#!/usr/bin/env bash
# Set-up + the whole test suite (ctest). UAVIP_SANITIZE=ON runs it under ASan + UBSan
# in build-asan.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${UAVIP_SANITIZE:-OFF}" = ON ]; then
  export BUILD_DIR=${BUILD_DIR:-build-asan} BUILD_TYPE=${BUILD_TYPE:-RelWithDebInfo}
  # third-party leaks only (tests/lsan.supp)
  export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
fi
bash scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
# The install test (label install) builds a consumer against the installed tree; it runs
# in the Release suite only (an instrumented tree needs an instrumented consumer).
exclude=()
# The heavy tests (label heavy: real clouds, the bridge) run in the Release suite only.
[ "${UAVIP_SANITIZE:-OFF}" = ON ] && exclude=(-LE 'install|heavy')
ctest --test-dir "$BUILD_DIR" --output-on-failure -j"$(nproc)" "${exclude[@]}"
