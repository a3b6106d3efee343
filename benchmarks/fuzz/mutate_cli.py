#!/usr/bin/env python3
"""Black-box mutation campaign of `laserfit import`, as a user's corrupt files
would reach it: seeded mutations of real CAD files (flipped bytes, cut files, repeated and deleted
chunks, extreme numbers), each run through the CLI with a hard wall-clock limit. Every run must
end with exit 0 and an output file, or exit 1, exactly one line on stderr naming the file, and
no output file. Anything else (a signal, another exit code, a hang, a stray output) is a finding.

  mutate_cli.py LASERFIT_BIN OUT_DIR --count N [--seed S] [--jobs J] SOURCE_FILE...

Writes OUT_DIR/summary.json and OUT_DIR/findings/ (the inputs that failed, with their stderr).
"""
import argparse
import concurrent.futures
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

EXTREMES = [b"1e308", b"-1e308", b"nan", b"inf", b"999999999999", b"-2147483649", b"0", b"-0",
            b"4294967296", b"1e-320"]
NUMBER = re.compile(rb"-?\d+(\.\d+)?([eE][-+]?\d+)?")


def mutate(data: bytes, rng: random.Random) -> bytes:
    b = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        kind = rng.choice(["flip", "cut", "repeat", "delete", "number"])
        n = len(b)
        if n < 2:
            break
        if kind == "flip":
            for _ in range(rng.randint(1, 16)):
                b[rng.randrange(n)] ^= 1 << rng.randrange(8)
        elif kind == "cut":
            del b[rng.randrange(1, n):]
        elif kind == "repeat":
            i = rng.randrange(n)
            j = min(n, i + rng.randint(1, 4096))
            b[j:j] = b[i:j] * rng.randint(1, 8)
        elif kind == "delete":
            i = rng.randrange(n)
            del b[i:i + rng.randint(1, 4096)]
        else:
            spans = [m.span() for m in NUMBER.finditer(bytes(b[:200000]))]
            if spans:
                i, j = rng.choice(spans)
                b[i:j] = rng.choice(EXTREMES)
    return bytes(b)


def run_one(args, index, source, data, tmp):
    ext = os.path.splitext(source)[1]
    path = os.path.join(tmp, f"m{index:06d}{ext}")
    out = os.path.join(tmp, f"m{index:06d}.out.ply")
    with open(path, "wb") as f:
        f.write(data)
    cmd = [args.bin, "import", path, "-o", out, "--timeout", str(args.timeout)]
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, capture_output=True, timeout=args.timeout + 60)
        code, err = p.returncode, p.stderr.decode(errors="replace")
    except subprocess.TimeoutExpired:
        code, err = "hang", ""
    secs = time.monotonic() - t0
    made = os.path.exists(out)
    lines = err.count("\n")
    ok = (code == 0 and made) or (code == 1 and lines == 1 and path in err and not made)
    leftovers = [f for f in os.listdir(tmp) if f.startswith(f"m{index:06d}.out")]
    if not ok and args.findings:
        os.makedirs(args.findings, exist_ok=True)
        shutil.copy(path, os.path.join(args.findings, os.path.basename(path)))
        with open(os.path.join(args.findings, os.path.basename(path) + ".txt"), "w") as f:
            f.write(f"exit {code}\n{err}")
    for f in [path] + [os.path.join(tmp, x) for x in leftovers]:
        if os.path.exists(f):
            os.remove(f)
    first = err.split(":", 3)[-1].strip()[:80] if err else ""
    return {"index": index, "source": os.path.basename(source), "code": code, "ok": ok,
            "seconds": round(secs, 3), "lines": lines, "stray_output": made and code != 0,
            "reason": first}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bin")
    ap.add_argument("out")
    ap.add_argument("sources", nargs="+")
    ap.add_argument("--count", type=int, default=1000, help="mutated files per source")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=os.cpu_count())
    ap.add_argument("--timeout", type=float, default=60)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    args.findings = os.path.join(args.out, "findings")
    tmp = tempfile.mkdtemp(prefix="laserfit-mutate-")
    results = []
    t0 = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        futures = []
        for s_i, source in enumerate(args.sources):
            data = open(source, "rb").read()
            rng = random.Random(args.seed * 1000003 + s_i)
            for k in range(args.count):
                futures.append(pool.submit(run_one, args, s_i * args.count + k, source,
                                           mutate(data, rng), tmp))
        for f in concurrent.futures.as_completed(futures):
            results.append(f.result())
    shutil.rmtree(tmp, ignore_errors=True)
    results.sort(key=lambda r: r["index"])
    with open(os.path.join(args.out, "runs.jsonl"), "w") as f:
        for r in results:
            f.write(json.dumps(r) + "\n")
    summary = {}
    for r in results:
        s = summary.setdefault(r["source"], {"runs": 0, "exit0": 0, "exit1": 0, "findings": 0,
                                             "crashes": 0, "hangs": 0, "stray_outputs": 0,
                                             "max_seconds": 0})
        s["runs"] += 1
        s["exit0"] += r["code"] == 0
        s["exit1"] += r["code"] == 1
        s["findings"] += not r["ok"]
        s["crashes"] += isinstance(r["code"], int) and r["code"] < 0
        s["hangs"] += r["code"] == "hang"
        s["stray_outputs"] += r["stray_output"]
        s["max_seconds"] = max(s["max_seconds"], r["seconds"])
    total = {"seed": args.seed, "count_per_source": args.count, "timeout_s": args.timeout,
             "wall_s": round(time.monotonic() - t0, 1), "sources": summary}
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(total, f, indent=2)
    print(json.dumps(total, indent=2))
    return 1 if any(s["findings"] for s in summary.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
