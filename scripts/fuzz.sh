#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang 14 under ASan + UBSan and runs
# each for SECONDS (default 60) on seed corpora made from tests/data, then prints the
# executions per target. A crash, leak or sanitizer report stops with exit 1 and
# leaves the input in FUZZ_DIR (default build-fuzz).
# Usage: bash scripts/fuzz.sh [SECONDS]      (SKIP_APT=1 to skip apt-get)
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET=${1:-60}
OUT=${FUZZ_DIR:-build-fuzz}

if [ "${SKIP_APT:-0}" != 1 ]; then
  missing=()
  for p in clang-14 libclang-rt-14-dev libpcl-dev libeigen3-dev nlohmann-json3-dev libgeographiclib-dev; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    $SUDO apt-get update -q
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
  fi
fi

mkdir -p "$OUT"
CXX=clang++-14
FLAGS=(-std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
  -Iinclude -I. -isystem /usr/include/eigen3 -isystem "$(ls -d /usr/include/pcl-1.* | tail -1)")

echo "fuzz: building fuzz_cloud and fuzz_json in $OUT" >&2
$CXX "${FLAGS[@]}" tests/fuzz/fuzz_cloud.cpp src/io/cloud_io.cpp src/io/las_reader.cpp src/io/atomic_file.cpp \
  src/core/error.cpp -lpcl_io -lpcl_common -o "$OUT/fuzz_cloud"
$CXX "${FLAGS[@]}" tests/fuzz/fuzz_json.cpp src/io/scene_json.cpp src/io/mission_export.cpp src/io/atomic_file.cpp \
  src/core/error.cpp src/core/geometry.cpp -lGeographicLib -o "$OUT/fuzz_json"

# Seeds: the first byte picks the reader (fuzz_cloud: 0 pcd, 1 ply, 2 xyz, 3 las;
# fuzz_json: 0 scene, 1-2 mission surfaces, 3 mission sorties).
seed() { mkdir -p "$OUT/corpus_$1"; { printf "\\x$(printf %02x "$2")"; cat; } > "$OUT/corpus_$1/$3"; }
head -c 4096 tests/data/room_scan1.pcd | seed cloud 0 room.pcd
printf 'VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3\n4 5 6\n' | seed cloud 0 ascii.pcd
printf 'VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary\n\0\0\0\0\0\0\xf0\x3f\0\0\0\0\0\0\0\x40\0\0\0\0\0\0\x08\x40' | seed cloud 0 binary.pcd
printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n4 5 6\n' | seed cloud 1 ascii.ply
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n\0\0\x80\x3f\0\0\0\x40\0\0\x40\x40' | seed cloud 1 binary.ply
printf '1 2 3\n4 5 6\n7,8,9\n' | seed cloud 2 a.xyz
head -c 4096 tests/data/autzen_trim.las | seed cloud 3 autzen.las
[ -f "$OUT/last_mission.json" ] || true
printf '{"surfaces": [{"id": 0, "normal": [0,0,1], "offset": 0, "area_m2": 1, "centroid": [0,0,0], "axis_u": [1,0,0], "boundary": [[0,0,0],[1,0,0],[1,1,0]], "points": [[0,0,0]]}], "obstacles": [], "cloud": {"points": 1}}' | seed json 0 scene.json
m='{"inflation_radius_m": 0.6, "surfaces": [{"surface_id": 0, "status": "ok", "reason": "", "stops": [{"position": [0,0,1], "yaw_deg": 0, "gimbal_pitch_deg": 0, "problem": "none"}], "waypoints": [[0,0,1],[1,0,1]]}], "flight": {"status": "ok", "sorties": [{"waypoints": [[1,0,1],[0,0,1],[1,0,1]], "stops": [{"surface_id": 0, "stop": 0, "waypoint": 1}]}]}}'
printf '%s' "$m" | seed json 1 mission1.json
printf '%s' "$m" | seed json 2 mission2.json
printf '%s' "$m" | seed json 3 mission3.json

total=0
for t in cloud json; do
  log="$OUT/fuzz_$t.log"
  echo "fuzz: running fuzz_$t for $SECONDS_PER_TARGET s" >&2
  if ! "$OUT/fuzz_$t" "$OUT/corpus_$t" -max_total_time="$SECONDS_PER_TARGET" -print_final_stats=1 \
      -artifact_prefix="$OUT/crash_$t-" -rss_limit_mb=2048 -timeout=10 >"$log" 2>&1; then
    echo "fuzz: fuzz_$t found a problem; see $log and $OUT/crash_$t-*" >&2
    tail -30 "$log" >&2
    exit 1
  fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
  echo "fuzz_$t: ${runs:-0} executions, no crash, leak or sanitizer report"
  total=$((total + ${runs:-0}))
done
echo "fuzz: $total executions in total"
