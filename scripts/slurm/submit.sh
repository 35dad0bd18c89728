#!/usr/bin/env bash
# Submits a tiled site (uavip tile → TILES/manifest.json) to Slurm:
#   one job array, a task per tile:  uavip run-tile TILES/manifest.json --index $SLURM_ARRAY_TASK_ID
#   the merge, after every task succeeded (--dependency=afterok, --kill-on-invalid-dep=yes):
#                                    uavip merge TILES/manifest.json -o OUT
# and prints both job ids. --cpus-per-task and --mem come from the manifest's largest
# tile (core + buffer points; the memory model is in benchmarks/README.md).
#
#   scripts/slurm/submit.sh TILES/ [-o OUT] [--array LIST] [--wait] [-- extra sbatch options]
#
# --array LIST (e.g. 3,7 or 2-5) submits only those tiles (a rerun of failed ones; the
# others keep their results) and the merge after them.
# OUT defaults to TILES/merged. Logs: TILES/slurm/tile_<index>.out, TILES/slurm/merge.out.
# --wait: waits for the merge; prints each task's state and time; a failed tile is
# named with its index and the command that reruns it (exit 1). UAVIP names the uavip
# binary (default: uavip on PATH, else build/uavip of this checkout).
set -euo pipefail
usage() { echo "usage: $0 TILES/ [-o OUT] [--array LIST] [--wait] [-- sbatch options]" >&2; exit 2; }
[[ $# -ge 1 ]] || usage
TILES=$(cd "$1" && pwd) || usage
shift
OUT="$TILES/merged"
WAIT=0
EXTRA=()
LIST=""
while [[ $# -gt 0 ]]; do
  case $1 in
    -o) OUT=$(realpath -m "$2"); shift 2 ;;
    --wait) WAIT=1; shift ;;
    --array) LIST=$2; shift 2 ;;
    --array=*) LIST=${1#--array=}; shift ;;
    --) shift; EXTRA=("$@"); break ;;
    *) usage ;;
  esac
done
MANIFEST="$TILES/manifest.json"
[[ -f $MANIFEST ]] || { echo "submit: error: $MANIFEST: no manifest; run uavip tile first" >&2; exit 2; }
UAVIP=${UAVIP:-$(command -v uavip || echo "$(cd "$(dirname "$0")/../.." && pwd)/build/uavip")}
UAVIP=$(realpath "$UAVIP")
[[ -x $UAVIP ]] || { echo "submit: error: $UAVIP: no uavip binary; set UAVIP=/path/to/uavip" >&2; exit 2; }

# The manifest (manifest.json, one key a line): tiles, and the largest tile's points.
TILE_COUNT=$(grep -c '"index":' "$MANIFEST" || true)
[[ $TILE_COUNT -gt 0 ]] || { echo "submit: error: $MANIFEST holds no tile" >&2; exit 2; }
# Within a tile's object the keys are sorted: buffer_points, ..., core_points, index.
LARGEST=$(awk -F'[:,]' '/"buffer_points":/ {b = $2; nb = 1} /"core_points":/ {c = $2; nc = 1}
  /"index":/ {if (nb && nc && b + c > m) m = b + c; nb = nc = 0} END {printf "%d", m}' "$MANIFEST")
# Memory per task [MB]: 300 MB + 1 kB per point of the largest tile, about twice the
# measured peak RSS of run-tile (90 MB + 0.5-0.6 kB a point; benchmarks/README.md,
# "Tiles on Slurm").
MEM_MB=$(( 300 + LARGEST / 1000 ))
CPUS=${UAVIP_TILE_CPUS:-2}  # stage 3 runs 2 threads
mkdir -p "$TILES/slurm"

LIST=${LIST:-0-$((TILE_COUNT - 1))}
ARRAY=$(sbatch --parsable --job-name=uavip-tile --array="$LIST" \
  --cpus-per-task="$CPUS" --mem="${MEM_MB}M" --output="$TILES/slurm/tile_%a.out" \
  "${EXTRA[@]}" --wrap="exec '$UAVIP' -v run-tile '$MANIFEST' --index \$SLURM_ARRAY_TASK_ID")
ARRAY=${ARRAY%%;*}
MERGE=$(sbatch --parsable --job-name=uavip-merge --dependency="afterok:$ARRAY" \
  --kill-on-invalid-dep=yes --cpus-per-task="$CPUS" --output="$TILES/slurm/merge.out" \
  "${EXTRA[@]}" --wrap="exec '$UAVIP' -v merge '$MANIFEST' -o '$OUT'")
MERGE=${MERGE%%;*}
echo "tiles: job $ARRAY (array $LIST of $TILE_COUNT tiles, $CPUS CPUs and ${MEM_MB} MB per task, largest tile $LARGEST points)"
echo "merge: job $MERGE (after every tile succeeded) -> $OUT"
printf 'ARRAY_JOB=%s\nMERGE_JOB=%s\n' "$ARRAY" "$MERGE" >"$TILES/slurm/jobs.env"
[[ $WAIT == 1 ]] || exit 0

# Waits until neither job is pending or running, then reports every task from
# scontrol (no accounting database needed; MinJobAge keeps finished jobs listed).
while squeue -h -j "$ARRAY,$MERGE" -o %i 2>/dev/null | grep -q .; do sleep 2; done
failed=()
while read -r line; do
  id=$(grep -o 'ArrayTaskId=[0-9]*' <<<"$line" | cut -d= -f2)
  state=$(grep -o 'JobState=[A-Z_]*' <<<"$line" | cut -d= -f2)
  run=$(grep -o 'RunTime=[0-9:-]*' <<<"$line" | cut -d= -f2)
  echo "  tile $id: $state, $run"
  [[ $state == COMPLETED ]] || failed+=("$id")
done < <(scontrol -o show job "$ARRAY" | grep ArrayTaskId= | sort -t= -k1,1)
mline=$(scontrol -o show job "$MERGE" 2>/dev/null || true)
mstate=$(grep -o 'JobState=[A-Z_]*' <<<"$mline" | cut -d= -f2 || true)
mrun=$(grep -o 'RunTime=[0-9:-]*' <<<"$mline" | cut -d= -f2 || true)
echo "  merge: ${mstate:-gone}, ${mrun:-}"
if ((${#failed[@]})); then
  list=$(IFS=,; echo "${failed[*]}")
  echo "submit: tile(s) $list failed (logs $TILES/slurm/tile_<index>.out); the merge did not run." \
    "Rerun them and the merge: $0 $TILES -o $OUT --array $list" >&2
  exit 1
fi
[[ $mstate == COMPLETED ]] || { echo "submit: the merge ended $mstate (log $TILES/slurm/merge.out)" >&2; exit 1; }
echo "done: $OUT/mission.json"
