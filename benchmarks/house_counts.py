#!/usr/bin/env python3
"""House counts of issue 42 (one home per fact), read from a checkout.

Usage: python3 benchmarks/house_counts.py [ROOT]   (default: the checkout holding this file)

Each count is defined here so that a before/after comparison uses the same rule:
- config keys written more than once: every YAML leaf key (a key with a value, not a section) used by scenarios/*.yaml and
  benchmarks/*.yaml, counted as a quoted string ("key") in src/, planners/ and
  benchmarks/*.cpp outside src/io and src/view (which write file formats whose field names
  may equal config keys); a key counts when it appears on more than one line;
- places comparing planner names: lines outside the planner table file that hold a quoted
  planner name (from the table) or an OMPL display name (AStarCoarse, ...);
- io/view/config headers including planning's algorithm headers (the planner, validator,
  flight or mission planner, path tools, tour) or planners/;
- lines in src/cli, and the ten largest source files.
"""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parents[1])


def sources(dirs, exts=(".cpp", ".h")):
    for d in dirs:
        for p in sorted((root / d).rglob("*")):
            if p.suffix in exts and p.is_file():
                yield p


def yaml_keys():
    keys = set()
    for p in list((root / "scenarios").glob("*.yaml")) + list((root / "benchmarks").glob("*.yaml")):
        for line in p.read_text().splitlines():
            m = re.match(r"^\s*(?:-\s+)?([a-z][a-z0-9_]*):\s*(\S?)", line)
            if m and m.group(2) not in ("", "#", "{"):  # a leaf key (a value on its line); sections are not keys
                keys.add(m.group(1))
            keys.update(re.findall(r"[{,]\s*([a-z][a-z0-9_]*):", line))
    return keys


def key_counts():
    keys = yaml_keys()
    files = [p for p in sources(["src", "planners", "benchmarks"])
             if not str(p.relative_to(root)).startswith(("src/io/", "src/view/"))]
    counts = {k: 0 for k in keys}
    for p in files:
        for line in p.read_text(errors="replace").splitlines():
            for k in re.findall(r'"([a-z][a-z0-9_]*)"', line):
                if k in counts:
                    counts[k] += 1
    return {k: c for k, c in counts.items() if c > 1}, len(keys)


def planner_name_places():
    table_files = [p for p in sources(["planners"]) if "planner_table" in p.name or "planner_rows" in p.name]
    names = set()
    for p in table_files:
        for m in re.finditer(r'\{\s*"([a-z-]+)",\s*"([A-Za-z]+)"', p.read_text()):
            names.update(m.groups())
    if not names:  # fallback: the names the base version knew
        names = {"astar", "astar-euclid", "astar-coarse", "AStar", "AStarEuclid", "AStarCoarse"}
    places = []
    pattern = re.compile(r'"(' + "|".join(re.escape(n) for n in sorted(names, key=len, reverse=True)) + r')"')
    for p in sources(["src", "planners", "include"]):
        if p in table_files:
            continue
        for i, line in enumerate(p.read_text(errors="replace").splitlines(), 1):
            if pattern.search(line) and not line.lstrip().startswith("//"):
                places.append(f"{p.relative_to(root)}:{i}")
    return places


ALGO = re.compile(r'#include\s+"(uavip/planning/(flight_planner|mission_planner|path_validator|path_simplifier|'
                  r'tour|planner)\.h|planners/[a-z_]+\.h)"')


def algo_includes():
    hits = []
    heads = list(sources(["include/uavip/io", "include/uavip/view"], (".h",)))
    heads += [root / "include/uavip/app/scenario.h", root / "include/uavip/app/config.h"]
    for p in heads:
        if not p.exists():
            continue
        for m in ALGO.finditer(p.read_text()):
            hits.append(f"{p.relative_to(root)} -> {m.group(1)}")
    return hits


dup, nkeys = key_counts()
print(f"config keys (from scenario files): {nkeys}; written as a string on more than one line: {len(dup)}")
for k, c in sorted(dup.items(), key=lambda kv: -kv[1])[:15]:
    print(f"  {k}: {c}")
places = planner_name_places()
print(f"lines comparing or spelling planner names outside the table: {len(places)}")
for p in places:
    print(f"  {p}")
hits = algo_includes()
print(f"io/view/config headers including planning's algorithm headers or planners/: {len(hits)}")
for h in hits:
    print(f"  {h}")
cli = list(sources(["src/cli"]))
print(f"lines in src/cli: {sum(len(p.read_text().splitlines()) for p in cli)} in {len(cli)} files")
sizes = sorted(((len(p.read_text(errors='replace').splitlines()), p) for p in sources(["src", "planners", "include"])),
               reverse=True)[:10]
print("largest files:")
for n, p in sizes:
    print(f"  {n:5d} {p.relative_to(root)}")
