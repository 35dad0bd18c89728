#!/usr/bin/env bash
# house_counts.sh UAVIP [TREE]: the counts issue 42 reports, for TREE (default: this
# tree), with the key list of UAVIP (`uavip config --keys`: the keys the tables declare).
# Sections: keys (config keys written in more than one place, a table counting as one).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
uavip=$1
tree=$(realpath "${2:-$here/..}")
keys=$(mktemp)
trap 'rm -f "$keys"' EXIT
"$uavip" config --keys > "$keys"
echo "keys: $(wc -l < "$keys") declared in the tables; written in more than one place in $tree: $(bash "$here/config_keys.sh" "$keys" "$tree" --count)"
