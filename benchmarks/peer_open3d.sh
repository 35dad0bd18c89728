#!/usr/bin/env bash
# The Open3D peer benchmark with what it needs: Debian 12's python3-open3d (0.16) and
# python3-numpy, installed with apt-get when missing (as root, or through sudo), then
# benchmarks/peer_open3d.py with the arguments given (see its --help), e.g.
#
#   bash benchmarks/peer_open3d.sh --runs 5                # the bridge
#   bash benchmarks/peer_open3d.sh --runs 3 CLOUD.pcd ...
set -euo pipefail
cd "$(dirname "$0")/.."
missing=()
for p in python3-open3d python3-numpy; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if ((${#missing[@]})); then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  echo "peer_open3d: installing ${missing[*]}" >&2
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
exec /usr/bin/python3 benchmarks/peer_open3d.py "$@"
