#!/usr/bin/env bash
# Submits a tiled site (uavip tile → TILES/manifest.json) to Slurm as three jobs, each
# started only after the one before succeeded (--dependency=afterok,
# --kill-on-invalid-dep=yes):
#   tiles, a job array, a task per tile:
#     uavip run-tile TILES/manifest.json --index $SLURM_ARRAY_TASK_ID
#   sections, a job array, a task per section (uavip plan-section --list):
#     uavip plan-section TILES/manifest.json --section $SLURM_ARRAY_TASK_ID --if-stale
#   the merge, which only joins the sections' results, indexes and validates:
#     uavip merge TILES/manifest.json -o OUT --require-sections
# and prints the job ids. --cpus-per-task and --mem come from the manifest's largest
# tile and section (points; the memory model is in benchmarks/README.md).
#
#   scripts/slurm/submit.sh TILES/ [-o OUT] [--array LIST | --sections LIST | --merge-only]
#                           [--section-tiles K] [--wait] [-- extra sbatch options]
#
# --array LIST (e.g. 3,7 or 2-5): only those tiles (a rerun of failed ones; the others
# keep their results), then every section (a section whose result is up to date for its
# tiles' results is left as it is: --if-stale), then the merge. --sections LIST: only
# those sections (no tile), then the merge. --merge-only: the merge alone.
# --section-tiles K: sections of K x K tiles (uavip merge --section-tiles).
# OUT defaults to TILES/merged. Logs: TILES/slurm/tile_<index>.out,
# TILES/slurm/section_<index>.out, TILES/slurm/merge.out.
# --wait: waits for the merge; prints each task's state and time; a failed task is
# named with its index and the command that reruns it (exit 1). UAVIP names the uavip
# binary (default: uavip on PATH, else build/uavip of this checkout).
set -euo pipefail
usage() {
  echo "usage: $0 TILES/ [-o OUT] [--array LIST | --sections LIST | --merge-only] [--section-tiles K] [--wait] [-- sbatch options]" >&2
  exit 2
}
[[ $# -ge 1 ]] || usage
TILES=$(cd "$1" && pwd) || usage
shift
OUT="$TILES/merged"
WAIT=0
EXTRA=()
LIST=""
SECTIONS=""
MERGE_ONLY=0
K=0
while [[ $# -gt 0 ]]; do
  case $1 in
    -o) OUT=$(realpath -m "$2"); shift 2 ;;
    --wait) WAIT=1; shift ;;
    --array) LIST=$2; shift 2 ;;
    --array=*) LIST=${1#--array=}; shift ;;
    --sections) SECTIONS=$2; shift 2 ;;
    --sections=*) SECTIONS=${1#--sections=}; shift ;;
    --merge-only) MERGE_ONLY=1; shift ;;
    --section-tiles) K=$2; shift 2 ;;
    --) shift; EXTRA=("$@"); break ;;
    *) usage ;;
  esac
done
[[ -n $LIST && -n $SECTIONS ]] && usage
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
# The sections ("sections: N", then "section S: tiles ...; P points").
LISTING=$("$UAVIP" plan-section "$MANIFEST" --list --section-tiles "$K")
SECTION_COUNT=$(awk '/^sections:/ {print $2}' <<<"$LISTING")
SECTION_POINTS=$(awk '/^section / {if ($(NF - 1) > m) m = $(NF - 1)} END {printf "%d", m}' <<<"$LISTING")
# Memory per task [MB]: a tile 300 MB + 1 kB per point of the largest tile, about twice
# the measured peak RSS of run-tile (90 MB + 0.5-0.6 kB a point); a section 400 MB +
# 1 kB per point of the largest section, about 1.5 times the measured peak RSS of
# plan-section (benchmarks/README.md, "Tiles on Slurm").
MEM_MB=$((300 + LARGEST / 1000))
SECTION_MEM_MB=$((400 + SECTION_POINTS / 1000))
CPUS=${UAVIP_TILE_CPUS:-2}  # stage 3 runs 2 threads
mkdir -p "$TILES/slurm"

ARRAY=""
SECTION_JOB=""
after=()
if [[ -z $SECTIONS && $MERGE_ONLY == 0 ]]; then
  LIST=${LIST:-0-$((TILE_COUNT - 1))}
  ARRAY=$(sbatch --parsable --job-name=uavip-tile --array="$LIST" \
    --cpus-per-task="$CPUS" --mem="${MEM_MB}M" --output="$TILES/slurm/tile_%a.out" \
    "${EXTRA[@]}" --wrap="exec '$UAVIP' -v run-tile '$MANIFEST' --index \$SLURM_ARRAY_TASK_ID")
  ARRAY=${ARRAY%%;*}
  after=(--dependency="afterok:$ARRAY" --kill-on-invalid-dep=yes)
  echo "tiles: job $ARRAY (array $LIST of $TILE_COUNT tiles, $CPUS CPUs and ${MEM_MB} MB per task, largest tile $LARGEST points)"
fi
if [[ $MERGE_ONLY == 0 ]]; then
  SECTIONS=${SECTIONS:-0-$((SECTION_COUNT - 1))}
  SECTION_JOB=$(sbatch --parsable --job-name=uavip-section --array="$SECTIONS" "${after[@]}" \
    --cpus-per-task="$CPUS" --mem="${SECTION_MEM_MB}M" --output="$TILES/slurm/section_%a.out" \
    "${EXTRA[@]}" --wrap="exec '$UAVIP' -v plan-section '$MANIFEST' --section \$SLURM_ARRAY_TASK_ID --section-tiles $K --if-stale")
  SECTION_JOB=${SECTION_JOB%%;*}
  after=(--dependency="afterok:$SECTION_JOB" --kill-on-invalid-dep=yes)
  echo "sections: job $SECTION_JOB (array $SECTIONS of $SECTION_COUNT sections, ${SECTION_MEM_MB} MB per task, largest section $SECTION_POINTS points)"
fi
MERGE=$(sbatch --parsable --job-name=uavip-merge "${after[@]}" \
  --cpus-per-task="$CPUS" --output="$TILES/slurm/merge.out" \
  "${EXTRA[@]}" --wrap="exec '$UAVIP' -v merge '$MANIFEST' -o '$OUT' --section-tiles $K --require-sections")
MERGE=${MERGE%%;*}
echo "merge: job $MERGE (after every section succeeded) -> $OUT"
printf 'ARRAY_JOB=%s\nSECTION_JOB=%s\nMERGE_JOB=%s\n' "$ARRAY" "$SECTION_JOB" "$MERGE" >"$TILES/slurm/jobs.env"
[[ $WAIT == 1 ]] || exit 0

# Waits until no job is pending or running, then reports every task from scontrol (no
# accounting database needed; MinJobAge keeps finished jobs listed).
jobs=$(IFS=,; echo "${ARRAY:+$ARRAY,}${SECTION_JOB:+$SECTION_JOB,}$MERGE")
while squeue -h -j "$jobs" -o %i 2>/dev/null | grep -q .; do sleep 1; done
# "failed" indices of array job $1 (label $2), each task's state and time printed.
report() {
  local line id state run failed=()
  while read -r line; do
    id=$(grep -o 'ArrayTaskId=[0-9]*' <<<"$line" | cut -d= -f2)
    state=$(grep -o 'JobState=[A-Z_]*' <<<"$line" | cut -d= -f2)
    run=$(grep -o 'RunTime=[0-9:-]*' <<<"$line" | cut -d= -f2)
    echo "  $2 $id: $state, $run" >&2
    if [[ $state != COMPLETED ]]; then
      failed+=("$id")
      # what the task said last (an error naming a tile to run again, say)
      grep -h 'uavip: .*error' "$TILES/slurm/$2_$id.out" 2>/dev/null | tail -n 1 | sed 's/^/    /' >&2 || true
    fi
  done < <(scontrol -o show job "$1" | grep ArrayTaskId= | sort -t= -k1,1)
  (IFS=,; echo "${failed[*]}")
}
tile_failed=""
section_failed=""
[[ -n $ARRAY ]] && tile_failed=$(report "$ARRAY" tile)
[[ -n $SECTION_JOB ]] && section_failed=$(report "$SECTION_JOB" section)
mline=$(scontrol -o show job "$MERGE" 2>/dev/null || true)
mstate=$(grep -o 'JobState=[A-Z_]*' <<<"$mline" | cut -d= -f2 || true)
mrun=$(grep -o 'RunTime=[0-9:-]*' <<<"$mline" | cut -d= -f2 || true)
echo "  merge: ${mstate:-gone}, ${mrun:-}" >&2
[[ $mstate == COMPLETED ]] || grep -h 'uavip: .*error' "$TILES/slurm/merge.out" 2>/dev/null | tail -n 1 | sed 's/^/    /' >&2 || true
if [[ -n $tile_failed ]]; then
  echo "submit: tile(s) $tile_failed failed (logs $TILES/slurm/tile_<index>.out); the sections and the merge did not run." \
    "Rerun them, the sections and the merge: $0 $TILES -o $OUT --section-tiles $K --array $tile_failed" >&2
  exit 1
fi
if [[ -n $section_failed ]]; then
  echo "submit: section(s) $section_failed failed (logs $TILES/slurm/section_<index>.out); the merge did not run." \
    "Rerun them and the merge: $0 $TILES -o $OUT --section-tiles $K --sections $section_failed" >&2
  exit 1
fi
if [[ $mstate != COMPLETED ]]; then
  echo "submit: the merge ended ${mstate:-gone} (log $TILES/slurm/merge.out); its output is not complete." \
    "Rerun it: $0 $TILES -o $OUT --section-tiles $K --merge-only" >&2
  exit 1
fi
if [[ -f $OUT/site.json ]]; then echo "done: $OUT/site.json"; else echo "done: $OUT/mission.json"; fi
