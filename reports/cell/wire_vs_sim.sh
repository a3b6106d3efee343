#!/usr/bin/env bash
# `run` over the cell protocol against `cell-sim` vs `sim` in one process, on the same trials:
# prints how many outcomes agree (every field and log line but the wall-clock times).
#   reports/cell/wire_vs_sim.sh CELL TRIALS STRATEGIES [BUILD] [FIRST]
# e.g. reports/cell/wire_vs_sim.sh needle 30 ic1,laser_pose
#      reports/cell/wire_vs_sim.sh usb 3 laser_pose build 40   (trials 40-42: each touches the plate)
set -euo pipefail
cell=$1 trials=$2 strategies=$3 bin=${4:-build}/bin/laserfit-controller first=${5:-0}
cd "$(dirname "$0")/../.."
out=$(mktemp -d)
trap 'kill $server 2>/dev/null || true; rm -rf "$out"' EXIT
"$bin" cell-sim --cell "cells/$cell.yaml" --listen 127.0.0.1:0 > "$out/server.txt" &
server=$!
until grep -q port "$out/server.txt" 2>/dev/null; do sleep 0.1; done
port=$(grep -o 'port [0-9]*' "$out/server.txt" | cut -d' ' -f2)
common=(--cell "cells/$cell.yaml" --thresholds "reports/paper/thresholds_$cell.yaml"
        --strategy "$strategies" --trials "$trials" --first "$first")
"$bin" run --cell-endpoint "127.0.0.1:$port" "${common[@]}" --quiet -o "$out/run.jsonl"
"$bin" sim "${common[@]}" --jobs 2 --quiet -o "$out/sim.jsonl" > /dev/null
/usr/bin/python3 - "$out/run.jsonl" "$out/sim.jsonl" <<'PY'
import json, sys
def load(path):
    rows = [json.loads(line) for line in open(path)]
    for r in rows:
        for k in ("time_s", "cell_time_s", "compute_s", "completion_s"):
            r.pop(k)
    return rows
run, sim = load(sys.argv[1]), load(sys.argv[2])
same = sum(a == b for a, b in zip(run, sim))
print(f"{same} of {len(sim)} outcomes identical (run: {len(run)}); "
      f"inserted: run {sum(r['success'] for r in run)}, sim {sum(r['success'] for r in sim)}")
sys.exit(0 if same == len(sim) == len(run) else 1)
PY
