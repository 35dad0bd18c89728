#!/usr/bin/env bash
# CI step: one small tiled job through real Slurm, checked against the same
# tiles run one after another in one shell. Brings up a one-node Slurm
# (scripts/slurm/local.sh), tiles the bundled airborne LAS (autzen_trim.las, 6 tiles
# of 120 m, a section per tile), submits it (scripts/slurm/submit.sh --wait: the tiles'
# job array, the sections' job array, then the merge that joins them), runs the same
# tiles and a merge that plans every section itself in this shell, and compares each
# section's mission.json (all but the timings and the manifest's path) and scene.json
# (all but the timings). Then the faults on that Slurm path (scripts/slurm/faults.sh).
# Stops the daemons it started and removes its files, also on failure.
set -euo pipefail
cd "$(dirname "$0")/../.."
ROOT=$(pwd)
UAVIP=$(realpath "${UAVIP:-${BUILD_DIR:-build}/uavip}")
W=$(mktemp -d /tmp/uavip-slurm-ci.XXXXXX)
started=0
cleanup() {
  [[ $started == 1 ]] && bash "$ROOT/scripts/slurm/local.sh" stop || true
  rm -rf "$W"
}
trap cleanup EXIT
bash scripts/slurm/local.sh start
started=1
t0=$(date +%s.%N)
"$UAVIP" -q tile tests/data/autzen_trim.las --tile-size 120 -o "$W/slurm"
cp -r "$W/slurm" "$W/shell"  # the same tiles, before any result
t1=$(date +%s.%N)
K=1  # sections of one tile: six section tasks
UAVIP=$UAVIP bash scripts/slurm/submit.sh "$W/slurm" -o "$W/slurm/merged" --section-tiles $K --wait
t2=$(date +%s.%N)
n=$(grep -c '"index":' "$W/shell/manifest.json")
for ((i = 0; i < n; i++)); do "$UAVIP" -q run-tile "$W/shell/manifest.json" --index "$i"; done
"$UAVIP" -q merge "$W/shell/manifest.json" -o "$W/shell/merged" --section-tiles $K
t3=$(date +%s.%N)
strip() { sed -e '/"timings": {/,/}/d' -e '/"source":/d' -e '/"preprocess_s":/d' -e '/"perception_s":/d' "$1"; }
for f in $(cd "$W/slurm/merged" && find . -name mission.json -o -name scene.json); do
  if ! diff <(strip "$W/slurm/merged/$f") <(strip "$W/shell/merged/$f") >"$W/diff.txt"; then
    echo "slurm-ci: $f differs between Slurm and the shell:" >&2
    head -n 20 "$W/diff.txt" >&2
    exit 1
  fi
done
awk -v n="$n" -v a="$t0" -v b="$t1" -v c="$t2" -v d="$t3" 'BEGIN {
  printf "slurm-ci: %d tiles; Slurm (tiles, sections, merge) %.1f s, one shell %.1f s, tiling %.1f s; every mission.json and scene.json equal\n", n, c - b, d - c, b - a }'
cat "$W/slurm/slurm/jobs.env"
t4=$(date +%s.%N)
K=$K UAVIP=$UAVIP bash scripts/slurm/faults.sh "$W/slurm" "$W/slurm/merged"
t5=$(date +%s.%N)
awk -v a="$t4" -v b="$t5" 'BEGIN { printf "slurm-ci: faults %.1f s\n", b - a }'
