#!/usr/bin/env bash
# make bench peer: trigger -> skeleton latency of the whole rig as processes over real LCM on
# this machine (tools/demo/rig-loopback.sh): the trigger master at 30 Hz, 8 hullpose-camera-node
# processes and hullpose-fusion-host on hullpose-synth's 8-camera 800x600 'walk'. The nodes
# replay the rendered masks as simulated sensors on the trigger wire (one frame per edge:
# threshold, encode, publish; no background subtraction, which 8 nodes at 30 Hz cannot share 2
# cores with the host for). The masks are decoded into memory at start and looped (trigger k
# shows frame k modulo 100): decoding a PNG costs a node more than the rest of its work, and a
# real sensor has no such cost. Prints JSON lines with median_ms = p50 and p99_ms beside it.
set -euo pipefail
root=$(cd "$(dirname "$0")/../../.." && pwd)
build=${HULLPOSE_BUILD:-$root/build}
frames=${HULLPOSE_RIG_BENCH_FRAMES:-300}
work=$(mktemp -d /tmp/hullpose-rigbench.XXXXXX)
trap 'rm -rf "$work"' EXIT
"$build/tools/synth/hullpose-synth" --motion walk --frames 100 --fps 30 --out "$work/data" --seed 1 > /dev/null
cp "$work/data/rig.yaml" "$work/rig.yaml"
SOURCE_EXTRA="preload: true, loop: true" "$root/tools/demo/node-configs.sh" "$work" 8 "$work/data/rig.yaml" "{url}" "{wire}" masks:mask
"$root/tools/demo/rig-loopback.sh" "$build" "$work" "$frames" 30 8 "$build/camera_node/app/hullpose-camera-node --config $work/node{cam}.yaml" \
  "$build/fusion_host/app/hullpose-fusion-host --rig {rig} --min-cameras 6"
/usr/bin/python3 - "$work/skeletons.csv" "$work/summary.json" "$frames" <<'PY'
import csv, json, math, sys
# Steady state: the first WARM triggers are left out of the percentiles and reported on their
# own (start_max_ms): a node labels edges only once it has paired three announcements with its
# edges (the clock offset), so the first two or three triggers wait up to ~100 ms for that.
WARM = 10
rows = list(csv.DictReader(open(sys.argv[1])))
s = json.load(open(sys.argv[2]))
frames = int(sys.argv[3])
def pct(v, q): return v[min(len(v) - 1, max(0, math.ceil(q * len(v)) - 1))]
common = {"frames": frames, "skeletons": s["skeletons"], "missing_sequences": s["missing_sequences"],
          "cameras": 8, "rate_hz": 30, "warm_up_triggers": WARM,
          "nodes": "hullpose-camera-node replaying hullpose-synth masks (800x600, preloaded, threshold)",
          "pipeline": "hullpose-fusion-host: carve, clean-up, thin, tree, fit"}
for stage in ("node_done", "received", "fused", "published"):
    ms = lambda r: int(r[f"{stage}_us"]) / 1000
    v = sorted(ms(r) for r in rows if int(r["trigger_seq"]) >= WARM and int(r[f"{stage}_us"]) > 0)
    start = [ms(r) for r in rows if int(r["trigger_seq"]) < WARM and int(r[f"{stage}_us"]) > 0]
    if not v: continue
    print(json.dumps({"name": f"rig_trigger_to_{stage}_8cam_30hz", "median_ms": round(pct(v, 0.5), 3),
                      "p99_ms": round(pct(v, 0.99), 3), "max_ms": round(v[-1], 3), "n": len(v),
                      "start_max_ms": round(max(start), 3) if start else None, **common}))
PY
