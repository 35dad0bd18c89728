#!/usr/bin/env bash
# Unseen structures with defaults (issue 31; table in benchmarks/README.md): for each
# cloud, `uavip detect CLOUD` then `uavip plan scene.json --cover structure`, no config,
# views off; the median of RUNS wall times of the two commands (process start and file
# writing included), the photos and both coverage rules of the last run.
#
#   bash benchmarks/structure_defaults.sh [--runs N] CLOUD...
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD_DIR:-build}
UAVIP=$(realpath "$BUILD/uavip")
RUNS=3
[[ ${1:-} == --runs ]] && { RUNS=$2; shift 2; }
W=${UAVIP_BENCH_DIR:-/tmp/uavip-structure-defaults}
mkdir -p "$W"
echo "| cloud | photos | rule (a) | rule (b) | detect [s] | plan [s] | detect + plan [s] |"
echo "|---|---|---|---|---|---|---|"
for cloud in "$@"; do
  d="$W/$(basename "${cloud%.*}")"
  mkdir -p "$d"
  : >"$d/times.txt"
  for ((r = 0; r < RUNS; ++r)); do
    t0=$(date +%s.%N)
    "$UAVIP" detect "$cloud" -o "$d" --no-views -q
    t1=$(date +%s.%N)
    "$UAVIP" plan "$d/scene.json" --cover structure -o "$d" --no-views -q
    t2=$(date +%s.%N)
    echo "$t0 $t1 $t2" >>"$d/times.txt"
  done
  python3 - "$cloud" "$d" <<'EOF'
import json, statistics, sys
rows = [[float(x) for x in l.split()] for l in open(sys.argv[2] + "/times.txt") if l.strip()]
det = statistics.median(r[1] - r[0] for r in rows)
plan = statistics.median(r[2] - r[1] for r in rows)
tot = statistics.median(r[2] - r[0] for r in rows)
m = json.load(open(sys.argv[2] + "/mission.json"))
s = m["structure"]
print(f"| {sys.argv[1].split('/')[-1]} | {s['photos']} | {100 * s['coverage_rule_a']:.1f} % | "
      f"{100 * s['coverage_rule_b']:.1f} % | {det:.2f} | {plan:.2f} | {tot:.2f} |")
EOF
done
