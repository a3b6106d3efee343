#!/usr/bin/python3
"""Scans and completion time per insertion, as the NIST task board protocol scores a trial.

usage: completion.py LABEL OUTCOMES.jsonl [...]   (laserfit-controller sim/run --out files)

Prints one Markdown table row: trials, inserted, missed, refused, scans (median / p95 / max),
completion time (cell time + the controller's compute, median / p95) and its two parts'
medians. Percentiles are nearest-rank.
"""
import json, math, statistics, sys


def pct(v, p):
    v = sorted(v)
    return v[max(0, math.ceil(p / 100 * len(v)) - 1)]


label, rows = sys.argv[1], [json.loads(l) for f in sys.argv[2:] for l in open(f)]
if not rows:
    sys.exit('completion.py: no outcome records')
scans = [r['scans'] for r in rows]
done = [r['completion_s'] for r in rows]
inserted = sum(r['success'] for r in rows)
refused = sum(r['result'].startswith('refused') for r in rows)
print(f"| {label} | {len(rows)} | {inserted} = {100 * inserted / len(rows):.1f} % "
      f"| {sum(r['result'] == 'missed' for r in rows)} | {refused} "
      f"| {statistics.median(scans):g} / {pct(scans, 95)} / {max(scans)} "
      f"| {statistics.median(done):.1f} / {pct(done, 95):.1f} "
      f"| {statistics.median(r['cell_time_s'] for r in rows):.1f} "
      f"| {statistics.median(r['compute_s'] for r in rows):.1f} |")
