#!/usr/bin/python3
"""Test PhotoCheckViewPairs: benchmarks/photo_check.py's view_pairs (the image pairs COLMAP
matches) against a brute-force overlap on a known scene.

The scene is a structure's vertical edge: face A (x = 0, seen from -x) and face B (y = 3,
seen from +y) meet at x = 0, y = 3; a column of photos looks at the edge along the bisector,
as uavip's edge link does, beside each face's rows. The reference: rays through a grid of
pixels of photo i hit the two faces (exact ray-rectangle intersection), and the share of
those hits that photo j sees (in its image, in front of the face) is their overlap.

Asserted: every chosen pair overlaps by brute force; every photo is paired with the photo
that overlaps it most; every edge photo is paired with photos of both faces. The last is
what COLMAP needs to join the edge column to the faces, and the camera centres' 10
nearest (COLMAP's spatial matcher, until stop 60) miss it on this scene: checked here
too, so the scene stays one where the choice matters. Exit 77 without numpy.
"""

import os
import sys

try:
    import numpy as np
except ImportError:
    print("PhotoCheckViewPairs skipped: python3-numpy is not installed")
    sys.exit(77)

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "benchmarks"))
import photo_check  # noqa: E402

STANDOFF = 1.5
CAMERA = {"width_px": 600, "height_px": 400, "fx_px": 1500.0, "fy_px": 1500.0,
          "cx_px": 300.0, "cy_px": 200.0}  # a 0.6 x 0.4 m footprint at 1.5 m
# The faces: (corner, edge u, edge v, outward normal).
FACES = [(np.array([0.0, 0.0, 0.0]), np.array([0.0, 3.0, 0.0]), np.array([0.0, 0.0, 2.0]),
          np.array([-1.0, 0.0, 0.0])),
         (np.array([0.0, 3.0, 0.0]), np.array([3.0, 0.0, 0.0]), np.array([0.0, 0.0, 2.0]),
          np.array([0.0, 1.0, 0.0]))]


def photo(centre, target, face):
    """A row of poses.csv: camera x right, y down, z along the view (OpenCV)."""
    fwd = target - centre
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    down = np.cross(fwd, right)
    rot = np.column_stack([right, down, fwd])
    return {"centre": centre, "target": target, "q": photo_check.rot_to_quat(rot), "face": face}


def scene():
    rows = []
    for z in (0.4, 0.75, 1.1, 1.45):
        for s in np.arange(0.1, 2.95, 0.19):
            rows.append(photo(np.array([-STANDOFF, s, z]), np.array([0.0, s, z]), "A"))
            rows.append(photo(np.array([s, 3.0 + STANDOFF, z]), np.array([s, 3.0, z]), "B"))
    h = STANDOFF / np.sqrt(2.0)
    for z in np.arange(0.3, 1.75, 0.155):
        rows.append(photo(np.array([-h, 3.0 + h, z]), np.array([0.0, 3.0, z]), "edge"))
    return rows


def hits(r, n=24):
    """The face points the rays through an n x (2n/3) pixel grid of photo r hit first."""
    rot = photo_check.quat_to_rot(*r["q"])
    out = []
    for u in np.linspace(0.5, CAMERA["width_px"] - 0.5, n):
        for v in np.linspace(0.5, CAMERA["height_px"] - 0.5, 2 * n // 3):
            d = rot @ np.array([(u - CAMERA["cx_px"]) / CAMERA["fx_px"],
                                (v - CAMERA["cy_px"]) / CAMERA["fy_px"], 1.0])
            best = None
            for c, eu, ev, nrm in FACES:
                den = d @ nrm
                if den >= 0:
                    continue
                t = ((c - r["centre"]) @ nrm) / den
                p = r["centre"] + t * d
                a, b = (p - c) @ eu / (eu @ eu), (p - c) @ ev / (ev @ ev)
                if 0 <= a <= 1 and 0 <= b <= 1 and (best is None or t < best[0]):
                    best = (t, p, nrm)
            if best is not None:
                out.append(best[1:])
    return out


def seen_share(r, pts, nrms):
    """Share of the face points pts (normals nrms) that photo r sees: in front of their
    face, ahead of the camera and inside its image."""
    if len(pts) == 0:
        return 0.0
    d = pts - r["centre"]
    cam = d @ photo_check.quat_to_rot(*r["q"])
    z = np.where(cam[:, 2] > 0, cam[:, 2], 1.0)
    u = CAMERA["fx_px"] * cam[:, 0] / z + CAMERA["cx_px"]
    v = CAMERA["fy_px"] * cam[:, 1] / z + CAMERA["cy_px"]
    ok = ((np.einsum("ij,ij->i", -d, nrms) > 0) & (cam[:, 2] > 0) & (u >= 0) &
          (u < CAMERA["width_px"]) & (v >= 0) & (v < CAMERA["height_px"]))
    return float(ok.mean())


def main():
    rows = scene()
    n = len(rows)
    overlap = np.zeros((n, n))  # overlap[i, j]: share of photo i's face points j sees
    for i in range(n):
        h = hits(rows[i])
        pts = np.array([p for p, _ in h]).reshape(-1, 3)
        nrms = np.array([m for _, m in h]).reshape(-1, 3)
        for j in range(n):
            if i != j:
                overlap[i, j] = seen_share(rows[j], pts, nrms)
    pairs = photo_check.view_pairs(rows, CAMERA)
    failures = []
    partners = {i: set() for i in range(n)}
    for i, j in pairs:
        partners[i].add(j)
        partners[j].add(i)
        if not (overlap[i, j] > 0 and overlap[j, i] > 0):
            failures.append(f"pair {i}-{j} does not overlap (brute force {overlap[i, j]:.2f})")
    for i in range(n):
        best = int(np.argmax(overlap[i]))
        if best not in partners[i]:
            failures.append(f"photo {i} ({rows[i]['face']}) is not paired with {best}, which "
                            f"overlaps it most ({overlap[i, best]:.2f})")
    centres = np.array([r["centre"] for r in rows])
    spatial_misses = 0
    for i, r in enumerate(rows):
        if r["face"] != "edge":
            continue
        faces = {rows[j]["face"] for j in partners[i]}
        if not {"A", "B"} <= faces:
            failures.append(f"edge photo {i} is paired with faces {sorted(faces)} only")
        near = np.argsort(np.linalg.norm(centres - r["centre"], axis=1))[1:11]
        spatial_misses += not {"A", "B"} <= {rows[j]["face"] for j in near}
    if spatial_misses == 0:
        failures.append("the scene no longer tells the rules apart: the 10 nearest camera "
                        "centres pair every edge photo with both faces")
    print(f"{n} photos, {len(pairs)} pairs; the 10 nearest centres leave {spatial_misses} "
          "edge photos without a photo of each face")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
