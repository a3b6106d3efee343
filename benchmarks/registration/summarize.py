#!/usr/bin/python3
"""Summarise registration campaign records (JSON Lines) into a Markdown table.

usage: summarize.py results.jsonl [open3d.jsonl ...] > table.md
Per scene, object and method: trials, success rate (within tolerance, and `ok` or a correctly
reported `ambiguous` symmetric DoF), false accepts (`ok` outside tolerance), ambiguous / failed
counts, median and p95 of the translation and rotation errors over the trials that returned a
pose (status not failed), and the median / p95 registration time. Standard library only.
"""
import json
import sys


def quantile(v, q):
    if not v:
        return float("nan")
    v = sorted(v)
    pos = q * (len(v) - 1)
    i = int(pos)
    f = pos - i
    return v[i] * (1 - f) + v[i + 1] * f if i + 1 < len(v) else v[i]


def main(paths):
    groups = {}
    for p in paths:
        with open(p) as f:
            for line in f:
                r = json.loads(line)
                groups.setdefault((r["scene"], r["object"], r["method"]), []).append(r)
    print("| scene | object | method | trials | success | false accepts | ambiguous | failed |"
          " t median / p95 (µm) | r median / p95 (deg) | time median / p95 (s) |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for (scene, obj, method), rs in sorted(groups.items()):
        n = len(rs)
        posed = [r for r in rs if r["status"] != "failed"]
        t = [r["t_err_um"] for r in posed]
        a = [r["r_err_deg"] for r in posed]
        s = [r["time_s"] for r in rs]
        print(f"| {scene} | {obj} | {method} | {n} | {100.0 * sum(r['success'] for r in rs) / n:.1f} % |"
              f" {sum(r['false_accept'] for r in rs)} | {sum(r['status'] == 'ambiguous' for r in rs)} |"
              f" {sum(r['status'] == 'failed' for r in rs)} | {quantile(t, .5):.1f} / {quantile(t, .95):.1f} |"
              f" {quantile(a, .5):.3f} / {quantile(a, .95):.3f} | {quantile(s, .5):.2f} / {quantile(s, .95):.2f} |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: summarize.py results.jsonl [more.jsonl ...]")
    main(sys.argv[1:])
