#!/usr/bin/python3
"""Compares the live rig's accuracy with the offline replay's (two hullpose-eval --json files):
issue 7 asks them to agree within 1 %. usage: compare_eval.py LIVE.json REPLAY.json"""
import json
import sys

live, replay = (json.load(open(p)) for p in sys.argv[1:3])
ok = True
for key in ("mpjpe_mm", "hands_feet_mpjpe_mm", "pck100_pct", "valid_pct"):
    a, b = live.get(key), replay.get(key)
    if a is None or b is None:
        continue
    rel = abs(a - b) / max(abs(b), 1e-9)
    ok &= rel <= 0.01
    print(f"  {key:22s} live {a:8.2f}   replay {b:8.2f}   ({rel:.2%} apart)", file=sys.stderr)
print(f"  live vs offline replay: {'within' if ok else 'NOT within'} 1 %", file=sys.stderr)
sys.exit(0 if ok else 1)
