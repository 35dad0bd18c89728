#!/usr/bin/env bash
# Set-up + the main job: plans the bundled default scenario (a floating 3 m cube,
# scenarios/single_cube.yaml) and prints where the results are.
set -euo pipefail
cd "$(dirname "$0")/.."
# The CLI only (scripts/test.sh builds the rest): about 3 min on 2 cores from a clean
# build directory (benchmarks/README.md, "Build time").
BUILD_TARGET=${BUILD_TARGET:-uavip} bash scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
"$BUILD_DIR"/uavip run "${1:-scenarios/single_cube.yaml}" -o "${2:-out/single_cube}"
