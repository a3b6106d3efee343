#!/usr/bin/python3
"""Merge a needle laser campaign's chunk files into trials.jsonl + summary.json.

usage: aggregate.py CHUNK_DIR CAMPAIGN_DIR COMMIT

CHUNK_DIR holds chunk_K.jsonl, one per `laserfit-controller sim ... --first $((K*100)) --trials
100 --json --out chunk_K.jsonl` (K = 0, 1, ...; a chunk counts once it has 100 records).
CAMPAIGN_DIR/trials.jsonl gets every record with "trial" = 100 K + j added, in trial order, and
CAMPAIGN_DIR/summary.json the aggregate (the fields of the earlier campaigns' summaries; the
strategy is the records' own; for laser_pose, which also corrects the orientation, the true
angle to the eye's axis of the inserted threads is added).
"""
import json, math, os, statistics, sys

cdir, out, commit = sys.argv[1], sys.argv[2], sys.argv[3]
T, k = [], 0
while os.path.exists(f'{cdir}/chunk_{k}.jsonl'):
    rows = [json.loads(l) for l in open(f'{cdir}/chunk_{k}.jsonl')]
    if len(rows) != 100:
        break  # still running
    for j, r in enumerate(rows):
        r['trial'] = 100 * k + j
        T.append(r)
    k += 1
if not T:
    sys.exit(f'{cdir}: no complete chunk_0.jsonl')


def mmm(v):
    return {'min': min(v), 'median': statistics.median(v), 'max': max(v)}


ok = [t for t in T if t['success']]
fail, ft, pap = {}, {}, {}
for t in T:
    if not t['success']:
        fail[t['result']] = fail.get(t['result'], 0) + 1
        ft.setdefault(t['result'], []).append(t['trial'])
    p = pap.setdefault(t['trial'] // 30, {'arm_pair': t['trial'] // 30, 'successes': 0, 'trials': 0})
    p['trials'] += 1
    p['successes'] += t['success']
S0 = T[0].get('strategy', 'laser')  # the earlier campaigns' summaries: laser, no angle
S = {'cell': 'cells/needle.yaml', 'thresholds': 'reports/paper/thresholds_needle.yaml', 'seed': 1,
     'strategy': S0, 'commit': commit,
     'trials': len(T), 'successes': len(ok), 'success_rate': len(ok) / len(T),
     'failures': fail, 'failed_trials': ft,
     'trials_with_a_search_sweep': sum(any(l.startswith('no trusted') and ' mm' in l and 'sweeps' in l
                                           for l in t['log']) for t in T),
     'trials_with_a_raised_scan': sum(any(l.startswith('no trusted') and 'farther back' in l
                                          for l in t['log']) for t in T),
     'inserted_lateral_um': mmm([math.hypot(*t['lateral_um']) for t in ok]),
     'inserted_across_um_abs': mmm([abs(t['lateral_um'][1]) for t in ok]),
     'inserted_along_um_abs': mmm([abs(t['lateral_um'][0]) for t in ok]),
     'inserted_depth_um': mmm([t['depth_um'] for t in ok]),
     'all_depth_um': mmm([t['depth_um'] for t in T if t.get('depth_um') is not None]),
     **({'inserted_angle_deg': mmm([t['angle_deg'] for t in ok])} if S0 == 'laser_pose' else {}),
     'scans_median': float(statistics.median([t['scans'] for t in T])),
     'scans_max': max(t['scans'] for t in T),
     'time_s_median': statistics.median([t['time_s'] for t in T]),
     'per_arm_pair': [pap[a] for a in sorted(pap)]}
os.makedirs(out, exist_ok=True)
with open(f'{out}/trials.jsonl.tmp', 'w') as f:
    for t in T:
        f.write(json.dumps(t) + '\n')
with open(f'{out}/summary.json.tmp', 'w') as f:
    json.dump(S, f, indent=2)
os.replace(f'{out}/trials.jsonl.tmp', f'{out}/trials.jsonl')
os.replace(f'{out}/summary.json.tmp', f'{out}/summary.json')
print(len(T), 'trials,', len(ok), 'inserted', fail)
