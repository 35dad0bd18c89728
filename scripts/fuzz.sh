#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang 14 under ASan + UBSan (CMake
# with -DUAVIP_FUZZ=ON in FUZZ_DIR) and runs each for SECONDS (default 60) on seed
# corpora made from tests/data and scenarios/ (the raw log seeds are written here with
# printf), then prints the executions per target and in total. A crash, leak or
# sanitizer report stops with exit 1 and leaves the input in FUZZ_DIR (default build-fuzz).
# Usage: bash scripts/fuzz.sh [SECONDS]      (SKIP_APT=1 to skip apt-get;
#        FUZZ_TARGETS="cloud json" builds and runs only those, default all five)
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET=${1:-60}
OUT=${FUZZ_DIR:-build-fuzz}
TARGETS=${FUZZ_TARGETS:-cloud json yaml rawlog mesh}

# clang and its libFuzzer runtime, and what the project configures with (packages.txt).
if [ "${SKIP_APT:-0}" != 1 ]; then
  missing=()
  for p in clang-14 libclang-rt-14-dev $(sed -e 's/#.*//' scripts/packages.txt); do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    $SUDO apt-get update -q
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
  fi
fi

# The targets and what they link are CMake's (option UAVIP_FUZZ, cmake/fuzz.cmake).
echo "fuzz: building fuzz_{${TARGETS// /,}} in $OUT" >&2
CC=clang-14 CXX=clang++-14 cmake -S . -B "$OUT" -DCMAKE_BUILD_TYPE=Debug -DUAVIP_FUZZ=ON \
  -DUAVIP_BUILD_TESTS=OFF -DUAVIP_BUILD_BENCHMARKS=OFF >/dev/null
targets=()
for t in $TARGETS; do targets+=(--target "fuzz_$t"); done
cmake --build "$OUT" -j"$(nproc)" "${targets[@]}"

# Seeds: the first byte picks the reader (fuzz_cloud: 0 pcd, 1 ply, 2 xyz, 3 csv, 4 txt,
# 5 las, + 8 for input.scale 0.001;
# fuzz_json: 0 scene, 1-2 mission surfaces, 3 mission sorties; fuzz_yaml: 0 scenario,
# 1 config). fuzz_rawlog has no selector byte: its input is log.json, the vertical,
# horizontal and IMU CSV files of station 0, separated by "@@@@".
seed() { mkdir -p "$OUT/corpus_$1"; { printf "\\x$(printf %02x "$2")"; cat; } > "$OUT/corpus_$1/$3"; }
head -c 4096 tests/data/room_scan1.pcd | seed cloud 0 room.pcd
printf 'VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3\n4 5 6\n' | seed cloud 0 ascii.pcd
printf 'VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary\n\0\0\0\0\0\0\xf0\x3f\0\0\0\0\0\0\0\x40\0\0\0\0\0\0\x08\x40' | seed cloud 0 binary.pcd
printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n4 5 6\n' | seed cloud 1 ascii.ply
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n\0\0\x80\x3f\0\0\0\x40\0\0\x40\x40' | seed cloud 1 binary.ply
printf '1 2 3\n4 5 6\n7,8,9\n' | seed cloud 2 a.xyz
# Georeferenced text clouds (UTM 31N): recentred by the readers.
printf '500000.25 5400000.5 12.0\n500010.75 5400003.0 14.5\n500004 5400010 30\n' | seed cloud 2 utm.xyz
printf 'x,y,z\n500000.25,5400000.5,12.0\n500010.75,5400003.0,14.5\n' | seed cloud 3 utm.csv
printf '//X Y Z Intensity\n834003.5 815000.25 20.9997 12\n834010 815004 25 14\n' | seed cloud 4 hk.txt
printf '1 2 3\n4 5 6\n1e308 0 0\n' | seed cloud 2 far_point.xyz
printf '\n1e308 0 0\n' | seed cloud 2 lone_point.xyz  # found by fuzz_cloud: recentred to -inf
printf '500000250 5400000500 12000\n500010750 5400003000 14500\n' | seed cloud 10 utm_mm.xyz
printf 'VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n500000.125 5400000.5 12.25\n500001 5400002 13\n' | seed cloud 0 utm.pcd
head -c 4096 tests/data/autzen_trim.las | seed cloud 5 autzen.las
[ -f "$OUT/last_mission.json" ] || true
printf '{"surfaces": [{"id": 0, "normal": [0,0,1], "offset": 0, "area_m2": 1, "centroid": [0,0,0], "axis_u": [1,0,0], "boundary": [[0,0,0],[1,0,0],[1,1,0]], "points": [[0,0,0]]}], "obstacles": [], "cloud": {"points": 1}}' | seed json 0 scene.json
m='{"inflation_radius_m": 0.6, "surfaces": [{"surface_id": 0, "status": "ok", "reason": "", "stops": [{"position": [0,0,1], "yaw_deg": 0, "gimbal_pitch_deg": 0, "problem": "none"}], "waypoints": [[0,0,1],[1,0,1]]}], "flight": {"status": "ok", "sorties": [{"waypoints": [[1,0,1],[0,0,1],[1,0,1]], "stops": [{"surface_id": 0, "stop": 0, "waypoint": 1}]}]}}'
printf '%s' "$m" | seed json 1 mission1.json
printf '%s' "$m" | seed json 2 mission2.json
printf '%s' "$m" | seed json 3 mission3.json
for f in single_point single_line single_plane single_cube wall_on_ground bench_cube_around bridge; do
  seed yaml 0 "$f.yaml" < "scenarios/$f.yaml"
done
grep -E '^(input|preprocess|perception|uav|grid|camera|coverage|planner|mission|flight|assembly|registration):' \
  scenarios/bridge.yaml | seed yaml 1 bridge_config.yaml
printf '%s\n' 'input: {drop_classes: [3, 4, 5, 7]}' \
  'preprocess: {remove_outliers: true, outlier_k: 16, outlier_std_ratio: 2.0, voxelize: true, voxel_m: 0.05}' \
  'perception: {distance_threshold_m: 0.2, max_iterations: 200, min_area_m2: 2.0, plane_cluster_tolerance_m: 0.3,' \
  '  area_cell_m: 0.1, min_inliers: 30, open_voxel_m: 0.1, viewpoint: [0, 0, 0], max_planes: 64, max_failures: 8,' \
  '  seed: 42, obstacle_tolerance_m: 0.3, obstacle_min_points: 1}' \
  'uav: {size_m: [0.6, 0.6, 0.4], inflation_radius_m: 0.6}' 'grid: {resolution_m: 0.2, padding_m: 2.0}' \
  'camera: {sensor_mm: [13.2, 8.8], focal_mm: 8.8, image_px: [5472, 3648], gsd_mm_per_px: 1.0}' \
  'coverage: {overlap: [0.2, 0.3], standoff_m: 1.5, gimbal_pitch_deg: [-90, 90], max_stops: 200000}' \
  'planner: {name: rrtconnect, cost_weights: [1, 1, 1], max_expansions: 0, time_limit_s: 1.0, seed: 1, simplify: true}' \
  'mission: {simplify: true, max_skipped_fraction: 0.25, start: [0, 0, 1], home: [0, 0, 1], repair_stops: true,' \
  '  max_standoff_factor: 1.25, min_coverage: 0.95}' \
  'flight: {cruise_speed_m_s: 3, climb_speed_m_s: 2, descent_speed_m_s: 1.5, hover_s: 2, settle_s: 1,' \
  '  endurance_s: 1200, reserve: 0.25}' \
  'assembly: {use_imu_prior: true, icp: point_to_line, max_iterations: 30, max_correspondence_m: 0.5,' \
  '  keyframe_yaw_deg: 15, keyframe_translation_m: 0.2, horizontal_stride: 1, imu_smoothing_s: 0,' \
  '  max_imu_gap_s: 0.025, estimate_z: true, z_cone_deg: 20, include_horizontal: false}' \
  'registration: {method: translation, overlap_margin_m: 1.0, search_radius_m: 2.0, search_step_m: 0.2,' \
  '  downsample_m: 0.15, max_correspondence_m: 1.0, max_iterations: 40, ndt_resolution_m: 1.0,' \
  '  use_recorded_yaw: false, output_voxel_m: 0.02}' | seed yaml 1 full_config.yaml
# fuzz_mesh: vertex count, spacing byte, float x y z per vertex, index triples.
mkdir -p "$OUT/corpus_mesh"
python3 -c 'import struct, sys
v = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1)]
sys.stdout.buffer.write(bytes([len(v), 4]) + b"".join(struct.pack("<3f", *p) for p in v)
                        + bytes([0, 1, 2, 0, 2, 3, 0, 1, 4, 1, 1, 2]))' > "$OUT/corpus_mesh/pyramid.bin"
# A minimal valid raw log: one station, two scans per scanner, IMU samples over them.
mkdir -p "$OUT/corpus_rawlog"
station() {  # id, position: a log.json station record naming the files of station 0
  printf '{"id": %s, "recorded_position_m": [%s], "recorded_yaw_rad": 0.003, "vertical_scans": "station_0_vertical.csv",' "$1" "$2"
  printf ' "horizontal_scans": "station_0_horizontal.csv", "imu": "station_0_imu.csv"}'
}
rawlog() {  # stations...: the fuzz_rawlog input
  printf '{"format": "uavip-raw-log", "version": 1, "max_range_m": 30.0, "min_range_m": 0.1, "mounts": {'
  printf '"vertical": {"translation_m": [-0.15, 0, 0], "rotation_wxyz": [1, 0, 0, 0]}, '
  printf '"horizontal": {"translation_m": [0.15, 0, 0], "rotation_wxyz": [1, 0, 0, 0]}}, "stations": [%s]}\n' "$(IFS=,; echo "$*")"
  printf '@@@@# uavip raw log, vertical scans\n'
  printf '0.000000,0.018750,-2.356194490,0.004363323,4,5.654,0,31.500,0.050\n'
  printf '0.025000,0.018750,-2.356194490,0.004363323,4,5.650,5.700,0,2.000\n'
  printf '@@@@# uavip raw log, horizontal scans\n'
  printf '0.012500,0.018750,-0.785398163,0.004363323,3,1.000,2.000,3.000\n'
  printf '0.037500,0.018750,-0.785398163,0.004363323,3,1.100,2.100,3.100\n'
  printf '@@@@# uavip raw log, IMU samples\n'
  for t in 0.000000 0.020000 0.040000 0.060000; do printf '%s,1.000000000,0.000000000,0.000000000,0.000000000\n' "$t"; done
}
rawlog "$(station 0 0,0,0)" > "$OUT/corpus_rawlog/one_station.log"
rawlog "$(station 0 0,0,0)" "$(station 1 4.5,-0.2,0.01)" > "$OUT/corpus_rawlog/two_stations.log"

total=0
for t in $TARGETS; do
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
