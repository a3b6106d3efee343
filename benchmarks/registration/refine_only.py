#!/usr/bin/env python3
"""Refine-only honesty: `laserfit register --refine-only` from priors a fixed angle and distance
off the true pose (random axis and direction, seeded), graded against the scan's ground truth.
A false accept is an `ok` more than 50 um or 0.5 deg off (the trust limits' tolerance).

  laserfit scan datasets/scenes/o2ac_panel.yaml -o scan.pcd --gt gt.json
  laserfit refcloud tests/data/o2ac/02-PANEL.stl -o ref.pcd --density 20
  python3 benchmarks/registration/refine_only.py build/bin/laserfit scan.pcd ref.pcd gt.json \
      --count 30 --rotation-deg 20 --translation-mm 10 --seed 11
Needs python3-numpy (Debian)."""
import argparse, json, subprocess
import numpy as np


def rotvec(axis, angle):  # Rodrigues
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def quat_wxyz(R):
    w = np.sqrt(max(0.0, 1 + np.trace(R))) / 2
    x = np.copysign(np.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    return w, x, y, z


def main():
    a = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    for n in ("laserfit", "scan", "ref", "gt"):
        a.add_argument(n)
    a.add_argument("--count", type=int, default=30)
    a.add_argument("--rotation-deg", type=float, default=20)
    a.add_argument("--translation-mm", type=float, default=10)
    a.add_argument("--seed", type=int, default=11)
    o = a.parse_args()
    T = np.array(json.load(open(o.gt))["objects"][0]["T_scan_object"]["matrix"])
    rng = np.random.default_rng(o.seed)
    counts = {"ok": 0, "ambiguous": 0, "failed": 0, "false_accept": 0}
    for i in range(o.count):
        ax = rng.normal(size=3); ax /= np.linalg.norm(ax)
        d = rng.normal(size=3); d /= np.linalg.norm(d)
        R = T[:3, :3] @ rotvec(ax, np.radians(o.rotation_deg))
        t = T[:3, 3] + o.translation_mm * d
        prior = " ".join("%.9g" % v for v in (*t, *quat_wxyz(R)))
        out = subprocess.run([o.laserfit, "register", "--scan", o.scan, "--ref", o.ref, "--prior",
                              prior, "--refine-only", "--json"], capture_output=True, text=True)
        r = json.loads(out.stdout)["results"][0]
        E = np.linalg.inv(T) @ np.array(r["T_scan_ref"]["matrix"])
        ang = np.degrees(np.arccos(np.clip((np.trace(E[:3, :3]) - 1) / 2, -1, 1)))
        dt = np.linalg.norm(E[:3, 3])
        fa = r["status"] == "ok" and (dt > 0.05 or ang > 0.5)
        counts[r["status"]] += 1
        counts["false_accept"] += int(fa)
        print("%2d %-9s %8.3f deg %9.4f mm  rmse %6.1f um  sigma %5.1f um%s  %s" % (
            i, r["status"], ang, dt, r["inlier_rmse_um"], r["residual_sigma_um"],
            "  FALSE ACCEPT" if fa else "", r["reason"][:80]), flush=True)
    print(json.dumps(counts))


if __name__ == "__main__":
    main()
