#!/usr/bin/python3
"""The true angle to the insertion axis, trial by trial, of two campaigns over the same seeded trials.

usage: paired_angle.py A/trials.jsonl B/trials.jsonl [FIRST:LAST ...]

Trial i is the same arm pair, start and errors in both (it depends only on the seed and i), so the
difference is the strategy's (or the code's). Per range (default: every trial both hold): median
and max angle of each, and in how many trials B's is the smaller. Inserted or not, every trial
with an angle counts.
"""
import json, lzma, statistics, sys


def records(path):
    """A .jsonl file, or a .jsonl.xz as the campaigns are kept in reports/."""
    return lzma.open(path, 'rt') if path.endswith('.xz') else open(path)


def load(path):
    return {r['trial']: r['angle_deg'] for r in map(json.loads, records(path)) if r.get('angle_deg') is not None}


a, b = load(sys.argv[1]), load(sys.argv[2])
both = sorted(set(a) & set(b))
ranges = [tuple(map(int, s.split(':'))) for s in sys.argv[3:]] or [(both[0], both[-1] + 1)]
print(f'A = {sys.argv[1]}\nB = {sys.argv[2]}')
print('trials | n | A median / max (deg) | B median / max (deg) | B smaller')
for lo, hi in ranges:
    ks = [k for k in both if lo <= k < hi]
    if not ks:
        continue
    fa, fb = [a[k] for k in ks], [b[k] for k in ks]
    print(f'{lo}-{hi - 1} | {len(ks)} | {statistics.median(fa):.3f} / {max(fa):.3f} | '
          f'{statistics.median(fb):.3f} / {max(fb):.3f} | {sum(y < x for x, y in zip(fa, fb))}')
