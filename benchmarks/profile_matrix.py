#!/usr/bin/env python3
"""profile_matrix.py DIR: the table of benchmarks/README.md ("Aircraft profiles x real
clouds") from DIR/CLOUD/PROFILE/{mission.json,scene.json} and the export logs
DIR/exp_CLOUD_DRONE.log (`uavip export ... --format dji-kmz --surface all`), as made by
tests/cli/profile_matrix_test.cpp: photos, flight, sorties, and what the gimbal left
uncovered (planes: the stops dropped for the gimbal and their surfaces' uncovered area;
structure: the points no view within the gimbal's range images)."""
import json
import os
import re
import sys

DRONES = ["m300", "m350", "m30", "m30t", "m3e", "m3t", "m4e", "m4t", "generic"]


def row(d, cloud, drone):
    plan = "m30" if drone == "m30t" else drone
    m = json.load(open(f"{d}/{cloud}/{plan}/mission.json"))
    s = json.load(open(f"{d}/{cloud}/{plan}/scene.json"))
    area = {x["id"]: x["area_m2"] for x in s["surfaces"]}
    f = m["flight"]
    photos = sum(x["stop_count"] for x in f["sorties"])
    log = f"{d}/exp_{cloud}_{drone}.log"
    exported = "—"
    if os.path.exists(log) and drone != "generic":
        exported = sum(int(n) for n in re.findall(r"(\d+) photo stops ->", open(log).read()))
    if "structure" in m:
        st = m["structure"]
        gimbal = (f"{100 * (1 - st['imageable_points'] / st['points']):.2f} % of points not "
                  f"imageable; coverage {100 * st['coverage_rule_b']:.1f} %")
    else:
        dropped, lost, total = 0, 0.0, 0.0
        for x in m["surfaces"]:
            a = area.get(x["surface_id"], 0.0)
            total += a
            n = sum(1 for st in x["stops"] if st.get("problem") == "gimbal_limit")
            if n:
                dropped += n
                lost += (1 - x["coverage"]["fraction"]) * a
        gimbal = f"{dropped} stops, {lost:.2f} m² of {total:.0f} m² ({100 * lost / total:.2f} %)"
    return (f"| {cloud} | {drone} | {photos} | {exported} | {f['length_m']:.1f} m | "
            f"{f['sortie_count']} | {gimbal} |")


def main():
    d = sys.argv[1]
    print("| cloud | profile | photos | exported to KMZ | flight | sorties | left uncovered by the gimbal |")
    print("|---|---|---|---|---|---|---|")
    for cloud in ("cube", "mbs", "autzen"):
        for drone in DRONES:
            print(row(d, cloud, drone))


main()
