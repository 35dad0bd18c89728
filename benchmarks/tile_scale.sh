#!/usr/bin/env bash
# The tiling scale benchmark (issue 34; table in benchmarks/README.md, "Tiles").
#
#   bash benchmarks/tile_scale.sh [--nodes "1 4 16"] CASE...     CASE: viaduct:KM | airborne
#
# viaduct:KM: the bridge of scenarios/bridge_sampled.yaml repeated for KM km
# (uavip_site_cloud --viaduct, 10 cm sampling) with benchmarks/viaduct.yaml, tiles of
# 100 m; airborne: autzen_trim.las repeated 3 x 6 (1 km², 1.98 M points), tiles of
# 250 m, no config. Per case: uavip tile, every run-tile one after another (each its own
# process, as a Slurm task would be), merge; wall time and peak RSS of each (GNU time).
# Prints one Markdown row per case: points, tiles, the wall times, the largest peak RSS
# of a tile task and of the merge, the CPU time (user + system) of all steps and per
# km (CPU time is what a shared machine's load disturbs least), and the projected wall
# time on N nodes of 2 cores (tile + the per-tile times scheduled longest first on N
# nodes + merge).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD_DIR:-build}
UAVIP=$(realpath "$BUILD/uavip")
NODES="1 4 16"
[[ ${1:-} == --nodes ]] && { NODES=$2; shift 2; }
W=${UAVIP_BENCH_DIR:-/tmp/uavip-tile-scale}
mkdir -p "$W"
echo "| case | points | tiles | tile s | run-tile s (sum / max) | merge s | peak RSS tile task MB | peak RSS merge MB | one machine s | CPU s | CPU s per km | projected on $(echo $NODES | sed 's/ / \/ /g') nodes s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for case in "$@"; do
  d="$W/$case"
  rm -rf "$d"
  mkdir -p "$d"
  config=()
  size=100
  km=0
  if [[ $case == viaduct:* ]]; then
    km=${case#viaduct:}
    "$BUILD/uavip_site_cloud" --viaduct "$km" -o "$d/cloud.xyz" >"$d/generate.txt"
    config=(-c benchmarks/viaduct.yaml)
  elif [[ $case == airborne ]]; then
    "$BUILD/uavip_site_cloud" --repeat tests/data/autzen_trim.las 3 6 -o "$d/cloud.xyz" >"$d/generate.txt"
    size=250
    km=1
  else
    echo "tile_scale: unknown case $case" >&2
    exit 2
  fi
  points=$(wc -l <"$d/cloud.xyz")
  /usr/bin/time -o "$d/tile.t" -f "%e %M %U %S" "$UAVIP" -q tile "$d/cloud.xyz" --tile-size "$size" "${config[@]}" -o "$d/T"
  n=$(grep -c '"index":' "$d/T/manifest.json")
  : >"$d/tiles.t"
  for ((i = 0; i < n; i++)); do
    /usr/bin/time -o "$d/one.t" -f "%e %M %U %S" "$UAVIP" -q run-tile "$d/T/manifest.json" --index "$i"
    cat "$d/one.t" >>"$d/tiles.t"
  done
  /usr/bin/time -o "$d/merge.t" -f "%e %M %U %S" "$UAVIP" merge "$d/T/manifest.json" -o "$d/out" --no-views >"$d/merge.txt"
  awk -v name="$case" -v points="$points" -v n="$n" -v km="$km" -v nodes="$NODES" \
      -v tile="$(cat "$d/tile.t")" -v merge="$(cat "$d/merge.t")" '
    { t[NR] = $1; sum += $1; cpu += $3 + $4; if ($1 > max) max = $1; if ($2 > rss) rss = $2 }
    END {
      split(tile, a, " "); split(merge, b, " ");
      # longest first onto the least loaded of N nodes
      for (i = 1; i <= NR; i++) for (j = i + 1; j <= NR; j++) if (t[j] > t[i]) { x = t[i]; t[i] = t[j]; t[j] = x }
      proj = ""; k = split(nodes, ns, " ");
      for (q = 1; q <= k; q++) {
        delete load; for (m = 1; m <= ns[q]; m++) load[m] = 0;
        for (i = 1; i <= NR; i++) { lo = 1; for (m = 2; m <= ns[q]; m++) if (load[m] < load[lo]) lo = m; load[lo] += t[i] }
        span = 0; for (m = 1; m <= ns[q]; m++) if (load[m] > span) span = load[m];
        proj = proj (q > 1 ? " / " : "") sprintf("%.0f", a[1] + span + b[1]);
      }
      total = a[1] + sum + b[1];
      cpu += a[3] + a[4] + b[3] + b[4];
      printf "| %s | %d | %d | %.1f | %.1f / %.1f | %.1f | %.0f | %.0f | %.0f | %.0f | %.0f | %s |\n",
        name, points, n, a[1], sum, max, b[1], rss / 1024, b[2] / 1024, total, cpu, cpu / km, proj
    }' "$d/tiles.t"
done
