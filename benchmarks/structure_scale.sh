#!/usr/bin/env bash
# Cost as work grows (issue 31; table in benchmarks/README.md, "Structure coverage as
# work grows").
#
#   bash benchmarks/structure_scale.sh [RUNS]
#
# The tower of scenarios/tower.yaml (a 6 x 6 m shaft with a 10 x 10 x 1 m platform at
# three quarters of its height, on a ground of 40 x 40 m), sensed by surface sampling,
# then detect + plan --cover structure (uavip run, views off):
#   - points: the 40 m tower sampled every 0.2, 0.1 and 0.05 m (1 x, 4 x, 16 x points);
#   - size:   towers of 24, 48 and 96 m sampled every 0.2 m (surface area ~ height).
# Per case, the median of RUNS runs (default 3) of detect (preprocess + perception, from
# scene.json) and plan (grid, views, legs, flight, from mission.json), and the largest
# peak RSS of the process (GNU time; sensing included).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD_DIR:-build}
UAVIP=$(realpath "$BUILD/uavip")
RUNS=${1:-3}
W=${UAVIP_BENCH_DIR:-/tmp/uavip-structure-scale}
mkdir -p "$W"

# scenario HEIGHT SPACING FILE
scenario() {
  local h=$1 s=$2
  python3 - "$h" "$s" >"$3" <<'EOF'
import sys
h, s = float(sys.argv[1]), float(sys.argv[2])
p = 0.75 * h
print(f"""name: tower_{h:g}m_{s:g}
world:
  - {{type: box, name: shaft, min: [-3.0, -3.0, 0.0], max: [3.0, 3.0, {h}]}}
  - {{type: box, name: platform, min: [-5.0, -5.0, {p}], max: [5.0, 5.0, {p + 1.0}]}}
  - {{type: plane, name: ground, corner: [-20.0, -20.0, 0.0], edge_u: [40.0, 0.0, 0.0], edge_v: [0.0, 40.0, 0.0]}}
sensing: {{mode: sample, spacing_m: {s}, noise_sigma_m: 0.01, outlier_fraction: 0.0, seed: 4, viewpoint: [20.0, -20.0, {h / 2}]}}
coverage: {{mode: structure}}""")
EOF
}

echo "| case | height [m] | spacing [m] | points | photos | detect [s] | plan [s] | detect + plan [s] | per 100 k points [s] | peak RSS [MB] |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for c in "points-1x 40 0.2" "points-4x 40 0.1" "points-16x 40 0.05" \
         "size-24m 24 0.2" "size-48m 48 0.2" "size-96m 96 0.2"; do
  read -r name h s <<<"$c"
  d="$W/$name"
  mkdir -p "$d"
  scenario "$h" "$s" "$d/scenario.yaml"
  : >"$d/runs.txt"
  for ((r = 0; r < RUNS; ++r)); do
    /usr/bin/time -f '%M' -o "$d/rss.txt" "$UAVIP" run "$d/scenario.yaml" -o "$d/out" --no-views -q \
      >/dev/null
    python3 - "$d/out" "$(cat "$d/rss.txt")" >>"$d/runs.txt" <<'EOF'
import json, sys
scene = json.load(open(sys.argv[1] + "/scene.json"))
mission = json.load(open(sys.argv[1] + "/mission.json"))
t = mission["timings"]  # coverage_s counts from the start of planning, the grid included
detect = scene["timings"]["preprocess_s"] + scene["timings"]["perception_s"]
plan = t["coverage_s"] + t["planning_s"] + t["flight_s"]
photos = sum(m["stop_count"] for m in mission["surfaces"])
print(scene["cloud"]["points"], photos, detect, plan, int(sys.argv[2]) / 1024)
EOF
  done
  python3 - "$name" "$h" "$s" "$d/runs.txt" <<'EOF'
import statistics, sys
rows = [l.split() for l in open(sys.argv[4]) if l.strip()]
pts, photos = int(rows[0][0]), int(rows[0][1])
det = statistics.median(float(r[2]) for r in rows)
plan = statistics.median(float(r[3]) for r in rows)
rss = max(float(r[4]) for r in rows)
print(f"| {sys.argv[1]} | {sys.argv[2]} | {sys.argv[3]} | {pts} | {photos} | {det:.2f} | {plan:.2f} | "
      f"{det + plan:.2f} | {100000 * (det + plan) / pts:.3f} | {rss:.0f} |")
EOF
done
