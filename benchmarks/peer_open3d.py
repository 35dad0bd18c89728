#!/usr/bin/python3
"""Peer benchmark: uavip's stages 3-5 against the same steps in Open3D, on the same cloud.

For each cloud, `uavip -v detect CLOUD -o TMP` runs --runs times, and Open3D does the same
steps --runs times with the same parameters (the values uavip resolved for that cloud, read
from its scene.json `parameters`; k, std ratio, iterations, stop rule from uavip's headers):
  stage 3    remove_statistical_outlier(k + 1, std_ratio), voxel_down_sample(voxel_m)
  stage 4    segment_plane(distance_threshold_m, 3, max_iterations) again and again on the
             points left, each candidate trimmed to its largest cluster (cluster_dbscan,
             plane_cluster_tolerance_m), kept when it has >= min_inliers points and
             min(convex hull area, occupied-cell area) >= min_area_m2 (uavip's rule)
  stage 5    cluster_dbscan(obstacle_tolerance_m, min_points=1) on the points in no plane
The runs of the two sides alternate (same machine load). It prints, per cloud, a table of
what each side found and its median time (loading excluded on both sides), the time ratio
uavip / Open3D, and a one-line verdict per cloud at the end.

uavip's time: the stage times uavip reports in scene.json `timings` when it writes them;
otherwise measured from outside on its own markers: from its -v progress line
"stage 3: ..." to the first file it creates in the output directory (cloud_clean.pcd's
temporary, written right after stage 5 returns), with "stages 4-5: ..." splitting stage 3
from stages 4-5. The process wall time (load, measuring, writing, views) is shown too.

  python3 benchmarks/peer_open3d.py [--uavip build/uavip] [--runs 5] [CLOUD ...]
(Debian's python3, /usr/bin/python3: a pyenv or venv python3 does not see python3-open3d.)
With no cloud: the bridge (scenarios/bridge.yaml) simulated with `uavip simulate` and
assembled with `uavip assemble` into ~/.cache/uavip-peer-open3d/bridge.pcd (once).
Open3D runs on as many OpenMP threads as the machine has cores (uavip uses them too: equal
cores) unless OMP_NUM_THREADS is set; OMP_NUM_THREADS=1 makes its seeded findings repeatable.
Needs Debian 12's python3-open3d (0.16) and python3-numpy; skips (exit 0) without Open3D.
"""
import argparse, ctypes, json, os, re, selectors, shutil, statistics, subprocess, sys, tempfile, time
from pathlib import Path

UAVIP_ENV = dict(os.environ)  # uavip runs with the caller's environment
# Equal cores: Open3D gets every core uavip may use. Its segment_plane draws its RANSAC
# samples in OpenMP threads, so only OMP_NUM_THREADS=1 makes the seeded result repeatable.
os.environ.setdefault("OMP_NUM_THREADS", str(os.cpu_count() or 1))
try:
    import numpy as np
    import open3d as o3d
except ImportError:
    print("peer_open3d: python3-open3d is not installed (apt-get install python3-open3d); skipped")
    if sys.executable != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        print(f"peer_open3d: (this is {sys.executable}; the Debian package is for /usr/bin/python3)")
    sys.exit(0)

REPO = Path(__file__).resolve().parent.parent
# uavip's fixed defaults (not in `parameters:`), re-read from its headers when present.
DEFAULTS = {"outlier_k": 16, "outlier_std_ratio": 2.0, "max_iterations": 200, "max_planes": 64,
            "max_failures": 8, "seed": 42, "min_points": 1}


def header_defaults():
    d = dict(DEFAULTS)
    for h in ("preprocess/filters.h", "perception/plane_detector.h", "perception/obstacle_clusterer.h"):
        path = REPO / "include/uavip" / h
        if path.exists():
            for name, value in re.findall(r"\b(\w+)\{([0-9.]+)\}", path.read_text()):
                if name in d:
                    d[name] = type(DEFAULTS[name])(float(value))
    return d


def bridge_cloud(uavip):
    cache = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "uavip-peer-open3d"
    cloud, scenario = cache / "bridge.pcd", REPO / "scenarios/bridge.yaml"
    if cloud.exists() and cloud.stat().st_mtime >= scenario.stat().st_mtime:
        print(f"bridge cloud: {cloud} (cached; delete it to regenerate)")
        return str(cloud)
    cache.mkdir(parents=True, exist_ok=True)
    for cmd in ([uavip, "-q", "simulate", str(scenario), "-o", str(cache / "scans")],
                [uavip, "-q", "assemble", str(cache / "scans"), "-o", str(cloud)]):
        print("generating the bridge cloud:", " ".join(cmd), flush=True)
        subprocess.run(cmd, check=True, env=UAVIP_ENV)
    return str(cloud)


def watch_creates(directory):
    """inotify fd reporting files created in `directory` (stdlib only: ctypes)."""
    libc = ctypes.CDLL(None, use_errno=True)
    fd = libc.inotify_init1(os.O_NONBLOCK | os.O_CLOEXEC)
    if fd < 0 or libc.inotify_add_watch(fd, os.fsencode(directory), 0x100) < 0:  # IN_CREATE
        raise OSError(ctypes.get_errno(), "inotify")
    return fd


def run_uavip(uavip, cloud, extra):
    """One `uavip -v detect`: its stage times, wall time, stdout and scene.json."""
    out = tempfile.mkdtemp(prefix="peer_uavip_")
    ino = watch_creates(out)
    t0 = time.perf_counter()
    p = subprocess.Popen([uavip, "-v", "detect", cloud, "-o", out] + extra, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, env=UAVIP_ENV)
    sel = selectors.DefaultSelector()
    sel.register(p.stdout, selectors.EVENT_READ, "out")
    sel.register(p.stderr, selectors.EVENT_READ, "err")
    sel.register(ino, selectors.EVENT_READ, "ino")
    text, marks, pending = {"out": b"", "err": b""}, {}, b""
    while len(sel.get_map()) > 1:  # until stdout and stderr are both closed
        for key, _ in sel.select():
            data = os.read(key.fd, 65536)
            now = time.perf_counter()
            if key.data == "ino":  # nothing is created in `out` before stage 5 has returned
                marks.setdefault("end", now)
                continue
            if not data:
                sel.unregister(key.fileobj)
                continue
            text[key.data] += data
            if key.data == "err":  # progress lines: time-stamp the stage markers
                pending += data
                while b"\n" in pending:
                    line, pending = pending.split(b"\n", 1)
                    if b"stage 3:" in line:
                        marks["stage3"] = now
                    elif b"stages 4-5:" in line:
                        marks["stages45"] = now
    rc, wall = p.wait(), time.perf_counter() - t0
    os.close(ino)
    stdout, stderr = text["out"].decode(), text["err"].decode()
    if rc != 0:
        sys.exit(f"peer_open3d: uavip detect failed ({rc}):\n{stdout}{stderr}")
    scene = json.loads((Path(out) / "scene.json").read_text())
    shutil.rmtree(out, ignore_errors=True)
    t = scene.get("timings", {})
    if "preprocess_s" in t and "perception_s" in t:
        s3, s45, how = t["preprocess_s"], t["perception_s"], "reported by uavip (scene.json timings)"
    elif {"stage3", "stages45", "end"} <= marks.keys():
        s3, s45 = marks["stages45"] - marks["stage3"], marks["end"] - marks["stages45"]
        how = "uavip's -v stage markers to its first output file (uavip reports no stage times)"
    else:
        sys.exit("peer_open3d: uavip detect reported no stage times and printed no -v stage markers")
    return {"stage3": s3, "stages45": s45, "total": s3 + s45, "wall": wall, "how": how,
            "stdout": stdout, "scene": scene}


def plane_areas(pts, cell):
    """(convex hull area, occupied-cell area) of points projected on their PCA plane, as uavip."""
    c = pts.mean(axis=0)
    d = pts - c
    _, vec = np.linalg.eigh(d.T @ d)
    uv = np.c_[d @ vec[:, 2], d @ vec[:, 1]]
    keys = np.floor(uv / cell).astype(np.int64)
    keys -= keys.min(axis=0)
    cells = np.unique(keys[:, 0] * (int(keys[:, 1].max()) + 1) + keys[:, 1]).size
    # 2D hull with Open3D's qhull: the hull of a unit prism over the points; its bottom
    # vertices are the 2D hull, in angular order about their mean.
    n = len(uv)
    prism = np.r_[np.c_[uv, np.zeros(n)], np.c_[uv, np.ones(n)]]
    try:
        _, idx = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(prism)).compute_convex_hull()
    except RuntimeError:
        return 0.0, cells * cell * cell  # collinear: no area
    h = uv[np.unique([i for i in idx if i < n])]
    h = h[np.argsort(np.arctan2(*(h - h.mean(axis=0)).T[::-1]))]
    hull = 0.5 * abs(np.dot(h[:, 0], np.roll(h[:, 1], -1)) - np.dot(h[:, 1], np.roll(h[:, 0], -1)))
    return hull, cells * cell * cell


def run_open3d(cloud, P):
    """Stages 3-5 in Open3D; returns times and what it found. `cloud` is not modified."""
    o3d.utility.random.seed(P["seed"])
    t0 = time.perf_counter()
    # Open3D counts the query point among its nb_neighbors (distance 0), PCL / uavip do
    # not: k + 1 gives the same mean distances times k / (k + 1), hence the same kept set.
    sor, _ = cloud.remove_statistical_outlier(nb_neighbors=P["outlier_k"] + 1, std_ratio=P["outlier_std_ratio"])
    n_sor, v = len(sor.points), P["voxel_m"]
    # uavip's voxels are floor(p / v) cells; Open3D's start at the cloud's minimum - v/2.
    # One extra point at floor(min / v) * v - v/2 moves Open3D's grid onto uavip's; its
    # own voxel is dropped again.
    lo = np.floor(sor.get_min_bound() / v) * v
    sor.points.append(lo - v / 2)
    vox = sor.voxel_down_sample(v)
    vox = vox.select_by_index(np.flatnonzero(~np.all(np.asarray(vox.points) < lo, axis=1)))
    t1 = time.perf_counter()
    pts = np.asarray(vox.points)
    pool, pool_idx, in_plane = vox, np.arange(len(pts)), np.zeros(len(pts), bool)
    planes, failures, candidates, trim_s = [], 0, 0, 0.0
    # uavip's loop: stop at max_planes accepted or max_failures rejected in a row. Not
    # mirrored (no Open3D call): uavip scores RANSAC on <= 60,000 random pool points (Open3D
    # scores on all) and narrows the 0.2 m band to 4 robust sigmas before trimming.
    while len(planes) < P["max_planes"] and failures < P["max_failures"] and len(pool_idx) >= 3:
        _, inl = pool.segment_plane(P["distance_threshold_m"], 3, P["max_iterations"])
        inl = np.asarray(inl)
        if len(inl) < 3:
            break
        candidates += 1
        tc = time.perf_counter()
        labels = np.asarray(pool.select_by_index(inl).cluster_dbscan(P["plane_cluster_tolerance_m"], 1))
        trim_s += time.perf_counter() - tc
        kept = inl[labels == np.bincount(labels).argmax()]
        area = plane_areas(pts[pool_idx[kept]], P["area_cell_m"]) if len(kept) >= P["min_inliers"] else (0, 0)
        if min(area) >= P["min_area_m2"]:
            planes.append(pool_idx[kept])
            in_plane[pool_idx[kept]] = True
            drop, failures = kept, 0
        else:
            drop, failures = inl, failures + 1  # rejected: the whole band leaves the pool
        pool = pool.select_by_index(drop, invert=True)
        pool_idx = np.delete(pool_idx, drop)
    t2 = time.perf_counter()
    rest = vox.select_by_index(np.flatnonzero(~in_plane))
    labels = np.asarray(rest.cluster_dbscan(P["obstacle_tolerance_m"], P["min_points"]))
    t3 = time.perf_counter()
    sizes = np.bincount(labels) if len(labels) else np.zeros(0, int)
    return {"stage3": t1 - t0, "stages45": t3 - t1, "planes_s": t2 - t1, "trim_s": trim_s, "total": t3 - t0,
            "after_sor": n_sor, "after_voxel": len(pts), "candidates": candidates,
            "planes": [pts[i] for i in planes], "clusters": sizes}


def found(planes, sizes, P):
    """The comparable findings, plane areas measured the same way (plane_areas) for both."""
    areas = [plane_areas(p, P["area_cell_m"]) for p in planes]
    hull = [a[0] for a in areas]
    return {"planes": len(planes), "planes_big": sum(min(a) >= P["min_area_m2"] for a in areas),
            "plane_points": sum(len(p) for p in planes), "area_sum": sum(hull),
            "area_max": max(hull, default=0.0), "clusters": len(sizes), "largest_cluster": max(sizes, default=0),
            "clusters10": sum(n >= 10 for n in sizes)}


def bench(cloud_path, args, P0):
    name = Path(cloud_path).name
    extra = ["--no-views"] if "--no-views" in subprocess.run([args.uavip, "detect", "--help"],
                                                           capture_output=True, text=True).stdout else []
    print(f"\n== {name}: {args.runs} x uavip detect and {args.runs} x Open3D, alternating ...", flush=True)
    u_runs = [run_uavip(args.uavip, cloud_path, extra)]  # the first run gives the parameters
    u = u_runs[0]
    counts = re.search(r"cloud: (\d+) points -> (\d+) after outlier removal -> (\d+) after voxel", u["stdout"])
    P = dict(P0, **{k.split(".", 1)[1]: v["value"] for k, v in u["scene"]["parameters"].items()})
    P["min_inliers"] = int(P["min_inliers"])
    t_load = time.perf_counter()
    pcd = o3d.io.read_point_cloud(cloud_path)
    t_load = time.perf_counter() - t_load
    if not pcd.has_points():
        print(f"peer_open3d: Open3D cannot read {cloud_path}; skipped")
        return None
    o_runs = []
    for i in range(args.runs):  # alternating, so that both sides see the same machine load
        o_runs.append(run_open3d(pcd, P))
        if i + 1 < args.runs:
            u_runs.append(run_uavip(args.uavip, cloud_path, extra))
    o = o_runs[-1]
    sc = u["scene"]
    uf = found([np.asarray(s["points"]) for s in sc["surfaces"]], [len(b["points"]) for b in sc["obstacles"]], P)
    of = found(o["planes"], o["clusters"].tolist(), P)
    med = lambda runs, key: statistics.median(r[key] for r in runs)
    ut, ot = med(u_runs, "total"), med(o_runs, "total")
    print(f"\n{name} (median of {args.runs} runs; uavip time: {u['how']})")
    print("parameters: " + " ".join(f"{k} {P[k]}" for k in (
        "outlier_k", "outlier_std_ratio", "voxel_m", "distance_threshold_m", "max_iterations",
        "plane_cluster_tolerance_m", "min_inliers", "min_area_m2", "area_cell_m", "obstacle_tolerance_m")))
    rows = [("points in", counts.group(1), len(pcd.points)),
            ("after outlier removal", counts.group(2), o["after_sor"]),
            ("after voxel grid", counts.group(3), o["after_voxel"]),
            ("plane candidates (RANSAC runs)", "-", o["candidates"]),
            ("planes found", uf["planes"], of["planes"]),
            (f"  with area >= {P['min_area_m2']} m2 (script's measure)", uf["planes_big"], of["planes_big"]),
            ("  points in planes", uf["plane_points"], of["plane_points"]),
            ("  hull area: sum / largest m2", f"{uf['area_sum']:.1f} / {uf['area_max']:.1f}",
             f"{of['area_sum']:.1f} / {of['area_max']:.1f}"),
            ("obstacle clusters (largest, points)", f"{uf['clusters']} ({uf['largest_cluster']})",
             f"{of['clusters']} ({of['largest_cluster']})"),
            ("  of them with >= 10 points", uf["clusters10"], of["clusters10"]),
            ("stage 3 s (outliers + voxel)", f"{med(u_runs, 'stage3'):.3f}", f"{med(o_runs, 'stage3'):.3f}"),
            ("stages 4-5 s (planes + clusters)", f"{med(u_runs, 'stages45'):.3f}", f"{med(o_runs, 'stages45'):.3f}"),
            ("  of which planes s (trimming: DBSCAN s)", "-",
             f"{med(o_runs, 'planes_s'):.3f} ({med(o_runs, 'trim_s'):.3f})"),
            ("stages 3-5 s", f"{ut:.3f}", f"{ot:.3f}"),
            ("wall s (uavip: process; Open3D: load + 3-5)", f"{med(u_runs, 'wall'):.3f}", f"{t_load + ot:.3f}")]
    w, c = max(len(r[0]) for r in rows), max(len(str(x)) for r in rows for x in r[1:])
    print(f"| {'':{w}} | {'uavip':>{c}} | {'Open3D':>{c}} |\n|{'-' * (w + 2)}|{'-' * (c + 1)}:|{'-' * (c + 1)}:|")
    for label, a, b in rows:
        print(f"| {label:{w}} | {a!s:>{c}} | {b!s:>{c}} |")
    print(f"stages 3-5 time ratio uavip / Open3D: {ut / ot:.2f}, Open3D / uavip: {ot / ut:.2f} -> "
          + (f"uavip {ot / ut:.2f}x faster" if ut < ot else f"Open3D {ut / ot:.2f}x faster"))
    faster = "uavip" if ut < ot else "Open3D"
    return (f"{name}: {faster} is {max(ut, ot) / min(ut, ot):.2f}x faster on stages 3-5 ({ut:.2f} s uavip vs "
            f"{ot:.2f} s Open3D); planes {uf['planes']} vs {of['planes']}, obstacle clusters "
            f"{uf['clusters']} vs {of['clusters']}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--uavip", default=str(REPO / "build/uavip"), help="uavip binary (default build/uavip)")
    ap.add_argument("--runs", type=int, default=5, help="runs per side; the median is reported (default 5)")
    ap.add_argument("clouds", nargs="*", help="cloud files (default: the bridge, generated once)")
    args = ap.parse_args()
    if args.runs < 1:
        ap.error("--runs must be >= 1")
    if not os.access(args.uavip, os.X_OK):
        ap.error(f"--uavip {args.uavip} is not an executable (build it first)")
    o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)
    P0, load0 = header_defaults(), os.getloadavg()[0]
    t0 = time.perf_counter()
    verdicts = [bench(c, args, P0) for c in (args.clouds or [bridge_cloud(args.uavip)])]
    print(f"\nOpen3D {o3d.__version__} on {os.environ['OMP_NUM_THREADS']} OpenMP thread(s), numpy {np.__version__}, "
          f"{os.cpu_count()} cores, load average "
          f"{load0:.2f} at the start, {os.getloadavg()[0]:.2f} at the end; total {time.perf_counter() - t0:.0f} s")
    for v in filter(None, verdicts):
        print("verdict:", v)


if __name__ == "__main__":
    main()
