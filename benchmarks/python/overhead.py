#!/usr/bin/env python3
"""The Python module's overhead over the C++ call it wraps, on a 1 M-point scan.

Simulates the USB socket scan (laserfit.scan: 1201 x 2048 grid, 1.69 M measured points, float32),
samples the plug's reference, then registers it `--repetitions` times from the true pose as prior
(refine only: the shortest call, where a fixed overhead weighs most) and as the paper's q0 gate
(RANSAC). Overhead = wall time of laserfit.register (array conversion, settings, GIL, result)
over the C++ register_scan's own wall time (result.timings_s["total"]), median of the runs.

  PYTHONPATH=build/python /usr/bin/python3 benchmarks/python/overhead.py [--repetitions 5]
"""
import argparse
import statistics
import time

import numpy as np

import laserfit


def quaternion(R):
    w = np.sqrt(max(1 + np.trace(R), 0)) / 2
    return [w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repetitions", type=int, default=5)
    a = ap.parse_args()
    s = laserfit.scan("datasets/scenes/usb_socket.yaml")
    pts = s["points"]
    v, f = laserfit.import_mesh("cad/usb_a_plug.ply")
    ref, n = laserfit.refcloud(v, f, count=50000, seed=1)
    T = s["T_scan_object"]["usb_a_plug"]
    print(f"scan {pts.shape[0]} x {pts.shape[1]}, {int(np.isfinite(pts).all(axis=2).sum())} measured")
    cases = {"refine only (prior)": dict(prior=T, refine_only=True),
             "RANSAC (q0)": dict(q0=quaternion(T[:3, :3]))}
    for name, kw in cases.items():
        ratios, walls = [], []
        for _ in range(a.repetitions):
            t = time.perf_counter()
            r = laserfit.register(pts, ref, ref_normals=n, sensor_origin=s["sensor_origin"], **kw)
            wall = time.perf_counter() - t
            walls.append(wall)
            ratios.append(wall / r.timings_s["total"] - 1)
        print(f"{name:20s} {r.status:9s} wall median {statistics.median(walls):.3f} s, overhead "
              f"median {100 * statistics.median(ratios):.1f} % (max {100 * max(ratios):.1f} %)")


if __name__ == "__main__":
    main()
