#!/usr/bin/env bash
# fleet_bench.sh [UAVIP] [SCENARIO…]: makespan of K = 1..5 UAVs (planning/fleet.h) per
# scenario, against one UAV and the lower bound, with the closest approach, the waits
# and the run time (sense, detect, plan); every fleet re-checked by `uavip validate` (exit 0 required).
# Prints one Markdown table row per (scenario, K); KS="1 2" limits the fleet sizes. Default scenarios: single_cube,
# tower, bridge_sampled.
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
for s in "${scenarios[@]}"; do
  for k in ${KS:-1 2 3 4 5}; do
    out="$work/$s-$k"
    start=$(date +%s.%N)
    "$uavip" run "scenarios/$s.yaml" --uavs "$k" -q --no-views -o "$out" >/dev/null 2>&1 || true
    end=$(date +%s.%N)
    v=$("$uavip" validate "$out/mission.json" -q >/dev/null 2>&1 && echo ok || echo "FAILED")
    python3 - "$out/mission.json" "$s" "$k" "$start" "$end" "$v" <<'EOF'
import json, sys
path, s, k, t0, t1, v = sys.argv[1:]
m = json.load(open(path))
f = m.get("fleet")
secs = float(t1) - float(t0)
if f is None:  # K = 1: the single flight
    d = m["flight"]["duration_s"] / 60
    n = len(m["flight"]["sorties"])
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
  done
done
