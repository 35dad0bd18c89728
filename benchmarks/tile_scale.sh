#!/usr/bin/env bash
# The tiling scale benchmark (issue 34; table in benchmarks/README.md, "Tiles").
#
#   bash benchmarks/tile_scale.sh [--nodes "1 4 16"] CASE...     CASE: viaduct:KM | airborne
#
# viaduct:KM: the bridge of scenarios/bridge_sampled.yaml repeated for KM km
# (uavip_site_cloud --viaduct, 10 cm sampling) with benchmarks/viaduct.yaml, tiles of
# 100 m; airborne: autzen_trim.las repeated 3 x 6 (1 km², 1.98 M points), tiles of
# 250 m, no config. Per case: uavip tile, every run-tile one after another (each its own
# process, as a Slurm task would be), every plan-section likewise (the second array),
# then the merge that joins them (--require-sections); wall time and peak RSS of each
# (GNU time). Prints one Markdown row per case: points, tiles, sections, the wall
# times, the largest peak RSS of a tile task, a section task and the merge, the serial
# share ((tile + merge) / one machine), the CPU time (user + system) of all steps and
# per km (CPU time is what a shared machine's load disturbs least), and the projected
# wall time on N nodes of 2 cores (tile + the per-tile times scheduled longest first on
# N nodes + the per-section times likewise + merge).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD_DIR:-build}
UAVIP=$(realpath "$BUILD/uavip")
NODES="1 4 16"
[[ ${1:-} == --nodes ]] && { NODES=$2; shift 2; }
W=${UAVIP_BENCH_DIR:-/tmp/uavip-tile-scale}
mkdir -p "$W"
echo "| case | points | tiles | sections | tile s | run-tile s (sum / max) | plan-section s (sum / max) | merge s | peak RSS tile / section / merge MB | serial share | one machine s | CPU s | CPU s per km | projected on $(echo $NODES | sed 's/ / \/ /g') nodes s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
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
  ns=$("$UAVIP" plan-section "$d/T/manifest.json" --list | awk '/^sections:/ {print $2}')
  : >"$d/sections.t"
  for ((i = 0; i < ns; i++)); do
    /usr/bin/time -o "$d/one.t" -f "%e %M %U %S" "$UAVIP" -q plan-section "$d/T/manifest.json" --section "$i" --no-views
    cat "$d/one.t" >>"$d/sections.t"
  done
  /usr/bin/time -o "$d/merge.t" -f "%e %M %U %S" "$UAVIP" merge "$d/T/manifest.json" -o "$d/out" --no-views --require-sections >"$d/merge.txt"
  awk -v name="$case" -v points="$points" -v n="$n" -v ns="$ns" -v km="$km" -v nodes="$NODES" \
      -v tile="$(cat "$d/tile.t")" -v merge="$(cat "$d/merge.t")" '
    FNR == 1 { f++ }
    f == 1 { t[++nt] = $1; sum += $1; cpu += $3 + $4; if ($1 > max) max = $1; if ($2 > rss) rss = $2 }
    f == 2 { u[++nu] = $1; ssum += $1; cpu += $3 + $4; if ($1 > smax) smax = $1; if ($2 > srss) srss = $2 }
    # the span of times x[1..c] scheduled longest first onto the least loaded of N nodes
    function span(x, c, nn,   i, j, m, lo, y, load, s) {
      for (i = 1; i <= c; i++) for (j = i + 1; j <= c; j++) if (x[j] > x[i]) { y = x[i]; x[i] = x[j]; x[j] = y }
      for (m = 1; m <= nn; m++) load[m] = 0;
      for (i = 1; i <= c; i++) { lo = 1; for (m = 2; m <= nn; m++) if (load[m] < load[lo]) lo = m; load[lo] += x[i] }
      s = 0; for (m = 1; m <= nn; m++) if (load[m] > s) s = load[m];
      return s
    }
    END {
      split(tile, a, " "); split(merge, b, " ");
      proj = ""; k = split(nodes, ns_, " ");
      for (q = 1; q <= k; q++)
        proj = proj (q > 1 ? " / " : "") sprintf("%.0f", a[1] + span(t, nt, ns_[q]) + span(u, nu, ns_[q]) + b[1]);
      total = a[1] + sum + ssum + b[1];
      cpu += a[3] + a[4] + b[3] + b[4];
      printf "| %s | %d | %d | %d | %.1f | %.1f / %.1f | %.1f / %.1f | %.1f | %.0f / %.0f / %.0f | %.1f %% | %.0f | %.0f | %.0f | %s |\n",
        name, points, n, ns, a[1], sum, max, ssum, smax, b[1], rss / 1024, srss / 1024, b[2] / 1024,
        100 * (a[1] + b[1]) / total, total, cpu, cpu / km, proj
    }' "$d/tiles.t" "$d/sections.t"
done
