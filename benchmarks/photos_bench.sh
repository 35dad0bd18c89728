#!/usr/bin/env bash
# The photos of a plan (issue 46): plans each case once, then runs `uavip photos` RUNS
# times and prints a Markdown row per case: photos, image size, megapixels, the wall time
# of rendering + PNG encoding + staging (the command's own figure) as the median of RUNS,
# seconds per megapixel, PNG size, and the load average before the runs.
# Usage: bash benchmarks/photos_bench.sh [RUNS] [BUILD_DIR] [THREADS]   (python3 for the medians)
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${1:-5}
BUILD=${2:-build}
THREADS=${3:-0}
UAVIP="$BUILD/uavip"
OUT=$(mktemp -d /tmp/uavip_photos_bench.XXXXXX)
trap 'rm -rf "$OUT"' EXIT

# name | plan command (the world is the scenario's)
cases=(
  "single_cube|scenarios/single_cube.yaml|run scenarios/single_cube.yaml"
  "bridge (sampled; deck, pier, trees, grass)|scenarios/bridge_sampled.yaml|run scenarios/bridge_sampled.yaml"
  "tower (--cover structure, 20 MP)|scenarios/tower.yaml|run scenarios/tower.yaml"
)
median() { python3 -c 'import statistics,sys; print(f"{statistics.median(float(x) for x in sys.argv[1:]):.3f}")' "$@"; }
threads_opt=""
[ "$THREADS" != 0 ] && threads_opt="--threads $THREADS"

echo "| case | photos | image | MP | photos s (median of $RUNS) | s / MP | PNG MB | load before |"
echo "|---|---|---|---|---|---|---|---|"
for c in "${cases[@]}"; do
  IFS='|' read -r name world plan <<<"$c"
  dir="$OUT/$(echo "$name" | cut -d' ' -f1)"
  # shellcheck disable=SC2086
  "$UAVIP" $plan --no-views -q -o "$dir" || [ $? -eq 3 ]
  load=$(cut -d' ' -f1 /proc/loadavg)
  times=()
  for _ in $(seq "$RUNS"); do
    # shellcheck disable=SC2086
    line=$("$UAVIP" photos "$dir/mission.json" --world "$world" -o "$dir/photos" $threads_opt | head -1)
    times+=("$(echo "$line" | sed -E 's/.* MP, ([0-9.]+) s,.*/\1/')")
    mp=$(echo "$line" | sed -E 's/.*\(([0-9.]+) MP,.*/\1/')
    n=$(echo "$line" | sed -E 's/^photos: ([0-9]+) .*/\1/')
  done
  t=$(median "${times[@]}")
  size=$(python3 -c "import json; c=json.load(open('$dir/photos/photos.json'))['camera']; print(f\"{c['width_px']} x {c['height_px']}\")")
  mb=$(du -sm "$dir/photos/images" | cut -f1)
  echo "| $name | $n | $size | $mp | $t | $(python3 -c "print(f'{$t/$mp:.3f}')") | $mb | $load |"
done
