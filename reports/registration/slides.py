#!/usr/bin/python3
"""Where a method's misses lie against a reference run's correct pose of the same trial.

usage: slides.py REFERENCE.jsonl OTHER.jsonl [object]   (object default: needle)

For every unsuccessful OTHER record of the object whose trial the REFERENCE run got right and
whose reason names an axis ("about [x, y, z]"), prints per method the displacement of the
reference's origin between the two poses (um: median, min, max) and the smallest share of it
that lies along the named axis. Records naming a translation ("along [...]") are counted apart.
Needs python3-numpy (Debian), hence /usr/bin/python3.
"""
import json, lzma, re, sys
from collections import defaultdict

import numpy as np


def records(path):
    """A .jsonl file, or a .jsonl.xz as the campaigns are kept in reports/."""
    return lzma.open(path, 'rt') if path.endswith('.xz') else open(path)


def main(ref_path, other_path, obj="needle"):
    right = {}
    for line in records(ref_path):
        r = json.loads(line)
        if r["object"] == obj and r["success"]:
            right[r["trial"]] = np.array(r["T_scan_ref"])
    shifts, along = defaultdict(list), defaultdict(int)
    for line in records(other_path):
        r = json.loads(line)
        if r["object"] != obj or r["success"] or r["trial"] not in right or "T_scan_ref" not in r:
            continue
        m = re.search(r"about \[([^\]]+)\]", r.get("reason", ""))
        if not m:
            along[r["method"]] += 1
            continue
        axis = np.array([float(x) for x in m.group(1).split(",")])
        d = np.array(r["T_scan_ref"])[:3, 3] - right[r["trial"]][:3, 3]
        n = np.linalg.norm(d)
        shifts[r["method"]].append((n * 1e3, abs(d @ axis) / n if n > 0 else 1.0))
    for method in sorted(set(shifts) | set(along)):
        s = shifts[method]
        um = [x[0] for x in s]
        print(f"{method}: {len(s)} misses naming a rotation axis", end="")
        if s:
            print(f", shift median {np.median(um):.0f} um (min {min(um):.0f}, max {max(um):.0f}),"
                  f" smallest axial share {min(x[1] for x in s):.3f}", end="")
        print(f"; {along[method]} naming no rotation axis")


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    main(*sys.argv[1:])
