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
/usr/bin/python3 - "$work/summary.json" "$frames" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
lat = s["latency_ms"]
common = {"frames": int(sys.argv[2]), "skeletons": s["skeletons"], "missing_sequences": s["missing_sequences"],
          "cameras": 8, "rate_hz": 30, "nodes": "hullpose-camera-node replaying hullpose-synth masks (800x600, preloaded, threshold)",
          "pipeline": "hullpose-fusion-host: carve, clean-up, thin, tree, fit"}
for stage in ("received", "fused", "published"):
    l = lat[stage]
    print(json.dumps({"name": f"rig_trigger_to_{stage}_8cam_30hz", "median_ms": l["p50"], "p99_ms": l["p99"],
                      "max_ms": l["max"], **common}))
PY
