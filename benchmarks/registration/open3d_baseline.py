#!/usr/bin/python3
"""Open3D baseline on a laserfit dataset: FPFH + RANSAC (feature matching) + point-to-plane ICP.

usage: open3d_baseline.py DATASET OUT.jsonl [--trials N]
DATASET is what `laserfit bench generate` wrote (scans/, gt/, refs/, manifest.json). For every
trial (the first N of each scene with --trials) and target, the target's own scan points (the
simulator's labels: an oracle segmentation that favours Open3D) are registered against the same
reference cloud laserfit uses. Same voxel rule as laserfit (the benchmark's voxel, else reference
diagonal / 150), FPFH radius 5 voxels on a 2x grid, RANSAC seeded, then point-to-plane ICP at 2
voxels. Open3D has no trust decision: every result is `ok`. Errors modulo the symmetry, as in
laserfit. The records have laserfit's fields, so `laserfit report` puts both side by side.
Needs Debian's python3-open3d and python3-numpy (make deps-bench).
"""
import glob
import json
import math
import os
import sys
import time

import numpy as np
import open3d as o3d


def read_labelled_pcd(path):
    """laserfit's binary PCD (FIELDS x y z label): points and labels as numpy arrays."""
    with open(path, "rb") as f:
        header = {}
        while True:
            line = f.readline().decode("ascii").strip()
            if line.startswith("#"):
                continue
            key, _, value = line.partition(" ")
            header[key] = value
            if key == "DATA":
                break
        if header["DATA"] != "binary" or header["FIELDS"] != "x y z label":
            raise SystemExit(f"{path}: expected a laserfit binary PCD with x y z label")
        n = int(header["POINTS"])
        rec = np.frombuffer(f.read(16 * n), dtype=[("xyz", "<f4", 3), ("label", "<i4")], count=n)
    return rec["xyz"].astype(np.float64), rec["label"]


def sym_rotations(text):
    parts = text.split()
    if parts[0] == "none":
        return [np.eye(3)], None
    axis = {"x": np.array([1.0, 0, 0]), "y": np.array([0, 1.0, 0]), "z": np.array([0, 0, 1.0])}[parts[-1]]
    if parts[0] == "continuous":
        return [np.eye(3)], axis
    n = int(parts[1])
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return [np.eye(3) + math.sin(2 * math.pi * k / n) * K + (1 - math.cos(2 * math.pi * k / n)) * K @ K
            for k in range(n)], None


def errors(T, G, sym):
    rots, cont = sym_rotations(sym)
    t = np.linalg.norm(T[:3, 3] - G[:3, 3]) * 1e3
    if cont is not None:
        a, b = T[:3, :3] @ cont, G[:3, :3] @ cont
        return t, math.degrees(math.atan2(np.linalg.norm(np.cross(a, b)), a @ b))
    c = [(np.trace(T[:3, :3].T @ G[:3, :3] @ S) - 1) / 2 for S in rots]
    return t, min(math.degrees(math.acos(max(-1.0, min(1.0, x)))) for x in c)


def register(scan, ref, v):
    s, r = scan.voxel_down_sample(v), ref.voxel_down_sample(v)
    for c in (s, r):
        c.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=3 * v, max_nn=30))
    sc, rc = s.voxel_down_sample(2 * v), r.voxel_down_sample(2 * v)
    if len(sc.points) < 3 or len(rc.points) < 3:
        return None
    feat = lambda c: o3d.pipelines.registration.compute_fpfh_feature(
        c, o3d.geometry.KDTreeSearchParamHybrid(radius=10 * v, max_nn=100))
    reg = o3d.pipelines.registration
    ransac = reg.registration_ransac_based_on_feature_matching(
        rc, sc, feat(rc), feat(sc), True, 5 * v, reg.TransformationEstimationPointToPoint(False), 3,
        [reg.CorrespondenceCheckerBasedOnEdgeLength(0.9), reg.CorrespondenceCheckerBasedOnDistance(5 * v)],
        reg.RANSACConvergenceCriteria(100000, 0.999))
    icp = reg.registration_icp(r, s, 2 * v, ransac.transformation, reg.TransformationEstimationPointToPlane())
    return icp.transformation  # maps the reference into the scan: T_scan_ref


def main(d, out, max_trials):
    o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)
    o3d.utility.random.seed(1)
    manifest = json.load(open(f"{d}/manifest.json"))
    tol = {"t": manifest["tolerance"]["translation_mm"] * 1e3, "r": manifest["tolerance"]["rotation_deg"]}
    gts = sorted((json.load(open(p)) for p in glob.glob(f"{d}/gt/*.json")), key=lambda g: g["trial"])
    per_scene, lines = {}, []
    for g in gts:
        if max_trials and per_scene.get(g["scene"], 0) >= max_trials:
            continue
        per_scene[g["scene"]] = per_scene.get(g["scene"], 0) + 1
        xyz, label = read_labelled_pcd(f"{d}/scans/{g['trial']}.pcd")
        for tg in g["targets"]:
            mine = xyz[(label == tg["label"]) & np.isfinite(xyz).all(axis=1)]
            scan = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(mine))
            ref = o3d.io.read_point_cloud(f"{d}/{tg['reference']}")
            v = tg["voxel_mm"] or float(np.linalg.norm(ref.get_axis_aligned_bounding_box().get_extent())) / 150
            t0 = time.perf_counter()
            T = register(scan, ref, v) if len(mine) >= 3 else None
            dt = time.perf_counter() - t0
            te, re = errors(T if T is not None else np.eye(4), np.array(tg["T_scan_object"]["matrix"]), tg["symmetry"])
            ok = T is not None
            within = te <= tol["t"] and re <= tol["r"]
            pose = tg["expect"] == "pose"
            lines.append({"benchmark": manifest["benchmark"], "scene": g["scene"], "object": tg["object"],
                          "method": "open3d", "trial": g["trial"], "cell": g["cell"], "repetition": g["repetition"],
                          "seed": g["seed"], "conditions": g["conditions"], "expect": tg["expect"],
                          "status": "ok" if ok else "failed", "reason": "" if ok else "too few points",
                          "success": bool(ok and within) if pose else not ok,
                          "false_accept": bool(ok and not within) if pose else ok,
                          "t_err_um": te, "r_err_deg": re, "scan_points": int(np.isfinite(xyz).all(axis=1).sum()),
                          "timing": {"time_s": dt, "peak_rss_mb": 0.0, "memory_scope": "not measured"}})
    with open(out + ".tmp", "w") as f:
        for l in lines:
            f.write(json.dumps(l) + "\n")
    os.replace(out + ".tmp", out)
    print(f"open3d {o3d.__version__}: {len(lines)} registrations -> {out}", file=sys.stderr)


if __name__ == "__main__":
    args = sys.argv[1:]
    n = 0
    if "--trials" in args:
        i = args.index("--trials")
        n = int(args[i + 1])
        del args[i:i + 2]
    if len(args) != 2:
        sys.exit(__doc__)
    main(args[0], args[1], n)
