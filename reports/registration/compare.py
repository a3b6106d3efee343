#!/usr/bin/python3
"""Record by record, what changed between two runs of the same trials (same benchmark seeds).

usage: compare.py BEFORE.jsonl AFTER.jsonl [object ...]

Per target: success and determinable counts in both over the trials both hold, then every
(trial, object, method) whose success, status or determinable differs, with the errors.
"""
import json, lzma, sys


def records(path):
    """A .jsonl file, or a .jsonl.xz as the campaigns are kept in reports/."""
    return lzma.open(path, 'rt') if path.endswith('.xz') else open(path)


def load(path, objs):
    out = {}
    for line in records(path):
        r = json.loads(line)
        if not objs or r['object'] in objs:
            out[(r['trial'], r['object'], r['method'])] = r
    return out


before, after = (load(p, set(sys.argv[3:])) for p in sys.argv[1:3])
keys = sorted(set(before) & set(after))
print(f'{len(keys)} records in both ({len(before)} before, {len(after)} after)')
for obj in sorted({k[1] for k in keys}):
    ks = [k for k in keys if k[1] == obj]
    row = [obj, len(ks)]
    for run in (before, after):
        ok = sum(run[k]['success'] for k in ks)
        det = [k for k in ks if run[k].get('determinable', True)]
        det_ok = sum(run[k]['success'] for k in det)
        fa = sum(run[k]['false_accept'] for k in ks)
        row += [f'success {ok}', f'determinable {det_ok}/{len(det)}', f'false accepts {fa}']
    print(' | '.join(map(str, row)))
for k in keys:
    b, a = before[k], after[k]
    if (b['success'], b['status'], b.get('determinable')) != (a['success'], a['status'], a.get('determinable')):
        fmt = lambda r: (f"{r['status']:9s} success={int(r['success'])} det={int(r.get('determinable', True))} "
                         f"t={r['t_err_um']:.1f}um r={r['r_err_deg']:.3f}deg")
        print(f'rep {b["repetition"]:3d} {k[1]:18s} {fmt(b)}  ->  {fmt(a)}')
