#!/usr/bin/python3
"""Open3D baseline for the registration campaign: FPFH + RANSAC (feature matching) + ICP
point-to-plane on the scans and references dumped by `registration_campaign --dump DIR`.

usage: open3d_baseline.py DIR OUT.jsonl [--t-tol-mm 0.05] [--r-tol-deg 0.5]
Each dumped scan holds only the target's points (the simulator's labels: an oracle segmentation
that favours Open3D). Same voxel rule as laserfit (given voxel or reference diagonal / 150), FPFH
radius 5 voxels on a 2x grid, RANSAC seeded, then point-to-plane ICP at 2 voxels. Open3D has no
trust decision: every result counts as `ok`. Errors modulo the symmetry, as in the C++ runner.
"""
import json
import math
import sys
import time

import numpy as np
import open3d as o3d


def sym_rotations(text):
    parts = text.split()
    if parts[0] == "none":
        return [np.eye(3)], None
    axis = {"x": np.array([1.0, 0, 0]), "y": np.array([0, 1.0, 0]), "z": np.array([0, 0, 1.0])}[parts[-1]]
    if parts[0] == "continuous":
        return [np.eye(3)], axis
    n = int(parts[1])
    rots = []
    for k in range(n):
        a = 2 * math.pi * k / n
        K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        rots.append(np.eye(3) + math.sin(a) * K + (1 - math.cos(a)) * K @ K)
    return rots, None


def errors(T, G, sym):
    rots, cont = sym_rotations(sym)
    t = np.linalg.norm(T[:3, 3] - G[:3, 3]) * 1e3
    if cont is not None:
        a, b = T[:3, :3] @ cont, G[:3, :3] @ cont
        return t, math.degrees(math.atan2(np.linalg.norm(np.cross(a, b)), a @ b))
    r = min(math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(T[:3, :3].T @ G[:3, :3] @ S) - 1) / 2)))) for S in rots)
    return t, r


def matrix(j):
    return np.array(j["matrix"], dtype=float)


def main(d, out, t_tol=0.05, r_tol=0.5):
    o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)
    o3d.utility.random.seed(1)
    manifest = json.load(open(f"{d}/manifest.json"))
    lines = []
    for e in manifest:
        scan = o3d.io.read_point_cloud(f"{d}/{e['scan']}")
        ref = o3d.io.read_point_cloud(f"{d}/{e['ref']}")
        ext = ref.get_axis_aligned_bounding_box().get_extent()
        v = e["voxel_mm"] or float(np.linalg.norm(ext)) / 150
        t0 = time.perf_counter()
        s = scan.voxel_down_sample(v)
        r = ref.voxel_down_sample(v)
        for c in (s, r):
            c.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=3 * v, max_nn=30))
        sc, rc = s.voxel_down_sample(2 * v), r.voxel_down_sample(2 * v)
        feat = lambda c: o3d.pipelines.registration.compute_fpfh_feature(
            c, o3d.geometry.KDTreeSearchParamHybrid(radius=10 * v, max_nn=100))
        ok = len(sc.points) >= 3 and len(rc.points) >= 3
        T = np.eye(4)
        if ok:
            ransac = o3d.pipelines.registration.registration_ransac_based_on_feature_matching(
                rc, sc, feat(rc), feat(sc), True, 5 * v,
                o3d.pipelines.registration.TransformationEstimationPointToPoint(False), 3,
                [o3d.pipelines.registration.CorrespondenceCheckerBasedOnEdgeLength(0.9),
                 o3d.pipelines.registration.CorrespondenceCheckerBasedOnDistance(5 * v)],
                o3d.pipelines.registration.RANSACConvergenceCriteria(100000, 0.999))
            icp = o3d.pipelines.registration.registration_icp(
                r, s, 2 * v, ransac.transformation,
                o3d.pipelines.registration.TransformationEstimationPointToPlane())
            T = icp.transformation  # maps the reference into the scan: T_scan_ref
        dt = time.perf_counter() - t0
        te, re = errors(T, matrix(e["T_gt"]), e["symmetry"])
        within = te <= t_tol * 1e3 and re <= r_tol
        lines.append({"scene": e["scene"], "object": e["object"], "method": "open3d", "trial": e["trial"],
                      "status": "ok" if ok else "failed", "reason": "", "t_err_um": te, "r_err_deg": re,
                      "time_s": dt, "success": bool(ok and within), "false_accept": bool(ok and not within)})
    with open(out + ".tmp", "w") as f:
        for l in lines:
            f.write(json.dumps(l) + "\n")
    import os
    os.replace(out + ".tmp", out)
    print(f"open3d {o3d.__version__}: {len(lines)} registrations -> {out}", file=sys.stderr)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
