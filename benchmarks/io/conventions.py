#!/usr/bin/env python3
"""The same scan in other tools' conventions registers to the same pose (issue: your part, your scan).

From laserfit's own scan (organized binary PCD, mm, sensor origin in its header) this writes
  viewpoint.pcd  the same PCD without its laserfit.* comments: the sensor origin only in the
                 standard VIEWPOINT field, the unit unstated (read as the default mm)
  flat.pcd       laserfit's PCD of the same scan unorganized (its measured points only)
  open3d_m.ply   Open3D's write_point_cloud of those points: double x y z, metres, no unit stated
then runs `laserfit register` on each (Open3D's with --unit m and --viewpoint and priors in
metres, as a lab would give them) and prints how far each pose lies from the pose of the PCD it
stands for (translation in um, rotation in deg, per reference). Open3D has no organized clouds,
so its PLY is compared with flat.pcd; how far flat.pcd lies from the organized scan (the
mixed-pixel filter needs the grid) is printed too. --assembled adds `laserfit assemble`'s cloud
of the same sweep (from `scan --raw --flange-poses`), compared with the scan. --prior (once per
reference, mm) and --q0 are handed to every registration: the arm's belief, as in a cell.
Needs python3-open3d and numpy.

  python3 benchmarks/io/conventions.py build/bin/laserfit scan.pcd ref.pcd [ref.pcd ...]
      [--assembled scan_assembled.pcd] [--prior "x y z qw qx qy qz" ...] [--q0 "qw qx qy qz"]
"""
import argparse
import json
import pathlib
import subprocess
import sys
import tempfile

import numpy as np
import open3d as o3d


def read_laserfit_pcd(path):
    """Header lines and the float32 x y z of a binary laserfit PCD (its own writer's layout)."""
    raw = pathlib.Path(path).read_bytes()
    end = raw.index(b"DATA binary\n") + len(b"DATA binary\n")
    header = raw[:end].decode().splitlines()
    fields = next(l for l in header if l.startswith("FIELDS")).split()[1:]
    count = int(next(l for l in header if l.startswith("POINTS")).split()[1])
    rows = np.frombuffer(raw[end:], dtype=np.float32, count=count * len(fields))
    return header, raw, end, rows.reshape(count, len(fields))[:, :3].astype(np.float64)


def register(binary, scan, refs, extra):
    out = subprocess.run([binary, "register", "--scan", scan, "--json"] +
                         [a for r in refs for a in ("--ref", r)] + extra,
                         check=True, capture_output=True, text=True).stdout
    return {r["ref"]: (np.array(r["T_scan_ref"]["matrix"]), r["status"])
            for r in json.loads(out)["results"]}


def apart(A, B):
    dt = np.linalg.norm(A[:3, 3] - B[:3, 3]) * 1e3
    c = (np.trace(A[:3, :3].T @ B[:3, :3]) - 1) / 2
    return dt, np.degrees(np.arccos(np.clip(c, -1, 1)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("laserfit")
    ap.add_argument("scan")
    ap.add_argument("refs", nargs="+")
    ap.add_argument("--assembled", help="laserfit assemble's cloud of the same sweep")
    ap.add_argument("--prior", action="append", default=[], help="x y z qw qx qy qz (mm), per ref")
    ap.add_argument("--q0", help="qw qx qy qz")
    a = ap.parse_args()
    belief = [x for p in a.prior for x in ("--prior", p)] + (["--q0", a.q0] if a.q0 else [])
    belief_m = [x for p in a.prior
                for x in ("--prior", " ".join([str(float(v) * 1e-3) for v in p.split()[:3]] +
                                             p.split()[3:]))] + (["--q0", a.q0] if a.q0 else [])
    header, raw, end, xyz = read_laserfit_pcd(a.scan)
    vp = next(l for l in header if l.startswith("# laserfit.viewpoint")).split()[2:5]
    with tempfile.TemporaryDirectory() as tmp:
        o3d_ply = f"{tmp}/open3d_m.ply"
        finite = np.isfinite(xyz).all(axis=1)
        pc = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(xyz[finite] * 1e-3))
        o3d.io.write_point_cloud(o3d_ply, pc, write_ascii=False)
        vp_pcd = f"{tmp}/viewpoint.pcd"
        kept = [l for l in header if not l.startswith("# laserfit.")]
        pathlib.Path(vp_pcd).write_bytes(("\n".join(kept) + "\n").encode() + raw[end:])
        flat_pcd = f"{tmp}/flat.pcd"
        n = int(finite.sum())
        flat = [l for l in header if not l.startswith(("FIELDS", "SIZE", "TYPE", "COUNT", "WIDTH",
                                                       "HEIGHT", "POINTS", "DATA"))]
        flat += ["FIELDS x y z", "SIZE 4 4 4", "TYPE F F F", "COUNT 1 1 1", f"WIDTH {n}",
                 "HEIGHT 1", f"POINTS {n}", "DATA binary"]
        body = np.ascontiguousarray(xyz[finite].astype(np.float32)).tobytes()
        pathlib.Path(flat_pcd).write_bytes(("\n".join(flat) + "\n").encode() + body)
        own = register(a.laserfit, a.scan, a.refs, belief)
        own_flat = register(a.laserfit, flat_pcd, a.refs, belief)
        pairs = [
            ("viewpoint.pcd", register(a.laserfit, vp_pcd, a.refs, belief), "own", own),
            ("open3d_m.ply", register(a.laserfit, o3d_ply, a.refs,
                                      ["--unit", "m", "--viewpoint",
                                       " ".join(str(float(v) * 1e-3) for v in vp)] + belief_m),
             "flat.pcd", own_flat),
            ("flat.pcd", own_flat, "own (organized)", own),
        ]
        if a.assembled:
            pairs.append(("assembled", register(a.laserfit, a.assembled, a.refs, belief), "own",
                          own))
    for name, poses, base_name, base in pairs:
        for ref, (T, status) in poses.items():
            dt, dr = apart(base[ref][0], T)
            print(f"{name:14s} {ref} {status:9s}: {dt:9.3f} um, {dr:.6f} deg from {base_name} "
                  f"({base[ref][1]})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
