#!/usr/bin/env python3
"""Compares two output folders of `uavip run` (or two JSON files): mission.json and
scene.json with every timing field removed must be equal, value for value.

    scripts/compare_outputs.py BEFORE_DIR AFTER_DIR      (each holds mission.json, scene.json)
    scripts/compare_outputs.py before.json after.json

The timing fields are the `timings` objects (mission.json: top level, each surface,
the flight; scene.json: top level) and any key ending in `_seconds`; a flight's planned
durations (`duration_s`, `hover_s`, ...) are results and are compared. Exit 0 when equal, 1 with the first differences listed."""
import json
import os
import re
import sys

TIMING = re.compile(r"^timings?$|_seconds$")
FILES = ("mission.json", "scene.json")


def strip(node):
    if isinstance(node, dict):
        return {k: strip(v) for k, v in node.items()
                if not TIMING.search(k)}
    if isinstance(node, list):
        return [strip(v) for v in node]
    return node


def diff(a, b, path, out):
    if len(out) >= 20:
        return
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                out.append(f"{path}.{k}: only in {'after' if k in b else 'before'}")
            else:
                diff(a[k], b[k], f"{path}.{k}", out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: {len(a)} items before, {len(b)} after")
        for i, (x, y) in enumerate(zip(a, b)):
            diff(x, y, f"{path}[{i}]", out)
    elif a != b:
        out.append(f"{path}: {a!r} before, {b!r} after")


def compare(before, after):
    with open(before) as f:
        a = strip(json.load(f))
    with open(after) as f:
        b = strip(json.load(f))
    out = []
    diff(a, b, "", out)
    return out


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    before, after = sys.argv[1], sys.argv[2]
    pairs = [(before, after)]
    if os.path.isdir(before):
        pairs = [(os.path.join(before, n), os.path.join(after, n)) for n in FILES]
    failed = False
    for a, b in pairs:
        if not os.path.exists(a) or not os.path.exists(b):
            print(f"missing: {a if not os.path.exists(a) else b}")
            failed = True
            continue
        d = compare(a, b)
        print(f"{'same' if not d else 'DIFFERENT'}: {b}")
        for line in d:
            print("  " + line)
        failed = failed or bool(d)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
