#!/usr/bin/env bash
# make bench peer: trigger -> skeleton published latency of the whole rig as processes over real
# LCM on this machine (8 camera nodes at 30 Hz, tools/demo/rig-loopback.sh). Prints JSON lines:
# median_ms is the p50; p99_ms beside it. Nodes and pipeline: see "nodes"/"pipeline" fields.
set -euo pipefail
root=$(cd "$(dirname "$0")/../../.." && pwd)
build=${HULLPOSE_BUILD:-$root/build}
frames=${HULLPOSE_RIG_BENCH_FRAMES:-300}
work=$(mktemp -d /tmp/hullpose-rigbench.XXXXXX)
trap 'rm -rf "$work"' EXIT
"$build/tests/rig/rig_write_test_rig" "$work/rig.yaml" 8 320 240 rigA
# Until camera_node/app and the carve->thin->fit pipeline are wired in: the stand-in node (real
# trigger stage + codec, synthetic masks) and the fusion service with the sequence-check pipeline.
"$root/tools/demo/rig-loopback.sh" "$build" "$work" "$frames" 30 8 \
  "$build/tests/rig/rig_stand_in_camera_node --rig {rig} --camera-id {cam} --edges wire:{wire} --lcm-url {url} --duration-s $(( frames / 30 + 10 ))" \
  "$build/tests/rig/rig_stub_fusion_host --rig {rig} --min-cameras 5"
/usr/bin/python3 - "$work/summary.json" "$frames" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
lat = s["latency_ms"]
common = {"frames": int(sys.argv[2]), "skeletons": s["skeletons"], "valid": s["valid"], "cameras": 8, "rate_hz": 30,
          "nodes": "stand-in (real trigger stage, synthetic masks)", "pipeline": "sequence-check stand-in"}
for stage in ("received", "published"):
    l = lat[stage]
    print(json.dumps({"name": f"rig_trigger_to_{stage}_8cam_30hz", "median_ms": l["p50"], "p99_ms": l["p99"], "max_ms": l["max"], **common}))
PY
