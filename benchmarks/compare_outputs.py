#!/usr/bin/env python3
"""compare_outputs.py A_DIR B_DIR: mission.json and scene.json of two runs compared with
every "timings" object removed (wall times differ run to run); exit 1 on a difference."""
import json
import sys


def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if k != "timings"}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v


def main():
    a, b = sys.argv[1], sys.argv[2]
    same = True
    for name in ("mission.json", "scene.json"):
        with open(f"{a}/{name}") as fa, open(f"{b}/{name}") as fb:
            ja, jb = strip(json.load(fa)), strip(json.load(fb))
        ok = json.dumps(ja, sort_keys=True) == json.dumps(jb, sort_keys=True)
        print(f"{name}: {'same' if ok else 'DIFFERENT'}")
        same = same and ok
    sys.exit(0 if same else 1)


main()
