#!/usr/bin/env bash
# FC-Planner's three scenes, their photos checked by COLMAP (issue 46 item 5): the plans
# of uavip_fcplanner_compare (default and matched target), a mesh of each scene's dense
# cloud (uavip_mesh_cloud: PCL's greedy projection over the scan's own points), every
# photo stop rendered against that mesh with the world texture (`uavip photos --world
# MESH`), then benchmarks/photo_check.py in mesh mode: COLMAP 3.8 on the CPU with the
# planned priors; accuracy against the mesh's triangles, completeness of the imaged mesh.
# Usage: bash benchmarks/photo_check.sh --install-only   (colmap, python3-open3d, scipy)
#        bash benchmarks/fcplanner_photos.sh [OUT] [SCENES] [RUNS]
#   OUT default out/fcplanner_photos; SCENES a space-separated subset of "MBS christ pipe";
#   RUNS "matched" (default), "default" or "matched default". Appends to OUT/results.md.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/fcplanner_photos}
SCENES=${2:-"MBS christ pipe"}
RUNS=${3:-matched}
BUILD=${BUILD_DIR:-build}
DATA=${DATA_DIR:-../shared/data/real}
mkdir -p "$OUT"
if [ ! -f "$OUT/plans/results.json" ]; then
  "$BUILD/uavip_fcplanner_compare" "$DATA" -o "$OUT/plans" --runs 1
fi
declare -A dense=([MBS]=fcplanner_MBSmore.pcd [christ]=fcplanner_christmore.pcd [pipe]=fcplanner_pipe.pcd)
for scene in $SCENES; do
  mesh="$OUT/meshes/${scene}.ply"
  if [ ! -f "$mesh" ]; then
    mkdir -p "$OUT/meshes"
    "$BUILD/uavip_mesh_cloud" "$DATA/${dense[$scene]}" -o "$mesh"
  fi
  for run in $RUNS; do
    /usr/bin/python3 benchmarks/photo_check.py --mesh "$mesh" \
      --mission "$OUT/plans/${scene}_${run}/mission.json" --out "$OUT" --no-stitch \
      --uavip "$BUILD/uavip" --name "${scene}_${run}" || echo "photo_check: ${scene}_${run} failed" >&2
  done
done
