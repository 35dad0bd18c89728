#!/usr/bin/env bash
# Heavy test PhotoCheckWallSmall: scenarios/wall_small.yaml planned for reconstruction
# (coverage.purpose), its photos rendered and reconstructed by COLMAP through
# benchmarks/photo_check.py; passes when >= 95 % of the photos are in one model.
# Usage: photo_check_wall_small.sh UAVIP WORLD_TRUTH OUT_DIR. Exit 77 (ctest: skipped)
# when colmap is not installed (bash benchmarks/photo_check.sh --install-only installs
# it; scripts/test.sh does unless SKIP_APT=1).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
if ! command -v colmap >/dev/null 2>&1; then
  echo "PhotoCheckWallSmall skipped: colmap is not installed (bash benchmarks/photo_check.sh --install-only)"
  exit 77
fi
out=$3
rm -rf "$out"
mkdir -p "$out"
export QT_QPA_PLATFORM=offscreen
exec /usr/bin/python3 "$root/benchmarks/photo_check.py" "$root/scenarios/wall_small.yaml" \
  --purpose reconstruction --uavip "$1" --truth-tool "$2" --out "$out" --name wall_small \
  --no-noise --no-stitch --threads 2 --require-registered 0.95
