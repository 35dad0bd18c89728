#!/usr/bin/env bash
# Geographic exports of real missions (issue 32): plans each case once, then times
# `uavip export` per format (median of RUNS) and prints a Markdown table of file sizes,
# waypoints and the largest read-back difference of the KMZ (the file's own lon/lat/height
# converted back to the local frame, as export checks it before writing).
# Usage: bash benchmarks/export_bench.sh [RUNS] [BUILD_DIR]   (python3 for the medians)
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${1:-3}
BUILD=${2:-build}
UAVIP="$BUILD/uavip"
OUT=$(mktemp -d /tmp/uavip_export_bench.XXXXXX)
trap 'rm -rf "$OUT"' EXIT

# Structure missions are planned within the Mavic 3E's gimbal (-90..35 deg), so that
# every photo can be flown by it.
printf 'coverage:\n  gimbal_pitch_deg: [-90, 35]\n' >"$OUT/m3e.yaml"
# name | how the mission is made | how it is placed on the Earth and flown
cases=(
  "single_plane|run scenarios/single_plane.yaml|--origin 47.3977,8.5456,488 --drone m350"
  "wall_on_ground|run scenarios/wall_on_ground.yaml|--origin 22.3364,114.2655,12 --drone m350 --payload h30"
  "fcplanner_pipe (structure)|detect+plan tests/data/fcplanner_pipe.pcd|--origin 31.0256,121.4364,6 --drone m3e"
  "fcplanner_MBS (structure)|detect+plan tests/data/fcplanner_MBS.pcd|--origin 31.0256,121.4364,6 --drone m3e"
)

median() { python3 -c 'import statistics,sys; print(f"{statistics.median(float(x) for x in sys.argv[1:]):.2f}")' "$@"; }
seconds() { local t0 t1; t0=$(date +%s.%N); "$@" >/dev/null 2>&1; t1=$(date +%s.%N); python3 -c "print($t1-$t0)"; }

echo "| mission | waypoints / stops | sorties | .kmz (relative) | .kmz (ellipsoid) | .kml | .geojson | read back, largest difference | export dji-kmz (median of $RUNS) |"
echo "|---|---|---|---|---|---|---|---|---|"
for c in "${cases[@]}"; do
  IFS='|' read -r name make place <<<"$c"
  dir="$OUT/${name%% *}"
  if [[ $make == run* ]]; then
    "$UAVIP" run ${make#run } -o "$dir" -q --no-views
  else
    cloud=${make#detect+plan }
    "$UAVIP" detect "$cloud" -o "$dir" -q --no-views
    "$UAVIP" plan "$dir/scene.json" --cover structure -c "$OUT/m3e.yaml" -o "$dir" -q --no-views
  fi
  m="$dir/mission.json"
  rel=$("$UAVIP" export "$m" --surface all --format dji-kmz $place -o "$dir/rel.kmz")
  "$UAVIP" export "$m" --surface all --format dji-kmz $place --height-mode ellipsoid \
    -o "$dir/ell.kmz" -q
  "$UAVIP" export "$m" --surface all --format kml $place -o "$dir/site.kml" -q
  "$UAVIP" export "$m" --surface all --format geojson $place -o "$dir/site.geojson" -q
  size() { du -cb "$@" | tail -1 | cut -f1 | python3 -c 'import sys; print(f"{int(sys.stdin.read())/1024:.1f} KB")'; }
  wps=$(echo "$rel" | grep -o '[0-9]* waypoints, [0-9]* photo stops' | awk '{w+=$1; s+=$3} END {print w " / " s}')
  sorties=$(ls "$dir"/rel*.kmz | wc -l)
  diff=$(echo "$rel" | grep -o 'largest difference [0-9.]* mm' | awk '{if ($3 > m) m = $3} END {print m " mm"}')
  times=()
  for _ in $(seq "$RUNS"); do
    times+=("$(seconds "$UAVIP" export "$m" --surface all --format dji-kmz $place -o "$dir/t.kmz")")
  done
  echo "| $name | $wps | $sorties | $(size "$dir"/rel*.kmz) | $(size "$dir"/ell*.kmz) | $(size "$dir/site.kml") | $(size "$dir/site.geojson") | $diff | $(median "${times[@]}") s |"
done
