#!/usr/bin/python3
"""Adds peer_median_ms and speedup to every benchmark line that names a peer."""
import json
import sys

lines = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
by_name = {l["name"]: l for l in lines if "median_ms" in l}
for line in lines:
    peer = by_name.get(line.get("peer", ""))
    if peer and line.get("median_ms"):
        line["peer_median_ms"] = peer["median_ms"]
        line["speedup"] = round(peer["median_ms"] / line["median_ms"], 2)
    print(json.dumps(line))
