#!/usr/bin/env bash
# config_keys.sh KEYS [TREE] [--count]: where the config keys (KEYS: a file of
# "section.key" lines, `uavip config --keys`) are written as string literals in TREE's
# src/, planners/, benchmarks/ and include/ (default: this tree), outside the parameter
# tables (the bodies of the `table()` functions beside each Options struct and Config's).
# A key is looked for as "section.key" and, when its name holds an underscore (a plain
# word such as "seed" or "name" is also a JSON field), as "key" -- unless a section still
# read by hand in src/app/scenario.cpp (`s.number("key", …)`) has a key of that name: such
# a name is listed as pending, and checked once every section is read through the tables.
# Default: lists each hit and exits 1 when there is one (ctest config_keys_in_tables_only).
# --count: the number of keys written in more than one place, a table counting as one
# place (scripts/house_counts.sh).
set -euo pipefail
# Bare names also written legitimately elsewhere, each for another thing than its key:
#   standoff_m        a field of mission.json's and photos.json's camera records
#   gimbal_pitch_deg  a field of every stop in mission.json and the map exports
shared_names=(standoff_m gimbal_pitch_deg)
keys=$(realpath "$1")
tree=$(cd "$(dirname "$0")/.." && pwd)
mode=check
for arg in "${@:2}"; do
  if [ "$arg" = --count ]; then mode=count; else tree=$(realpath "$arg"); fi
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$tree"
# Outside the tables, and inside them: from a `...table() {` line to the closing brace
# at column 0.
find src planners benchmarks include -type f \( -name '*.cpp' -o -name '*.h' \) 2>/dev/null | sort |
  while read -r f; do
    awk -v out="$work/outside" -v in_="$work/inside" '
      /table\(\) \{$/ { skip = 1 }
      { print FILENAME ":" FNR ": " $0 >> (skip ? in_ : out) }
      skip && /^}/ { skip = 0 }' "$f"
  done
touch "$work/outside" "$work/inside"
grep -F "src/app/scenario.cpp:" "$work/outside" > "$work/hand" || true
many=0
while read -r full; do
  [ -n "$full" ] || continue
  name=${full#*.}
  patterns=(-e "\"$full\"")
  if [[ $name == *_* ]] && [[ " ${shared_names[*]} " != *" $name "* ]]; then
    if [ "$mode" = check ] && grep -qE "\(\"$name\"" "$work/hand"; then
      echo "config_keys: pending: \"$name\" is also a key of a section read by hand" >&2
    else
      patterns+=(-e "\"$name\"")
    fi
  fi
  n=$(grep -cF "${patterns[@]}" "$work/outside" || true)
  if [ "$mode" = count ]; then
    grep -qF -e "\"$name\"" "$work/inside" && n=$((n + 1))
    [ "$n" -gt 1 ] && many=$((many + 1))
  else
    grep -F "${patterns[@]}" "$work/outside" | sed "s|^|$full: |" >> "$work/hits" || true
  fi
done < "$keys"
if [ "$mode" = count ]; then
  echo "$many"
  exit 0
fi
if [ -s "$work/hits" ]; then
  echo "config_keys: config keys written outside the parameter tables (name them through Config::keyOf or the table's row):" >&2
  cat "$work/hits" >&2
  exit 1
fi
echo "config_keys: every config key is written in its table only"
