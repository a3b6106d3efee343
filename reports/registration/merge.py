#!/usr/bin/python3
"""Pool the records of several `laserfit bench` runs into one results.jsonl, sorted by trial.

usage: merge.py OUT.jsonl RUN_DIR[:object,object...] ...

Each RUN_DIR/results.jsonl contributes its records, or with ':objects' only those targets' (to
take the targets a later benchmark file left unchanged from an earlier run). A (trial, object,
method) given twice is an error, as is a record of another benchmark.
"""
import json, lzma, os, sys


def records(path):
    """A .jsonl file, or a .jsonl.xz as the campaigns are kept in reports/."""
    return lzma.open(path, 'rt') if path.endswith('.xz') else open(path)


out, seen, rows = sys.argv[1], set(), []
for arg in sys.argv[2:]:
    d, _, objs = arg.partition(':')
    keep = set(objs.split(',')) if objs else None
    plain = os.path.join(d, 'results.jsonl')
    for line in records(plain if os.path.exists(plain) else plain + '.xz'):
        r = json.loads(line)
        if keep is not None and r['object'] not in keep:
            continue
        key = (r['trial'], r['object'], r['method'])
        if key in seen:
            sys.exit(f'{d}: trial {key} given twice')
        if r['benchmark'] != 'registration':
            sys.exit(f'{d}: a record of benchmark {r["benchmark"]}')
        seen.add(key)
        rows.append((r['trial'], len(rows), line if line.endswith('\n') else line + '\n'))
rows.sort()
tmp = out + '.tmp'
with open(tmp, 'w') as f:
    f.writelines(line for _, _, line in rows)
os.replace(tmp, out)
print(f'{out}: {len(rows)} records')
