#!/usr/bin/python3
"""A plan's photos checked by the tools that consume them (issue 46).

For each scenario: `uavip run` plans it, `uavip photos` renders every photo stop
(docs/formats.md, "The photo folder"), then

* COLMAP 3.8 on the CPU reconstructs the photos with the plan's known pinhole
  intrinsics: SIFT (<= 4096 features an image), matching of the image pairs the photo
  folder lists (pairs.txt, photo/view_pairs.h: each photo with the 10 whose planned
  views overlap its own most; or, as until stop 60, spatial matching of the 10 nearest
  planned camera centres, or sequential matching, 10 neighbours in flown order), the
  incremental mapper. SIFT runs from the image's own
  resolution (first_octave 0: the texture's finest feature is >= 3 px, no upsampling),
  one orientation a keypoint (COLMAP's default two would double the 4096). Reported: photos
  registered (in any model, each once), models, the largest model, mean reprojection error;
  camera centres against the plan after a similarity fit (Umeyama) per model; accuracy
  (90th percentile of the distance from the sparse points, after the same fit, to the world's rectangles) and
  completeness (share of the chosen surfaces' outer truth, sampled at 1 cm, within
  5 and 10 cm of a sparse point).
* a second pass with seeded pose noise on the priors (3 cm per axis, 0.5 deg), as GNSS
  and a gimbal give: the similarity fit is made to the noisy centres (georeferencing by
  GNSS), and --matcher spatial matches by them (the folder's pairs come from the plan,
  as they would for a flight of it); the errors are still measured against the true
  plan and the truth. COLMAP 3.8's mapper uses no pose prior, so the rotation noise
  only reaches the database.
* OpenCV's stitcher in SCANS mode per planar surface (poses.csv surface_id >= 0): the
  pipeline cv2.Stitcher_create(cv2.Stitcher_SCANS) configures (ORB at its registration
  resolution, affine best-of-2-nearest matching, the biggest component above its
  confidence threshold, affine estimator, affine-partial bundle adjustment), run through
  cv2.detail because the Python Stitcher neither takes a matching mask nor returns its
  cameras: only plan-adjacent photos (footprints overlapping in the plan) are matched,
  and each photo's placement is read from its camera. A panorama counts only when every
  photo's placement lies within 10 % of a footprint (per image axis) of the plan after
  a 2D similarity fit.

Writes OUT/<case>/result.json and appends one Markdown row to OUT/results.md.
The ground truth comes from build/uavip_world_truth (the scenario loader's rectangles).

Mesh mode (`--mesh MESH --mission MISSION`, a real structure, issue 46 item 5): the
photos of an existing plan are rendered against a mesh of the structure (`uavip photos
MISSION --world MESH`; benchmarks/mesh_cloud.cpp meshes a cloud) and the mesh is the
truth: accuracy is the exact distance to its triangles (Open3D's RaycastingScene);
completeness is over area-uniform samples of the mesh (seeded; 2 cm apart, coarser
when that would pass MESH_MAX_SAMPLES), both of the whole mesh and of the part the
plan images (a sample inside some photo's image, within 1.25 x the standoff and seen
unoccluded from its centre).
"""

import argparse
import csv
import json
import math
import os
import shutil
import sqlite3
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TRUTH_SPACING_M = 0.01
TAUS_M = (0.05, 0.10)
MAX_FEATURES = 4096
MATCH_NEIGHBOURS = 10
NOISE_POSITION_M = 0.03
NOISE_ROTATION_DEG = 0.5
PLACEMENT_TOLERANCE = 0.10  # share of a footprint
# A panorama counts when it holds this share of its photos, each placed within the tolerance
# (issue 46: "one panorama holding >= 95 % of its photos").
PANORAMA_SHARE = 0.95
# The truth: a rectangle counts in completeness when some photo aims at it within this
# angle of its normal; a sample within CONTACT_M of a coplanar rectangle lying against it
# is not outer surface.
CHOSEN_MAX_DEG = 50.0
CONTACT_M = 1e-3
MESH_SPACING_M = 0.02
MESH_MAX_SAMPLES = 3_000_000
MESH_RANGE_FACTOR = 1.25
MAX_COMPOSITE_MP = 25.0


class CheckError(Exception):
    """A failed step: the message names the step and its log."""


def log(msg):
    print(f"photo_check: {msg}", file=sys.stderr, flush=True)


def run(cmd, log_path, env=None):
    """Runs cmd with stdout and stderr appended to log_path; raises CheckError on failure."""
    with open(log_path, "a") as f:
        f.write("$ " + " ".join(cmd) + "\n")
        f.flush()
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT, env=env)
    if rc != 0:
        with open(log_path) as f:
            tail = "".join(f.readlines()[-15:])
        raise CheckError(f"{os.path.basename(cmd[0])} {cmd[1]} exited {rc} (log {log_path}):\n{tail}")


# ---------------------------------------------------------------------------------------
# Geometry


def quat_to_rot(qw, qx, qy, qz):
    """Rotation matrix of a unit quaternion (w, x, y, z)."""
    q = np.array([qw, qx, qy, qz], dtype=float)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def rot_to_quat(r):
    """Unit quaternion (w, x, y, z) of a rotation matrix, from its largest diagonal term
    (Shepperd): exact for half turns too, where w = 0 leaves no sign to copy."""
    t = np.trace(r)
    k = int(np.argmax([t, r[0, 0], r[1, 1], r[2, 2]]))
    if k == 0:
        s = 2 * math.sqrt(1 + t)
        q = [s / 4, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    elif k == 1:
        s = 2 * math.sqrt(1 + r[0, 0] - r[1, 1] - r[2, 2])
        q = [(r[2, 1] - r[1, 2]) / s, s / 4, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s]
    elif k == 2:
        s = 2 * math.sqrt(1 - r[0, 0] + r[1, 1] - r[2, 2])
        q = [(r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, s / 4, (r[1, 2] + r[2, 1]) / s]
    else:
        s = 2 * math.sqrt(1 - r[0, 0] - r[1, 1] + r[2, 2])
        q = [(r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, s / 4]
    q = np.array(q)
    return q if q[0] >= 0 else -q


def umeyama(src, dst):
    """Similarity (s, R, t) minimising sum |s R src_i + t - dst_i|^2 (Umeyama 1991), no reflection."""
    src = np.asarray(src, float)
    dst = np.asarray(dst, float)
    mu_s, mu_d = src.mean(0), dst.mean(0)
    xs, xd = src - mu_s, dst - mu_d
    cov = xd.T @ xs / len(src)
    u, d, vt = np.linalg.svd(cov)
    sign = np.eye(src.shape[1])
    if np.linalg.det(u) * np.linalg.det(vt) < 0:
        sign[-1, -1] = -1
    r = u @ sign @ vt
    var_s = (xs ** 2).sum() / len(src)
    s = np.trace(np.diag(d) @ sign) / var_s
    return s, r, mu_d - s * r @ mu_s


def fit_cameras(src, dst, src_dirs, dst_dirs):
    """The similarity (s, R, t) taking model camera centres src to planned centres dst.
    Centres on one plane (a wall's grid) fit two proper rotations equally well: R and its
    mirror H_dst R H_src (H: the reflection across each set's plane), which puts the model
    on the other side of the cameras; the one that turns the model's viewing directions
    src_dirs onto the planned dst_dirs is kept."""
    s, r, t = umeyama(src, dst)
    if spread_rank(src) >= 3 or spread_rank(dst) >= 3:
        return s, r, t

    def normal(p):
        return np.linalg.svd(p - p.mean(0))[2][2]

    ns, nd = normal(src), normal(dst)
    r2 = (np.eye(3) - 2 * np.outer(nd, nd)) @ r @ (np.eye(3) - 2 * np.outer(ns, ns))
    agree = np.sum((r @ src_dirs.T).T * dst_dirs)
    agree2 = np.sum((r2 @ src_dirs.T).T * dst_dirs)
    if agree2 > agree:
        r = r2
        t = dst.mean(0) - s * r @ src.mean(0)
    return s, r, t


def spread_rank(points, rel=0.02):
    """Number of axes along which points spread more than rel of their largest spread."""
    p = np.asarray(points, float)
    if len(p) < 2:
        return 0
    sv = np.linalg.svd(p - p.mean(0), compute_uv=False)
    return int((sv > rel * sv[0]).sum()) if sv[0] > 0 else 0


# ---------------------------------------------------------------------------------------
# The photo folder (docs/formats.md) and the truth


def read_photo_folder(folder):
    """photos.json's camera and poses.csv's rows (flown order)."""
    with open(os.path.join(folder, "photos.json")) as f:
        meta = json.load(f)
    rows = []
    with open(os.path.join(folder, "poses.csv")) as f:
        for r in csv.DictReader(f):
            rows.append({
                "order": int(r["order"]), "stop_id": r["stop_id"], "surface_id": int(r["surface_id"]),
                "sortie": int(r["sortie"]),
                "centre": np.array([float(r["x_m"]), float(r["y_m"]), float(r["z_m"])]),
                "q": np.array([float(r["qw"]), float(r["qx"]), float(r["qy"]), float(r["qz"])]),
                "target": np.array([float(r["target_x_m"]), float(r["target_y_m"]), float(r["target_z_m"])]),
                "footprint": (float(r["footprint_w_m"]), float(r["footprint_h_m"])),
            })
    rows.sort(key=lambda r: r["order"])
    for r in rows:
        r["image"] = r["stop_id"] + ".png"
    return meta, rows


class Truth:
    """The world's rectangles; the outer surface is what lies inside no box of the world."""

    def __init__(self, truth_json):
        self.rects = []
        for r in truth_json["rects"]:
            c, u, v = (np.array(r[k], float) for k in ("corner", "edge_u", "edge_v"))
            n = np.cross(u, v)
            self.rects.append({"name": r["name"], "c": c, "u": u, "v": v, "n": n / np.linalg.norm(n)})
        groups = {}
        for r in self.rects:
            head, _, tail = r["name"].rpartition("/")
            if tail in ("+x", "-x", "+y", "-y", "+z", "-z"):
                groups.setdefault(head, []).append(r)
        # A box: six outward faces (world_model.cpp addBox); its interior is behind all six.
        self.boxes = {k: g for k, g in groups.items() if len(g) == 6}

    def inner_mask(self, points, own_name):
        """True where a point lies strictly inside a box of the world other than its own, or
        on another rectangle lying against its own (coplanar: a pier's top under a deck's
        underside; neither side of that contact can be seen)."""
        inside_any = np.zeros(len(points), bool)
        own_box = own_name.rpartition("/")[0]
        for name, faces in self.boxes.items():
            if name == own_box:
                continue
            inside = np.ones(len(points), bool)
            for f in faces:
                inside &= (points - f["c"]) @ f["n"] < -1e-6
            inside_any |= inside
        own = next(r for r in self.rects if r["name"] == own_name)
        for r in self.rects:
            if r["name"] == own_name or abs(r["n"] @ own["n"]) < 0.999:
                continue
            d = points - r["c"]
            s = d @ r["u"] / (r["u"] @ r["u"])
            t = d @ r["v"] / (r["v"] @ r["v"])
            inside_any |= (np.abs(d @ r["n"]) < CONTACT_M) & (s >= 0) & (s <= 1) & (t >= 0) & (t <= 1)
        return inside_any

    def distance(self, points):
        """Euclidean distance [m] from each point to the nearest rectangle of the world."""
        best = np.full(len(points), np.inf)
        for r in self.rects:
            d = points - r["c"]
            uu, vv = r["u"] @ r["u"], r["v"] @ r["v"]
            s = np.clip(d @ r["u"] / uu, 0, 1)
            t = np.clip(d @ r["v"] / vv, 0, 1)
            foot = r["c"] + np.outer(s, r["u"]) + np.outer(t, r["v"])
            best = np.minimum(best, np.linalg.norm(points - foot, axis=1))
        return best

    def chosen(self, targets, centres, tol=0.05):
        """The rectangles some photo aims at: its target within tol of the rectangle, seen
        within CHOSEN_MAX_DEG of the rectangle's normal (a pier face's bottom row aims at
        the ground's line too, 60-90 deg off the ground's normal; an edge link at 45 deg
        chooses both faces)."""
        out = []
        view = centres - targets
        view /= np.linalg.norm(view, axis=1)[:, None]
        cos_max = math.cos(math.radians(CHOSEN_MAX_DEG))
        for r in self.rects:
            d = targets - r["c"]
            s = d @ r["u"] / (r["u"] @ r["u"])
            t = d @ r["v"] / (r["v"] @ r["v"])
            on = (np.abs(d @ r["n"]) < tol) & (s > -1e-3) & (s < 1 + 1e-3) & (t > -1e-3) & (t < 1 + 1e-3)
            if (on & (np.abs(view @ r["n"]) >= cos_max)).any():
                out.append(r)
        return out


class MeshTruth:
    """A triangle mesh as the truth (mesh mode): exact distances, area-uniform samples."""

    def __init__(self, path, seed=46):
        import open3d as o3d  # noqa: PLC0415

        mesh = o3d.io.read_triangle_mesh(path)
        self.v = np.asarray(mesh.vertices, float)
        self.f = np.asarray(mesh.triangles, np.int64)
        if len(self.f) == 0:
            raise CheckError(f"{path}: no triangle")
        self.scene = o3d.t.geometry.RaycastingScene()
        self.scene.add_triangles(o3d.core.Tensor(self.v.astype(np.float32)),
                                 o3d.core.Tensor(self.f.astype(np.uint32)))
        a, b, c = self.v[self.f[:, 0]], self.v[self.f[:, 1]], self.v[self.f[:, 2]]
        area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
        self.area_m2 = float(area.sum())
        self.spacing = max(MESH_SPACING_M, math.sqrt(self.area_m2 / MESH_MAX_SAMPLES))
        n = int(self.area_m2 / self.spacing ** 2)
        rng = np.random.default_rng(seed)
        tri = rng.choice(len(self.f), size=n, p=area / area.sum())
        r1, r2 = rng.random(n), rng.random(n)
        flip = r1 + r2 > 1
        r1[flip], r2[flip] = 1 - r1[flip], 1 - r2[flip]
        self.samples = a[tri] + r1[:, None] * (b - a)[tri] + r2[:, None] * (c - a)[tri]
        self.o3d = o3d

    def distance(self, points):
        """Exact distance [m] from each point to the mesh."""
        q = self.o3d.core.Tensor(np.asarray(points, np.float32))
        return self.scene.compute_distance(q).numpy().astype(float)

    def imaged(self, rows, camera):
        """Mask of the samples some photo images: inside its image, nearer than
        MESH_RANGE_FACTOR x the standoff, and the first surface on the ray from its centre."""
        k = camera
        seen = np.zeros(len(self.samples), bool)
        max_range = MESH_RANGE_FACTOR * k["standoff_m"]
        for r in rows:
            c = np.array(r["centre"])
            rot = quat_to_rot(*r["q"])  # camera to world
            d = self.samples - c
            near = np.einsum("ij,ij->i", d, d) < max_range ** 2
            idx = np.nonzero(near & ~seen)[0]
            if len(idx) == 0:
                continue
            cam = d[idx] @ rot
            z = cam[:, 2]
            ok = z > 1e-6
            u = k["fx_px"] * cam[:, 0] / np.where(ok, z, 1) + k["cx_px"]
            v = k["fy_px"] * cam[:, 1] / np.where(ok, z, 1) + k["cy_px"]
            ok &= (u >= 0) & (u < k["width_px"]) & (v >= 0) & (v < k["height_px"])
            idx = idx[ok]
            if len(idx) == 0:
                continue
            dist = np.linalg.norm(d[idx], axis=1)
            dirs = d[idx] / dist[:, None]
            rays = np.hstack([np.repeat(c[None, :], len(idx), 0), dirs]).astype(np.float32)
            t = self.scene.cast_rays(self.o3d.core.Tensor(rays))["t_hit"].numpy()
            seen[idx[t >= dist - max(0.01, 2 * self.spacing)]] = True
        return seen

    def completeness(self, points, mask=None, taus=TAUS_M):
        """Share of the samples (those in `mask`) within each tau of a point."""
        from scipy.spatial import cKDTree  # noqa: PLC0415

        samples = self.samples if mask is None else self.samples[mask]
        if len(samples) == 0 or len(points) == 0:
            return {tau: 0.0 for tau in taus}, len(samples)
        d, _ = cKDTree(points).query(samples, distance_upper_bound=max(taus))
        return {tau: float((d <= tau).mean()) for tau in taus}, len(samples)


def samples_along(length, spacing):
    """sim/surface_sampler.cpp's count: floor(length / spacing) + 1, at least 2."""
    return max(int(math.floor(length / spacing + 1e-9)) + 1, 2)


def completeness(truth, rects, points, taus=TAUS_M, spacing=TRUTH_SPACING_M, by_rect=None):
    """Share of the rectangles' outer truth (a grid of `spacing`, both edges included, as
    sim samples it) within each tau of a point. Returns ({tau: share}, outer samples);
    fills `by_rect` (a dict) with each rectangle's {samples, tau: share}, to show where a
    model leaves the truth out."""
    covered = {tau: 0 for tau in taus}
    total = 0
    for r in rects:
        own = {tau: 0 for tau in taus}
        lu, lv = np.linalg.norm(r["u"]), np.linalg.norm(r["v"])
        nu, nv = samples_along(lu, spacing), samples_along(lv, spacing)
        du, dv = lu / (nu - 1), lv / (nv - 1)
        eu, ev = r["u"] / lu, r["v"] / lv
        # outer samples, row by row (bounded memory)
        outer = np.ones((nu, nv), bool)
        sv = np.arange(nv) * dv
        for i in range(nu):
            grid = r["c"] + i * du * eu + np.outer(sv, ev)
            outer[i] = ~truth.inner_mask(grid, r["name"])
        total += int(outer.sum())
        if by_rect is not None:
            by_rect[r["name"]] = {"samples": int(outer.sum())}
        if len(points) == 0:
            continue
        d = points - r["c"]
        h = d @ r["n"]
        s, t = d @ eu, d @ ev
        tmax = max(taus)
        near = (np.abs(h) < tmax) & (s > -tmax) & (s < lu + tmax) & (t > -tmax) & (t < lv + tmax)
        h, s, t = h[near], s[near], t[near]
        for tau in taus:
            hit = np.zeros((nu, nv), bool)
            rad2 = tau * tau - h * h
            ok = rad2 > 0
            hs, ss, ts, r2 = h[ok], s[ok], t[ok], rad2[ok]
            i0, j0 = np.rint(ss / du).astype(int), np.rint(ts / dv).astype(int)
            reach_i, reach_j = int(math.ceil(tau / du)) + 1, int(math.ceil(tau / dv)) + 1
            for di in range(-reach_i, reach_i + 1):
                ii = i0 + di
                ok_i = (ii >= 0) & (ii < nu)
                ds2 = (ii * du - ss) ** 2
                for dj in range(-reach_j, reach_j + 1):
                    jj = j0 + dj
                    m = ok_i & (jj >= 0) & (jj < nv) & (ds2 + (jj * dv - ts) ** 2 <= r2)
                    hit[ii[m], jj[m]] = True
            own[tau] = int((hit & outer).sum())
            covered[tau] += own[tau]
        if by_rect is not None and outer.any():
            by_rect[r["name"]].update(
                {f"{int(round(tau * 100))}cm": own[tau] / int(outer.sum()) for tau in taus})
    return {tau: (covered[tau] / total if total else 0.0) for tau in taus}, total


# ---------------------------------------------------------------------------------------
# COLMAP


def colmap_env():
    env = dict(os.environ)
    env["QT_QPA_PLATFORM"] = "offscreen"
    return env


def extract_features(colmap, folder, meta, rows, work, threads, logf):
    cam = meta["camera"]
    params = ",".join(repr(float(cam[k])) for k in ("fx_px", "fy_px", "cx_px", "cy_px"))
    image_list = os.path.join(work, "images.txt")
    with open(image_list, "w") as f:
        f.writelines(r["image"] + "\n" for r in rows)
    db = os.path.join(work, "features.db")
    for stale in (db, db + "-journal", db + "-wal", db + "-shm"):  # a killed run's too
        if os.path.exists(stale):
            os.remove(stale)
    run([colmap, "feature_extractor", "--database_path", db,
         "--image_path", os.path.join(folder, "images"), "--image_list_path", image_list,
         "--ImageReader.single_camera", "1", "--ImageReader.camera_model", "PINHOLE",
         "--ImageReader.camera_params", params,
         "--SiftExtraction.use_gpu", "0", "--SiftExtraction.num_threads", str(threads),
         "--SiftExtraction.max_num_features", str(MAX_FEATURES),
         "--SiftExtraction.max_num_orientations", "1",
         "--SiftExtraction.first_octave", "0"], logf, colmap_env())
    return db


def features_per_image(db):
    """Mean SIFT keypoints an image in COLMAP's database."""
    con = sqlite3.connect(db)
    rows = con.execute("SELECT rows FROM keypoints").fetchall()
    con.close()
    return sum(r[0] for r in rows) / len(rows) if rows else 0.0


def write_priors(db, rows, centres, quats):
    """The planned (or noisy) poses as COLMAP's image priors (world-to-camera rotation,
    prior_t* = the camera centre, which the spatial matcher reads)."""
    con = sqlite3.connect(db)
    for r, c, q in zip(rows, centres, quats):
        w2c = rot_to_quat(quat_to_rot(*q).T)
        con.execute("UPDATE images SET prior_qw=?, prior_qx=?, prior_qy=?, prior_qz=?, "
                    "prior_tx=?, prior_ty=?, prior_tz=? WHERE name=?",
                    (*map(float, w2c), *map(float, c), r["image"]))
    con.commit()
    con.close()


def folder_pairs(folder, rows):
    """The photo folder's pairs.txt (photo/view_pairs.h: each photo with the 10 whose
    planned views overlap its own most), those of the photos checked."""
    path = os.path.join(folder, "pairs.txt")
    if not os.path.exists(path):
        raise CheckError(f"{path}: missing (a folder from an older uavip); render the photos "
                         "again with `uavip photos`, or pass --matcher spatial")
    names = {r["image"] for r in rows}
    with open(path) as f:
        pairs = [line.split() for line in f if line.strip()]
    return [p for p in pairs if len(p) == 2 and p[0] in names and p[1] in names]


def match_and_map(colmap, folder, db, work, matcher, threads, logf, rows=None):
    """Matching and the mapper on db; returns the models as text folders, largest first.
    matcher "view" matches the folder's pairs among `rows` (folder_pairs)."""
    env = colmap_env()
    common = ["--database_path", db, "--SiftMatching.use_gpu", "0",
              "--SiftMatching.num_threads", str(threads)]
    if matcher == "view":
        pair_list = os.path.join(work, "pairs.txt")
        with open(pair_list, "w") as f:
            f.writelines(f"{a} {b}\n" for a, b in folder_pairs(folder, rows))
        run([colmap, "matches_importer", *common, "--match_list_path", pair_list,
             "--match_type", "pairs"], logf, env)
    elif matcher == "spatial":
        # ignore_z 0: the photos of a wall differ in height, not only in x and y.
        run([colmap, "spatial_matcher", *common, "--SpatialMatching.is_gps", "0",
             "--SpatialMatching.ignore_z", "0",
             "--SpatialMatching.max_num_neighbors", str(MATCH_NEIGHBOURS),
             "--SpatialMatching.max_distance", "1000"], logf, env)
    else:
        run([colmap, "sequential_matcher", *common, "--SequentialMatching.overlap",
             str(MATCH_NEIGHBOURS), "--SequentialMatching.loop_detection", "0"], logf, env)
    sparse = os.path.join(work, "sparse")
    shutil.rmtree(sparse, ignore_errors=True)
    os.makedirs(sparse)
    try:
        run([colmap, "mapper", "--database_path", db, "--image_path", os.path.join(folder, "images"),
             "--output_path", sparse, "--Mapper.num_threads", str(threads),
             "--Mapper.ba_refine_focal_length", "0", "--Mapper.ba_refine_principal_point", "0",
             "--Mapper.ba_refine_extra_params", "0"], logf, env)
    except CheckError:
        if os.listdir(sparse):
            raise
        log("the mapper made no model")  # COLMAP 3.8 exits 1 when no model forms
        return []
    models = []
    for sub in sorted(os.listdir(sparse), key=lambda s: int(s) if s.isdigit() else -1):
        path = os.path.join(sparse, sub)
        if not os.path.isdir(path):
            continue
        txt = path + "_txt"
        os.makedirs(txt, exist_ok=True)
        run([colmap, "model_converter", "--input_path", path, "--output_path", txt,
             "--output_type", "TXT"], logf, env)
        models.append(read_model(txt))
    models.sort(key=lambda m: -len(m["images"]))
    return models


def read_model(txt):
    """images {name: camera centre}, dirs {name: viewing direction}, points (N x 3), reprojection error over observations."""
    images, dirs = {}, {}
    with open(os.path.join(txt, "images.txt")) as f:
        lines = [l for l in f if not l.startswith("#")]
    for line in lines[0::2]:
        p = line.split()
        if len(p) < 10:
            continue
        r = quat_to_rot(*map(float, p[1:5]))
        t = np.array(list(map(float, p[5:8])))
        images[p[9]] = -r.T @ t
        dirs[p[9]] = r[2]  # the viewing direction (camera +z) in the model's frame
    pts, err_sum, obs = [], 0.0, 0
    with open(os.path.join(txt, "points3D.txt")) as f:
        for line in f:
            if line.startswith("#"):
                continue
            p = line.split()
            track = (len(p) - 8) // 2
            pts.append(list(map(float, p[1:4])))
            err_sum += float(p[7]) * track
            obs += track
    return {"images": images, "dirs": dirs, "points": np.array(pts).reshape(-1, 3),
            "reprojection_px": err_sum / obs if obs else None}


def score_models(models, rows, fit_centres, truth, chosen):
    """Per model a similarity fit of its camera centres to fit_centres (the plan or the
    noisy priors); centre errors against the true plan; accuracy and completeness of the
    points of every model whose cameras span a plane (a row of cameras fixes no rotation)."""
    by_name = {r["image"]: i for i, r in enumerate(rows)}
    plan = np.array([r["centre"] for r in rows])
    view_dirs = np.array([quat_to_rot(*r["q"])[:, 2] for r in rows])
    errors, largest_errors, points, skipped = [], None, [], 0
    for k, m in enumerate(models):
        names = [n for n in m["images"] if n in by_name]
        if len(names) < 3 or spread_rank(plan[[by_name[n] for n in names]]) < 2:
            skipped += 1
            continue
        src = np.array([m["images"][n] for n in names])
        idx = [by_name[n] for n in names]
        s, r, t = fit_cameras(src, fit_centres[idx], np.array([m["dirs"][n] for n in names]),
                              view_dirs[idx])
        e = np.linalg.norm((s * (r @ src.T)).T + t - plan[idx], axis=1)
        errors.extend(e.tolist())
        if k == 0:
            largest_errors = e
        if len(m["points"]):
            points.append((s * (r @ m["points"].T)).T + t)
    pts = np.vstack(points) if points else np.zeros((0, 3))
    out = {"models_fitted": len(models) - skipped, "models_skipped_degenerate": skipped}
    if largest_errors is not None:
        out["centre_error_largest_m"] = {"median": float(np.median(largest_errors)),
                                         "max": float(np.max(largest_errors))}
    if errors:
        out["centre_error_all_m"] = {"median": float(np.median(errors)), "max": float(np.max(errors))}
    out["sparse_points"] = int(len(pts))
    if len(pts):
        out["accuracy_p90_m"] = float(np.percentile(truth.distance(pts), 90))
    if isinstance(truth, MeshTruth):
        comp, total = truth.completeness(pts, chosen)
        whole, _ = truth.completeness(pts)
        out["completeness_whole_mesh"] = {f"{int(round(tau * 100))}cm": v for tau, v in whole.items()}
    else:
        by_rect = {}
        comp, total = completeness(truth, chosen, pts, by_rect=by_rect)
        out["completeness_by_rectangle"] = by_rect
    out["completeness"] = {f"{int(round(tau * 100))}cm": v for tau, v in comp.items()}
    out["truth_samples"] = total
    return out


def colmap_pass(args, folder, meta, rows, db_features, work, priors, truth, chosen, logf):
    """One matching + mapping pass with the given prior centres and rotations."""
    os.makedirs(work, exist_ok=True)
    db = os.path.join(work, "database.db")
    shutil.copyfile(db_features, db)
    write_priors(db, rows, priors[0], priors[1])
    t0 = time.time()
    models = match_and_map(args.colmap, folder, db, work, args.matcher, args.threads, logf, rows)
    res = {
        # Photos in some model: COLMAP may register one photo in two models.
        "registered": len(set().union(*(m["images"].keys() for m in models))),
        "registrations": int(sum(len(m["images"]) for m in models)),
        "models": len(models),
        "largest": len(models[0]["images"]) if models else 0,
        "model_sizes": [len(m["images"]) for m in models],
        "reprojection_px": models[0]["reprojection_px"] if models else None,
        "match_map_s": round(time.time() - t0, 1),
    }
    res.update(score_models(models, rows, priors[0], truth, chosen))
    return res


def noisy_priors(rows, seed):
    """Seeded pose noise: N(0, 3 cm) per axis on the centre, a rotation of N(0, 0.5 deg)
    about a uniform random axis on the camera's attitude."""
    rng = np.random.default_rng(seed)
    centres, quats = [], []
    for r in rows:
        centres.append(r["centre"] + rng.normal(0, NOISE_POSITION_M, 3))
        axis = rng.normal(0, 1, 3)
        axis /= np.linalg.norm(axis)
        ang = math.radians(rng.normal(0, NOISE_ROTATION_DEG))
        kx = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        dr = np.eye(3) + math.sin(ang) * kx + (1 - math.cos(ang)) * kx @ kx
        quats.append(rot_to_quat(dr @ quat_to_rot(*r["q"])))
    return np.array(centres), quats


# ---------------------------------------------------------------------------------------
# OpenCV's stitcher (SCANS) per planar surface


def plan_axes(rows):
    """The image axes (x right, y down) of the surface's first photo, in the world."""
    r = quat_to_rot(*rows[0]["q"])
    return r[:, 0], r[:, 1]


def similarity_2d_residuals(src, dst):
    s, r, t = umeyama(src, dst)
    return (s * (r @ src.T)).T + t - dst


def stitch_surface(folder, rows, max_photos):
    """The SCANS pipeline on one surface's photos; placements checked against the plan."""
    import cv2  # noqa: PLC0415 (only the stitching part needs OpenCV)

    rows = rows[:max_photos] if max_photos else rows
    n = len(rows)
    st = cv2.Stitcher_create(cv2.Stitcher_SCANS)
    reg_mp, conf = st.registrationResol(), st.panoConfidenceThresh()
    ex, ey = plan_axes(rows)
    w_m, h_m = rows[0]["footprint"]
    plan_uv = np.array([[r["target"] @ ex, r["target"] @ ey] for r in rows])
    mask = np.zeros((n, n), np.uint8)
    for i in range(n):
        for j in range(n):
            if i != j and (abs(i - j) == 1 or (abs(plan_uv[i, 0] - plan_uv[j, 0]) < w_m and
                                               abs(plan_uv[i, 1] - plan_uv[j, 1]) < h_m)):
                mask[i, j] = 1
    finder = cv2.ORB.create()
    features, centres = [], []
    for i, r in enumerate(rows):
        img = cv2.imread(os.path.join(folder, "images", r["image"]), cv2.IMREAD_COLOR)
        if img is None:
            raise CheckError(f"cannot read {r['image']} in {folder}/images")
        scale = min(1.0, math.sqrt(reg_mp * 1e6 / (img.shape[0] * img.shape[1])))
        small = cv2.resize(img, None, fx=scale, fy=scale, interpolation=cv2.INTER_LINEAR_EXACT)
        f = cv2.detail.computeImageFeatures2(finder, small)
        f.img_idx = i
        features.append(f)
        centres.append((small.shape[1] / 2.0, small.shape[0] / 2.0))
    matcher = cv2.detail_AffineBestOf2NearestMatcher(False, False)
    pairs = matcher.apply2(features, mask)
    kept = cv2.detail.leaveBiggestComponent(features, pairs, conf)
    kept = [int(k) for k in np.array(kept).ravel()]
    out = {"photos": n, "in_panorama": 0, "counts": False}
    if len(kept) < 2:
        return out
    if len(kept) < n:  # Python's lists are not cut in place: match the component again
        features = [features[i] for i in kept]
        for k, f in enumerate(features):
            f.img_idx = k
        pairs = matcher.apply2(features, np.ascontiguousarray(mask[np.ix_(kept, kept)]))
    matcher.collectGarbage()
    ok, cameras = cv2.detail_AffineBasedEstimator().apply(features, pairs, None)
    if not ok:
        return out
    for c in cameras:
        c.R = c.R.astype(np.float32)
    adjuster = cv2.detail_BundleAdjusterAffinePartial()
    adjuster.setConfThresh(conf)
    ok, cameras = adjuster.apply(features, pairs, cameras)
    if not ok:
        return out
    # Where the composite puts each photo: the affine warper the SCANS stitcher composes
    # with (a photo of another range is misplaced by it: that is the stitcher's verdict).
    warper = cv2.PyRotationWarper("affine", 1.0)
    placed = np.array([warper.warpPoint(centres[kept[k]], cameras[k].K().astype(np.float32),
                                        cameras[k].R) for k in range(len(kept))], float)
    res = similarity_2d_residuals(placed, plan_uv[kept])
    worst = float(np.max(np.abs(res) / np.array([w_m, h_m])))
    out.update({"in_panorama": len(kept), "worst_placement_footprints": worst,
                "counts": len(kept) >= PANORAMA_SHARE * n and worst <= PLACEMENT_TOLERANCE,
                "kept": kept})
    return out


# Photos of one block at most: OpenCV's bundle adjusters hold a dense Jacobian (two rows
# per inlier match, four columns per photo in affine-partial), so one panorama of 510
# photos (single_plane's mosaic: ~2,000 plan-adjacent pairs of ~200 inliers) needs
# ~13 GB and had not finished after 20 min; 64 photos need ~0.2 GB.
STITCH_BLOCK = 64


def stitch_blocks(folder, rows, max_photos):
    """A surface of more than STITCH_BLOCK photos in blocks: the plan's (u, v) box cut into
    k x k cells of at most ~STITCH_BLOCK / 2 photos, each block a cell's photos and those
    within one footprint around it (so neighbouring blocks share a band of photos), each
    stitched and checked against the plan as one panorama. The surface counts when every
    block counts; `in_panorama` is the photos of counted blocks. Blocks that each fit the
    plan within 10 % of a footprint and overlap are one panorama in the plan's frame."""
    rows = rows[:max_photos] if max_photos else rows
    n = len(rows)
    if n <= STITCH_BLOCK:
        return stitch_surface(folder, rows, 0)
    ex, ey = plan_axes(rows)
    w_m, h_m = rows[0]["footprint"]
    uv = np.array([[r["target"] @ ex, r["target"] @ ey] for r in rows])
    lo, hi = uv.min(axis=0), uv.max(axis=0) + 1e-9
    k = 2
    while True:
        size = (hi - lo) / k
        cell = np.minimum(((uv - lo) / size).astype(int), k - 1)
        blocks = []
        for cx in range(k):
            for cy in range(k):
                a = lo + size * np.array([cx, cy]) - np.array([w_m, h_m])
                b = lo + size * np.array([cx + 1, cy + 1]) + np.array([w_m, h_m])
                core = np.all(cell == [cx, cy], axis=1)
                if not core.any():
                    continue
                inside = np.all((uv >= a) & (uv <= b), axis=1)
                blocks.append([i for i in range(n) if inside[i]])
        if max(len(b) for b in blocks) <= STITCH_BLOCK or k >= n:
            break
        k += 1
    placed = set()
    counted, worst = 0, 0.0
    for b in blocks:
        res = stitch_surface(folder, [rows[i] for i in b], 0)
        worst = max(worst, res.get("worst_placement_footprints", math.inf))
        if res["counts"]:
            counted += 1
            placed.update(b[k] for k in res["kept"])
    return {"photos": n, "in_panorama": len(placed), "blocks": len(blocks),
            "blocks_counted": counted, "worst_placement_footprints": worst,
            "counts": counted == len(blocks) and len(placed) >= PANORAMA_SHARE * n}


def stitch_all(folder, rows, max_photos):
    surfaces = sorted({r["surface_id"] for r in rows if r["surface_id"] >= 0})
    out = {}
    for sid in surfaces:
        srows = [r for r in rows if r["surface_id"] == sid]
        if len(srows) >= 2:
            res = stitch_blocks(folder, srows, max_photos)
            res.pop("kept", None)  # the block's own indices: not for result.json
            out[str(sid)] = res
    return out


# ---------------------------------------------------------------------------------------
# The case


def prepare_scenario(src, work, overlap, structure, purpose=None):
    """The scenario, with coverage.overlap replaced, coverage.purpose (without the
    scenario's own overlap unless --overlap gives one) and coverage.mode structure set
    when asked (`uavip run` has no --cover; a copy in work)."""
    if overlap is None and not structure and purpose is None:
        return os.path.abspath(src)
    import yaml  # noqa: PLC0415

    with open(src) as f:
        doc = yaml.safe_load(f)
    coverage = doc.setdefault("coverage", {})
    if overlap is not None:
        coverage["overlap"] = overlap
    if structure:
        coverage["mode"] = "structure"
    if purpose is not None:
        coverage["purpose"] = purpose
        if overlap is None:  # the purpose's own overlap, not the scenario's paper 0.2
            coverage.pop("overlap", None)
    if "edits" in doc:
        doc["edits"] = os.path.join(os.path.dirname(os.path.abspath(src)), doc["edits"])
    path = os.path.join(work, os.path.basename(src))
    with open(path, "w") as f:
        yaml.safe_dump(doc, f, sort_keys=False)
    return path


def plan_summary(mission_json):
    """Photos (the flown stops), stops planned, path, sorties and the multi-view counts of a
    plan (mission.json)."""
    with open(mission_json) as f:
        m = json.load(f)
    flight = m["flight"]
    views = [s["coverage"] for s in m["surfaces"] if s.get("coverage") and "views_min" in s["coverage"]]
    out = {"photos": sum(st.get("problem", "none") == "none"
                         for s in m["surfaces"] for st in s["stops"]),
           "stops_planned": sum(s["stop_count"] for s in m["surfaces"]),
           "path_m": flight["length_m"], "sorties": flight["sortie_count"]}
    if views:
        out["views_min"] = min(v["views_min"] for v in views)
        out["triangulation_deg_min"] = min(v["triangulation_deg_min"] for v in views)
        out["consecutive_share_min"] = min(v["consecutive_share_min"] for v in views)
        below = [v["views_below_min"] for v in views if "views_below_min" in v]
        if below:
            out["views_below_min"] = sum(below)
            out["points"] = sum(v["points"] for v in views)
    return out


def case_name(args):
    if args.mesh:
        return (os.path.splitext(os.path.basename(args.mesh))[0] + "-" +
                os.path.basename(os.path.dirname(os.path.abspath(args.mission))))
    base = os.path.splitext(os.path.basename(args.scenario))[0]
    if args.cover_structure:
        base += "-structure"
    if args.purpose:
        base += f"-{args.purpose}"
    base += f"-overlap{args.overlap}" if args.overlap is not None else "-asplanned"
    base += f"-scale{args.image_scale:g}" if args.image_scale != 1.0 else ""
    return base + (f"-first{args.max_photos}" if args.max_photos else "")


def run_case(args):
    name = args.name or case_name(args)
    work = os.path.abspath(os.path.join(args.out, name))
    os.makedirs(work, exist_ok=True)
    logf = os.path.join(work, "log.txt")
    open(logf, "w").close()
    t_start = time.time()
    timings = {}
    scenario_rel = os.path.relpath(os.path.abspath(args.scenario), ROOT) if args.scenario else None
    result = {"case": name, "scenario": scenario_rel,
              "overlap": args.overlap, "cover": "structure" if args.cover_structure else "surfaces",
              "purpose": args.purpose, "matcher": args.matcher, "threads": args.threads,
              "image_scale": args.image_scale, "surface": args.surface}
    folder = args.photos_dir
    if args.mesh:
        return run_mesh_case(args, name, work, logf, t_start, result)
    scenario = prepare_scenario(args.scenario, work, args.overlap, args.cover_structure,
                                args.purpose)
    if folder is None:
        t0 = time.time()
        run([args.uavip, "run", scenario, "-o", os.path.join(work, "plan"), "-q"] +
            (["--surface", args.surface] if args.surface else []), logf)
        timings["plan_s"] = round(time.time() - t0, 1)
        result["plan"] = plan_summary(os.path.join(work, "plan", "mission.json"))
        t0 = time.time()
        folder = os.path.join(work, "photos")
        run([args.uavip, "photos", os.path.join(work, "plan", "mission.json"), "--world", scenario,
             "-o", folder, "--threads", str(args.threads), "--image-scale",
             str(args.image_scale), "-q"], logf)
        timings["photos_s"] = round(time.time() - t0, 1)
    meta, rows = read_photo_folder(folder)
    result["photos_planned"] = len(rows)
    if args.max_photos:
        rows = rows[:args.max_photos]
    result["photos"] = len(rows)
    result["camera"] = meta["camera"]
    truth_json = json.loads(subprocess.check_output([args.truth_tool, scenario]))
    if truth_json["sensing_mode"] != "sample":
        raise CheckError(f"{scenario}: sensing mode {truth_json['sensing_mode']}: the truth is "
                         "in the scenario's frame only in mode sample")
    truth = Truth(truth_json)
    chosen = truth.chosen(np.array([r["target"] for r in rows]),
                          np.array([r["centre"] for r in rows]))
    result["chosen_rects"] = [r["name"] for r in chosen]
    return check_photos(args, name, work, logf, t_start, timings, result, folder, meta, rows,
                        truth, chosen)


def run_mesh_case(args, name, work, logf, t_start, result):
    """Mesh mode: the plan's photos rendered against the mesh, the mesh as the truth."""
    timings = {}
    result.update({"mesh": os.path.abspath(args.mesh), "mission": os.path.abspath(args.mission),
                   "scenario": None, "cover": "as planned"})
    result["plan"] = plan_summary(args.mission)
    folder = args.photos_dir
    if folder is None:
        t0 = time.time()
        folder = os.path.join(work, "photos")
        cmd = [args.uavip, "photos", args.mission, "--world", args.mesh, "-o", folder,
               "--threads", str(args.threads), "--image-scale", str(args.image_scale), "-q"]
        if args.scene:
            cmd += ["--scene", args.scene]
        run(cmd, logf)
        timings["photos_s"] = round(time.time() - t0, 1)
    meta, rows = read_photo_folder(folder)
    result["photos_planned"] = len(rows)
    if args.max_photos:
        rows = rows[:args.max_photos]
    result["photos"] = len(rows)
    result["camera"] = meta["camera"]
    t0 = time.time()
    truth = MeshTruth(args.mesh, args.seed)
    imaged = truth.imaged(rows, meta["camera"])
    timings["truth_s"] = round(time.time() - t0, 1)
    result["mesh_truth"] = {"area_m2": round(truth.area_m2, 1), "triangles": int(len(truth.f)),
                            "sample_spacing_m": round(truth.spacing, 4),
                            "samples": int(len(truth.samples)),
                            "imaged_share": float(imaged.mean())}
    return check_photos(args, name, work, logf, t_start, timings, result, folder, meta, rows,
                        truth, imaged)


def check_photos(args, name, work, logf, t_start, timings, result, folder, meta, rows, truth,
                 chosen):
    """COLMAP (plan priors, then noisy priors) and the stitcher on a photo folder."""
    if not args.no_colmap:
        t0 = time.time()
        db = extract_features(args.colmap, folder, meta, rows, work, args.threads, logf)
        timings["features_s"] = round(time.time() - t0, 1)
        result["sift_features_per_image"] = round(features_per_image(db))
        plan = (np.array([r["centre"] for r in rows]), [r["q"] for r in rows])
        log(f"{name}: COLMAP on {len(rows)} photos")
        result["colmap"] = colmap_pass(args, folder, meta, rows, db, os.path.join(work, "colmap"),
                                       plan, truth, chosen, logf)
        timings["colmap_s"] = round(time.time() - t0, 1)
        if not args.no_noise:
            t0 = time.time()
            log(f"{name}: COLMAP with noisy priors")
            result["colmap_noisy"] = colmap_pass(args, folder, meta, rows, db,
                                                 os.path.join(work, "colmap_noisy"),
                                                 noisy_priors(rows, args.seed), truth, chosen, logf)
            result["colmap_noisy"]["noise"] = {"position_sigma_m": NOISE_POSITION_M,
                                               "rotation_sigma_deg": NOISE_ROTATION_DEG,
                                               "seed": args.seed}
            timings["colmap_noisy_s"] = round(time.time() - t0, 1)
    if not args.no_stitch:
        t0 = time.time()
        log(f"{name}: stitching per surface")
        result["stitch"] = stitch_all(folder, rows, args.stitch_max_photos)
        timings["stitch_s"] = round(time.time() - t0, 1)
    timings["total_s"] = round(time.time() - t_start, 1)
    result["timings"] = timings
    with open(os.path.join(work, "result.json"), "w") as f:
        json.dump(result, f, indent=1)
    return result


# ---------------------------------------------------------------------------------------
# Report


def cm(v):
    return "–" if v is None else f"{100 * v:.1f}"


def markdown_row(res):
    c = res.get("colmap")
    cells = [f"`{res['case']}`", str(res["photos"])]
    if c:
        ce = c.get("centre_error_largest_m", {})
        comp = c.get("completeness", {})
        cells += [f"{c['registered']} ({100 * c['registered'] / res['photos']:.0f} %)", str(c["models"]),
                  str(c["largest"]),
                  "–" if c["reprojection_px"] is None else f"{c['reprojection_px']:.3f}",
                  f"{cm(ce.get('median'))} / {cm(ce.get('max'))}", cm(c.get("accuracy_p90_m")),
                  f"{100 * comp.get('5cm', 0):.0f} / {100 * comp.get('10cm', 0):.0f} %"]
        n = res.get("colmap_noisy")
        if n:
            ne = n.get("centre_error_largest_m", {})
            cells.append(f"{n['registered']}, {n['models']} models; {cm(ne.get('median'))} / "
                         f"{cm(ne.get('max'))}; {cm(n.get('accuracy_p90_m'))}")
        else:
            cells.append("–")
    else:
        cells += ["–"] * 8
    s = res.get("stitch")
    if s:
        cells.append(", ".join(
            f"{v['in_panorama']}/{v['photos']}{'' if v['counts'] else '✗'}"
            + (f" ({v['blocks_counted']}/{v['blocks']} blocks)" if "blocks" in v else "")
            for v in s.values()))
    else:
        cells.append("–")
    cells.append(f"{res['timings']['total_s']:.0f}")
    return "| " + " | ".join(cells) + " |"


HEADER = ("| case | photos | registered | models | largest | reproj. error [px] | "
          "centres vs plan, median / max [cm] | accuracy p90 [cm] | completeness 5 / 10 cm | "
          "noisy priors: registered, models; centres [cm]; accuracy [cm] | "
          "stitched per surface (in panorama / photos; ✗ not counted) | wall time [s] |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenario", nargs="?", help="scenario YAML (e.g. scenarios/wall_small.yaml)")
    ap.add_argument("--mesh", help="mesh mode: render --mission against this mesh, the truth")
    ap.add_argument("--mission", help="mesh mode: the mission.json whose photos are checked")
    ap.add_argument("--scene", help="mesh mode: the scene.json giving the mesh's frame "
                    "(default: beside the mission)")
    ap.add_argument("--overlap", type=float, help="replace coverage.overlap (a copy of the scenario)")
    ap.add_argument("--purpose", choices=("inspection", "mosaic", "reconstruction"),
                    help="set coverage.purpose (a copy of the scenario)")
    ap.add_argument("--cover-structure", action="store_true",
                    help="coverage.mode structure (as plan --cover structure)")
    ap.add_argument("--surface", help="the surfaces to plan, as uavip run --surface (default: all)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "photo_check"), help="output folder")
    ap.add_argument("--name", help="case name (default: from scenario and options)")
    ap.add_argument("--uavip", default=os.path.join(ROOT, "build", "uavip"))
    ap.add_argument("--truth-tool", default=os.path.join(ROOT, "build", "uavip_world_truth"))
    ap.add_argument("--colmap", default=shutil.which("colmap") or "colmap")
    ap.add_argument("--photos-dir", help="an existing photo folder (skips run and photos)")
    ap.add_argument("--max-photos", type=int, help="check only the first N photos in flown order")
    ap.add_argument("--image-scale", type=float, default=1.0,
                    help="render the planned views at this fraction of the image size "
                         "(uavip photos --image-scale; e.g. 0.25 for a 20 MP camera)")
    ap.add_argument("--stitch-max-photos", type=int, default=0,
                    help="stitch only the first N photos of each surface (0: all)")
    ap.add_argument("--matcher", choices=("view", "spatial", "sequential"), default="view",
                    help="image pairs: view (the photo folder's pairs.txt: the photos whose "
                    "planned views overlap most), spatial (nearest planned camera centres) or "
                    "sequential (flown order); 10 an image")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seed", type=int, default=46, help="seed of the pose noise")
    ap.add_argument("--no-colmap", action="store_true")
    ap.add_argument("--no-noise", action="store_true", help="skip the noisy-prior pass")
    ap.add_argument("--no-stitch", action="store_true")
    ap.add_argument("--require-registered", type=float,
                    help="exit 1 unless this share of the photos is in the largest model")
    ap.add_argument("--require-centre-max-m", type=float,
                    help="exit 1 unless every camera centre of the largest model is this close to the plan")
    args = ap.parse_args()
    if bool(args.mesh) != bool(args.mission) or bool(args.mesh) == bool(args.scenario):
        ap.error("give a scenario, or --mesh and --mission")
    try:
        res = run_case(args)
    except (CheckError, OSError, subprocess.CalledProcessError) as e:
        print(f"photo_check: error: {e}", file=sys.stderr)
        return 2
    row = markdown_row(res)
    md = os.path.join(args.out, "results.md")
    new = not os.path.exists(md)
    with open(md, "a") as f:
        f.write((HEADER + "\n" if new else "") + row + "\n")
    print(row)
    failed = []
    c = res.get("colmap", {})
    if args.require_registered is not None and c.get("largest", 0) < args.require_registered * res["photos"]:
        failed.append(f"largest model holds {c.get('largest', 0)} of {res['photos']} photos, "
                      f"fewer than {args.require_registered:.0%}")
    if args.require_centre_max_m is not None:
        e = c.get("centre_error_largest_m", {}).get("max")
        if e is None or e > args.require_centre_max_m:
            failed.append(f"camera centre error max {e} m above {args.require_centre_max_m} m")
    for f in failed:
        print(f"photo_check: FAILED: {f}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
