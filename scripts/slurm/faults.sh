#!/usr/bin/env bash
# CI step (called by scripts/slurm/ci.sh): faults on the real Slurm path, injected through
# the test hook UAVIP_TEST_FAULT (include/uavip/core/test_fault.h) so they hit reliably.
#
#   scripts/slurm/faults.sh TILES/ CLEAN_OUT/     (Slurm up; TILES/ fully run, CLEAN_OUT/ its
#                                                  merged site, with --section-tiles $K)
#
# Each case damages TILES/ the way the fault would, submits through submit.sh --wait,
# checks that the run failed, that nothing partial is taken as done, and that the
# failure names the index and the command to rerun it; then runs that command and
# checks that the merged site equals CLEAN_OUT (every file but the timings).
#  1. a tile task killed with SIGKILL in the middle of writing its results (its
#     temporaries left, then removed by the rerun);
#  2. a section task failing;
#  3. the merge killed in the middle of writing the site (temporaries as in 1);
#  4. results left from another manifest: a tile's (stale sha256 of its cloud) and a
#     section's (stale sha256 of the manifest);
#  5. a tile run twice at once (two tasks of one index).
set -euo pipefail
cd "$(dirname "$0")/../.."
T=$(cd "$1" && pwd)
CLEAN=$(cd "$2" && pwd)
K=${K:-1}
UAVIP=$(realpath "${UAVIP:-build/uavip}")
export UAVIP
M="$T/manifest.json"
say() { echo "slurm-faults: $*"; }
fail() { echo "slurm-faults: FAILED: $*" >&2; exit 1; }
strip() { sed -e '/"timings": {/,/}/d' -e '/"preprocess_s":/d' -e '/"perception_s":/d' "$1"; }
# same_site OUT: OUT equals CLEAN (site.json and each section's mission and scene).
same_site() {
  local f rel
  [[ -f $1/site.json || -f $1/mission.json ]] || fail "$1: no merged site"
  while read -r f; do
    rel=${f#"$CLEAN"/}
    diff -q <(strip "$f") <(strip "$1/$rel") >/dev/null || fail "$1/$rel differs from the clean run's"
  done < <(find "$CLEAN" -name site.json -o -name mission.json -o -name scene.json)
}
# expect_failure LOG WORD...: the submission failed and its message holds every WORD.
expect_failure() {
  local log=$1 w
  shift
  for w in "$@"; do grep -qF -- "$w" "$log" || { cat "$log" >&2; fail "the message lacks '$w'"; }; done
}
submit() { bash scripts/slurm/submit.sh "$T" --section-tiles "$K" --wait "$@"; }
# The command submit.sh printed to rerun what failed.
rerun_of() { grep -o 'scripts/slurm/submit.sh .*' "$1" | tail -n 1 | sed -e 's/^/bash /' -e 's/$/ --wait/'; }
LOGS=$(mktemp -d /tmp/uavip-faults.XXXXXX)
trap 'rm -rf "$LOGS"' EXIT
section_of_tile() {  # the section whose tiles hold tile $1
  "$UAVIP" plan-section "$M" --list --section-tiles "$K" |
    awk -v t="$1" '/^section / {sub(":", "", $2); sub(";", "", $4); n = split($4, a, ","); for (i = 1; i <= n; i++) if (a[i] == t) print $2}'
}
S2=$(section_of_tile 2)
ONLY=${FAULTS_ONLY:-12345}  # the cases to run (all by default)

if [[ $ONLY == *1* ]]; then
# 1. tile 2 killed (SIGKILL) after renaming half of its results.
t0=$(date +%s)
rm -rf "$T/tile_0002" "$T/f1"
if UAVIP_TEST_FAULT="run-tile 2:kill-mid-write" submit -o "$T/f1" --array 2 >"$LOGS/1" 2>&1; then fail "1: the killed tile passed"; fi
[[ ! -f $T/tile_0002/scene.json ]] || fail "1: tile 2 has a scene.json after the kill"
ls "$T/tile_0002"/* >/dev/null 2>&1 || fail "1: the kill came before any write (no partial output to test)"
[[ ! -e $T/f1 ]] || fail "1: a merged site after the kill"
expect_failure "$LOGS/1" "tile(s) 2 failed" "--array 2"
ls -A "$T/tile_0002" | grep -q '\.tmp' || fail "1: the kill left no temporary (nothing to clean up)"
if "$UAVIP" -q merge "$M" -o "$T/f1" --section-tiles "$K" --require-sections 2>"$LOGS/1m"; then fail "1: merge took the partial tile"; fi
expect_failure "$LOGS/1m" "section(s) $S2" "plan-section"
eval "$(rerun_of "$LOGS/1")" >"$LOGS/1r" 2>&1 || { cat "$LOGS/1r" >&2; fail "1: the rerun failed"; }
! ls -A "$T/tile_0002" | grep '\.tmp' || fail "1: the killed task's temporaries are left after the rerun"
same_site "$T/f1"
say "1 tile killed mid-write: $(grep -o 'tile(s) 2 failed[^;]*' "$LOGS/1" | head -n 1); rerun equal ($(($(date +%s) - t0)) s)"

fi
if [[ $ONLY == *2* ]]; then
# 2. section 1 fails (after staging, before its commit).
t0=$(date +%s)
rm -rf "$T/section_001"
if UAVIP_TEST_FAULT="plan-section 1:fail" submit -o "$T/f2" --sections 1 >"$LOGS/2" 2>&1; then fail "2: the failing section passed"; fi
[[ ! -f $T/section_001/section.json ]] || fail "2: section 1 has a result"
[[ ! -e $T/f2 ]] || fail "2: a merged site after the failed section"
expect_failure "$LOGS/2" "section(s) 1 failed" "--sections 1"
eval "$(rerun_of "$LOGS/2")" >"$LOGS/2r" 2>&1 || { cat "$LOGS/2r" >&2; fail "2: the rerun failed"; }
same_site "$T/f2"
say "2 section failing: $(grep -o 'section(s) 1 failed[^;]*' "$LOGS/2" | head -n 1); rerun equal ($(($(date +%s) - t0)) s)"

fi
if [[ $ONLY == *3* ]]; then
# 3. the merge killed after renaming half of the site's files.
t0=$(date +%s)
if UAVIP_TEST_FAULT="merge:kill-mid-write" submit -o "$T/f3" --merge-only >"$LOGS/3" 2>&1; then fail "3: the killed merge passed"; fi
[[ -d $T/f3 ]] && ls -A "$T/f3" | grep -q . || fail "3: the kill came before any write"
[[ ! -f $T/f3/site.json && ! -f $T/f3/mission.json ]] || fail "3: the killed merge left its mark of a complete site"
expect_failure "$LOGS/3" "the merge ended" "--merge-only"
ls -A "$T/f3" | grep -q '\.tmp' || fail "3: the kill left no temporary (nothing to clean up)"
eval "$(rerun_of "$LOGS/3")" >"$LOGS/3r" 2>&1 || { cat "$LOGS/3r" >&2; fail "3: the rerun failed"; }
! find "$T/f3" -name '*.tmp*' | grep . || fail "3: the killed merge's temporaries are left after the rerun"
same_site "$T/f3"
say "3 merge killed mid-write: $(grep -o 'the merge ended [A-Z_]*' "$LOGS/3"); rerun equal ($(($(date +%s) - t0)) s)"

fi
if [[ $ONLY == *4* ]]; then
# 4a. tile 2's result from another tiling of the same cloud (its sha256 is another's).
t0=$(date +%s)
input=$(awk '/"input": \{/ {f = 1} f && /"path":/ {sub(/^ *"path": "/, ""); sub(/",?$/, ""); print; exit}' "$M")
"$UAVIP" -q tile "$input" --tile-size 100 -o "$LOGS/other"
"$UAVIP" -q run-tile "$LOGS/other/manifest.json" --index 2
rm -rf "$T/tile_0002"
cp -r "$LOGS/other/tile_0002" "$T/tile_0002"
if submit -o "$T/f4" --sections "$S2" >"$LOGS/4" 2>&1; then fail "4a: a stale tile result was taken"; fi
[[ ! -e $T/f4 ]] || fail "4a: a merged site from a stale tile"
expect_failure "$LOGS/4" "section(s) $S2 failed" "result of another tiling for tile 2" "--array=2"
bash scripts/slurm/submit.sh "$T" --section-tiles "$K" --wait -o "$T/f4" --array 2 >"$LOGS/4r" 2>&1 ||
  { cat "$LOGS/4r" >&2; fail "4a: the rerun failed"; }
same_site "$T/f4"
# 4b. section 0's result made from another manifest.
sed -i 's/"manifest_sha256": "[0-9a-f]*"/"manifest_sha256": "0000"/' "$T/section_000/section.json"
rm -rf "$T/f4"
if submit -o "$T/f4" --merge-only >"$LOGS/4b" 2>&1; then fail "4b: a stale section result was taken"; fi
[[ ! -e $T/f4/site.json && ! -e $T/f4/mission.json ]] || fail "4b: a merged site from a stale section"
expect_failure "$LOGS/4b" "section(s) 0" "another manifest.json" "--sections 0"
submit -o "$T/f4" --sections 0 >"$LOGS/4br" 2>&1 || { cat "$LOGS/4br" >&2; fail "4b: the rerun failed"; }
same_site "$T/f4"
say "4 stale results: tile 2 ($(grep -o 'the result of another tiling for tile 2' "$LOGS/4" | head -n 1)), section 0 ($(grep -o 'made from another manifest.json ([^)]*)' "$LOGS/4b" | head -n 1)); reruns equal ($(($(date +%s) - t0)) s)"

fi
if [[ $ONLY == *5* ]]; then
# 5. tile 2 run twice at once (two jobs of one index), then the sections and the merge.
t0=$(date +%s)
a=$(sbatch --parsable --output="$LOGS/5a.out" --wrap="exec '$UAVIP' -q run-tile '$M' --index 2")
b=$(sbatch --parsable --output="$LOGS/5b.out" --wrap="exec '$UAVIP' -q run-tile '$M' --index 2")
while squeue -h -j "$a,$b" -o %i 2>/dev/null | grep -q .; do sleep 1; done
! ls "$T/tile_0002" | grep -q '\.tmp' || fail "5: temporaries left beside tile 2's results"
submit -o "$T/f5" --sections "0-$(("$("$UAVIP" plan-section "$M" --list --section-tiles "$K" | awk '/^sections:/ {print $2}')" - 1))" \
  >"$LOGS/5" 2>&1 || { cat "$LOGS/5" >&2; fail "5: the sections or merge after the double run failed"; }
same_site "$T/f5"
say "5 tile run twice at once (jobs $a, $b): merged site equal ($(($(date +%s) - t0)) s)"
fi
