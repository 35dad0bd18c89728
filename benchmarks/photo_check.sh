#!/usr/bin/env bash
# The photo check (benchmarks/photo_check.py, issue 46) with what it needs: the packages
# of benchmarks/packages.txt, installed with apt-get when missing (as root, or through
# sudo; SKIP_APT=1 skips this), then benchmarks/photo_check.py with the arguments given
# (see its --help), e.g.
#
#   bash benchmarks/photo_check.sh scenarios/wall_small.yaml
#   bash benchmarks/photo_check.sh scenarios/single_plane.yaml --overlap 0.6
#   bash benchmarks/photo_check.sh scenarios/tower.yaml --cover-structure
#   bash benchmarks/photo_check.sh --install-only     # the packages only (scripts/test.sh)
#
# It needs build/uavip and build/uavip_world_truth (bash scripts/setup.sh builds both).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${SKIP_APT:-0}" != 1 ]; then
  mapfile -t wanted < <(sed -e 's/#.*//' -e 's/[[:space:]]//g' -e '/^$/d' benchmarks/packages.txt)
  missing=()
  for p in "${wanted[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
  done
  if ((${#missing[@]})); then
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    echo "photo_check: installing ${missing[*]}" >&2
    $SUDO apt-get update -q
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
  fi
fi
[ "${1:-}" = --install-only ] && exit 0
exec /usr/bin/python3 benchmarks/photo_check.py "$@"
