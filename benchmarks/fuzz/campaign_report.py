#!/usr/bin/env python3
"""Summarise a `make fuzz-campaign` run (out/fuzz/campaign/) as the Markdown tables of
reports/fuzz/README.md: per libFuzzer target its executions, rate, coverage and findings; per
source file of the black-box CLI mutation its runs, exits, crashes, hangs and stray outputs.

  campaign_report.py [CAMPAIGN_DIR]
"""
import json
import os
import re
import sys

d = sys.argv[1] if len(sys.argv) > 1 else "out/fuzz/campaign"
print("| target | executions | exec/s | coverage (edges) | features | corpus | findings |")
print("|---|---:|---:|---:|---:|---:|---:|")
for log in sorted(f for f in os.listdir(d) if f.endswith(".log")):
    name = log[:-4]
    text = open(os.path.join(d, log), errors="replace").read()
    stat = dict(re.findall(r"^stat::(\w+):\s+(\d+)", text, re.M))
    if "number_of_executed_units" not in stat:  # stopped before its final stats: last status line
        counts = re.findall(r"^#(\d+)\s", text, re.M)
        stat["number_of_executed_units"] = counts[-1] if counts else "0"
        rates = re.findall(r"exec/s: (\d+)", text)
        stat["average_exec_per_sec"] = (rates[-1] if rates else "?") + " (stopped)"
    last = re.findall(r"cov: (\d+) ft: (\d+) corp: (\d+)", text)
    cov, ft, corp = last[-1] if last else ("?", "?", "?")
    findings_dir = os.path.join(d, "findings", name)
    findings = len(os.listdir(findings_dir)) if os.path.isdir(findings_dir) else 0
    print(f"| {name} | {int(stat.get('number_of_executed_units', 0)):,} | "
          f"{stat.get('average_exec_per_sec', '?')} | {cov} | {ft} | {corp} | {findings} |")
print()
print("| mutated from | runs | exit 0 | exit 1 (one line) | of which the parser crashed | "
      "of which it ran out of time or memory | laserfit crashes | hangs | stray outputs | "
      "findings | slowest (s) |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
cli = os.path.join(d, "cli")
for sub in sorted(os.listdir(cli)) if os.path.isdir(cli) else []:
    p = os.path.join(cli, sub, "summary.json")
    if not os.path.exists(p):
        continue
    runs = [json.loads(l) for l in open(os.path.join(cli, sub, "runs.jsonl"))]
    for src, s in json.load(open(p))["sources"].items():
        mine = [r for r in runs if r["source"] == src]
        crashed = sum("crashed (signal" in r["reason"] for r in mine)
        limited = sum(("took longer" in r["reason"]) or ("memory" in r["reason"]) for r in mine)
        print(f"| {src} | {s['runs']} | {s['exit0']} | {s['exit1']} | {crashed} | {limited} | "
              f"{s['crashes']} | {s['hangs']} | {s['stray_outputs']} | {s['findings']} | "
              f"{s['max_seconds']:.1f} |")
