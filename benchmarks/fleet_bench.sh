#!/usr/bin/env bash
# fleet_bench.sh [UAVIP] [SCENARIO…]: makespan of K = 1..5 UAVs (planning/fleet.h) per
# scenario, against one UAV and the lower bound, with the closest approach, the waits
# and the run time (sense, detect, plan); every fleet re-checked by `uavip validate` (exit 0 required).
# Prints one Markdown table row per (scenario, K); KS="1 2" limits the fleet sizes. Default scenarios: single_cube,
# tower, bridge_sampled.
# A scenario viaduct:KM is the tiled site of tile_scale.sh (uavip_site_cloud --viaduct KM,
# benchmarks/viaduct.yaml, tiles of 100 m): tiled, every tile and section planned once
# for one UAV (or taken from SITE_DIR/KM/T when that holds them), then
# `merge --uavs K --require-sections` flies the sections at once (docs/fleet.md) and
# `uavip validate site.json` re-checks it; run time is the merge's (KS default 1 2 4 8).
# A scenario structure:CLOUD (e.g. structure:tests/data/fcplanner_MBS.pcd) is a real
# cloud: `uavip detect` once, then `uavip plan --cover structure --uavs K` (run time: the
# plan).
set -euo pipefail
cd "$(dirname "$0")/.."
uavip=${1:-build/uavip}
shift || true
scenarios=("$@")
[ ${#scenarios[@]} -gt 0 ] || scenarios=(single_cube tower bridge_sampled)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| scenario | K | makespan [min] | one UAV [min] | speed-up | lower bound [min] | makespan / bound | waits | closest approach nominal / swept [m] | UAVs flying | sorties per UAV | run time [s] | validate |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
row() {  # FILE (mission.json, or site.json of a merge) SCENARIO K SECONDS VALIDATE: one row
  python3 - "$@" <<'EOF'
import json, sys
path, s, k, secs, v = sys.argv[1:]
doc = json.load(open(path))
f = doc.get("fleet")
secs = float(secs)
if f is None:  # K = 1: the single flight (a site: its sections' flights)
    if "sections" in doc:
        n = sum(x["sorties"] for x in doc["sections"])
        print(f"| {s} | {k} | – | – | 1.00 | – | – | – | – | 1 | {n} | {secs:.1f} | {v} |")
    else:
        d = doc["flight"]["duration_s"] / 60
        n = len(doc["flight"]["sorties"])
        print(f"| {s} | {k} | {d:.1f} | {d:.1f} | 1.00 | – | – | – | – | 1 | {n} | {secs:.1f} | {v} |")
    sys.exit()
flying = [u for u in f["uavs"] if u["sorties"]]
ca = f["closest_approach"]
nom = "–" if ca["nominal_m"] is None else f"{ca['nominal_m']:.1f}"
sw = "–" if ca["swept_m"] is None else f"{ca['swept_m']:.1f}"
print(f"| {s} | {k} | {f['makespan_s']/60:.1f} | {f['single_uav_s']/60:.1f} | {f['speedup']:.2f} | "
      f"{f['lower_bound_s']/60:.1f} | {f['makespan_s']/f['lower_bound_s']:.2f} | {f['waits']} | "
      f"{nom} / {sw} | {len(flying)} | {'/'.join(str(len(u['sorties'])) for u in f['uavs'])} | "
      f"{secs:.1f} | {v} |")
EOF
}

site_case() {  # viaduct:KM
  local s=$1 km=${1#viaduct:} bin t
  bin=$(dirname "$uavip")
  t="$work/$s/T"
  if [ -n "${SITE_DIR:-}" ] && [ -f "$SITE_DIR/$km/T/manifest.json" ]; then
    t="$SITE_DIR/$km/T"
  else
    mkdir -p "$work/$s"
    "$bin/uavip_site_cloud" --viaduct "$km" -o "$work/$s/cloud.xyz" >/dev/null
    "$uavip" -q tile "$work/$s/cloud.xyz" --tile-size 100 -c benchmarks/viaduct.yaml -o "$t"
    local n ns i
    n=$(grep -c '"index":' "$t/manifest.json")
    for ((i = 0; i < n; i++)); do "$uavip" -q run-tile "$t/manifest.json" --index "$i"; done
    ns=$("$uavip" plan-section "$t/manifest.json" --list | awk '/^sections:/ {print $2}')
    for ((i = 0; i < ns; i++)); do
      "$uavip" -q plan-section "$t/manifest.json" --section "$i" --no-views
    done
  fi
  for k in ${KS:-1 2 4 8}; do
    local out="$work/$s-$k" start end v
    start=$(date +%s.%N)
    "$uavip" -q merge "$t/manifest.json" -o "$out" --no-views --require-sections --uavs "$k" \
      >/dev/null 2>&1 || true
    end=$(date +%s.%N)
    v="–"
    if [ "$k" != 1 ]; then
      v=$("$uavip" validate "$out/site.json" -q >/dev/null 2>&1 && echo ok || echo FAILED)
    fi
    row "$out/site.json" "$s" "$k" "$(python3 -c "print($end - $start)")" "$v"
  done
}

for s in "${scenarios[@]}"; do
  if [[ $s == viaduct:* ]]; then
    site_case "$s"
    continue
  fi
  if [[ $s == structure:* ]]; then
    scene="$work/$(basename "${s#structure:}")"
    "$uavip" detect "${s#structure:}" -q --no-views -o "$scene"
  fi
  for k in ${KS:-1 2 3 4 5}; do
    out="$work/$(basename "$s")-$k"
    start=$(date +%s.%N)
    if [[ $s == structure:* ]]; then
      mkdir -p "$out"
      cp "$scene"/*.json "$scene"/*.pcd "$out/"
      "$uavip" plan "$out/scene.json" --cover structure --uavs "$k" -q --no-views -o "$out" \
        >/dev/null 2>&1 || true
    else
      "$uavip" run "scenarios/$s.yaml" --uavs "$k" -q --no-views -o "$out" >/dev/null 2>&1 || true
    fi
    end=$(date +%s.%N)
    v=$("$uavip" validate "$out/mission.json" -q >/dev/null 2>&1 && echo ok || echo "FAILED")
    row "$out/mission.json" "$s" "$k" "$(python3 -c "print($end - $start)")" "$v"
  done
done
