#!/usr/bin/env bash
# config_keys.sh KEYS [TREE] [--count]: where the config keys (KEYS: a file of
# "section.key" lines, `uavip config --keys`) are written as string literals in TREE's
# src/, planners/, benchmarks/ and include/ (default: this tree), outside the parameter
# tables (the bodies of the `table()` functions beside each Options struct and Config's).
# A key is looked for as "section.key" and, when its name holds an underscore, as "key"
# (a plain word such as "seed", "name" or "scale" is also a JSON field and a CLI word),
# except the bare names below, which are also written for another meaning.
# Default: lists each hit and exits 1 when there is one (ctest config_keys_in_tables_only).
# --count: the number of keys written in more than one place, a table counting as one
# place (scripts/house_counts.sh).
set -euo pipefail
# Bare names also written elsewhere for another thing than the key (the check fails
# when a name here is no key or has no such use left):
#   mission.json (io/mission_json*.cpp, docs/formats.md) records the camera, the flight
#   model, the grid and the planning settings under the keys' names: footprint_m
#   sensor_mm focal_mm image_px gsd_mm_per_px cost_weights inflation_radius_m
#   resolution_m cruise_speed_m_s climb_speed_m_s descent_speed_m_s hover_s settle_s
#   endurance_s
#   scene.json's and the site manifest's read and safety records (io/scene_json.cpp,
#   tiling/tiles.cpp, cli/validate_commands.cpp): drop_classes cell_m (also the outline's
#   own cell, perception/surface_outline.cpp)
#   `uavip assemble`'s report (cli/scan_commands.cpp): use_recorded_yaw output_voxel_m
#   keys of the scenario's own sections (app/scenario.cpp): size_m (a grass primitive),
#   max_range_m (sensing:, also the raw log's field)
#   voxel_m: the default label of core/voxel_key.h's VoxelKeyer
#   standoff_m: a field of mission.json's and photos.json's camera records
#   gimbal_pitch_deg: a field of every stop in mission.json and the map exports
shared_names=(standoff_m gimbal_pitch_deg footprint_m sensor_mm focal_mm image_px gsd_mm_per_px cost_weights
  inflation_radius_m resolution_m cruise_speed_m_s climb_speed_m_s descent_speed_m_s hover_s settle_s
  endurance_s drop_classes cell_m use_recorded_yaw output_voxel_m size_m max_range_m voxel_m)
# Full keys written by code that reports or reads a file format, "FILE KEY" (each with
# the format it belongs to):
#   the site manifest's JSON paths of its read options (tiling/tiles.cpp)
#   scene.json's path of the safety record (io/scene_json.cpp)
#   FlightPlan::home_source, a value of mission.json (planning/flight_planner.cpp, types.h)
shared_full=("src/tiling/tiles.cpp input.scale" "src/tiling/tiles.cpp input.drop_classes"
  "src/io/scene_json.cpp safety.cell_m"
  "src/planning/flight_planner.cpp mission.home" "src/planning/flight_planner.cpp mission.start"
  "include/uavip/planning/types.h mission.home" "include/uavip/planning/types.h mission.start")
tree=$(cd "$(dirname "$0")/.." && pwd)
mode=check
for arg in "${@:2}"; do
  if [ "$arg" = --count ]; then mode=count; else tree=$(realpath "$arg"); fi
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
keys=$work/keys
cat "$1" > "$keys"  # read once: KEYS may be a pipe, `<(uavip config --keys)`
cd "$tree"
# Outside the tables, and inside them: from a `...table() {` line, or a function that
# fills a table `p`, to the closing brace at column 0.
find src planners benchmarks include -type f \( -name '*.cpp' -o -name '*.h' \) 2>/dev/null | sort |
  while read -r f; do
    awk -v out="$work/outside" -v in_="$work/inside" '
      /table\(\) \{$/ || /^[^ ].*\(params::Table<[^>]*>& p[,)]/ { skip = 1 }
      { print FILENAME ":" FNR ": " $0 >> (skip ? in_ : out) }
      skip && /^}/ { skip = 0 }' "$f"
  done
touch "$work/outside" "$work/inside" "$work/hits"
shared() {
  local n
  for n in "${shared_names[@]}"; do [ "$n" = "$1" ] && return 0; done
  return 1
}
many=0
while read -r full; do
  [ -n "$full" ] || continue
  name=${full#*.}
  patterns=(-e "\"$full\"")
  if [[ $name == *_* ]] && ! shared "$name"; then
    patterns+=(-e "\"$name\"")
  fi
  grep -F "${patterns[@]}" "$work/outside" > "$work/key_hits" || true
  for pair in "${shared_full[@]}"; do
    [ "${pair#* }" = "$full" ] || continue
    grep -v "^${pair%% *}:[0-9]*: " "$work/key_hits" > "$work/kept" || true
    mv "$work/kept" "$work/key_hits"
  done
  n=$(wc -l < "$work/key_hits")
  if [ "$mode" = count ]; then
    grep -qF -e "\"$name\"" "$work/inside" && n=$((n + 1))
    [ "$n" -gt 1 ] && many=$((many + 1))
  else
    sed "s|^|$full: |" "$work/key_hits" >> "$work/hits"
  fi
done < "$keys"
if [ "$mode" = count ]; then
  echo "$many"
  exit 0
fi
for pair in "${shared_full[@]}"; do
  [ "$(grep "^${pair%% *}:[0-9]*: " "$work/outside" | grep -cF "\"${pair#* }\"")" -gt 0 ] ||
    echo "config_keys: \"${pair#* }\" is no longer written in ${pair%% *}; drop it from the list" >> "$work/hits"
done
for n in "${shared_names[@]}"; do
  if ! grep -q "^[^.]*\.$n\$" "$keys" || ! grep -qF "\"$n\"" "$work/outside"; then
    echo "config_keys: \"$n\" is listed as shared but is no key or has no other use; drop it from the list" >> "$work/hits"
  fi
done
if [ -s "$work/hits" ]; then
  echo "config_keys: config keys written outside the parameter tables (name them through Config::keyOf or the table's row):" >&2
  cat "$work/hits" >&2
  exit 1
fi
echo "config_keys: every config key is written in its table only"
