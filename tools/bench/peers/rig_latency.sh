#!/usr/bin/env bash
# make bench peer: trigger -> skeleton latency of the whole rig as processes over real LCM on
# this machine (8 camera nodes at 30 Hz, tools/demo/rig-loopback.sh). Prints JSON lines with
# median_ms = p50 and p99_ms beside it; "nodes" and "pipeline" say what ran.
set -euo pipefail
root=$(cd "$(dirname "$0")/../../.." && pwd)
build=${HULLPOSE_BUILD:-$root/build}
frames=${HULLPOSE_RIG_BENCH_FRAMES:-300}
work=$(mktemp -d /tmp/hullpose-rigbench.XXXXXX)
trap 'rm -rf "$work"' EXIT
node="$build/tests/rig/rig_stand_in_camera_node --rig {rig} --camera-id {cam} --edges wire:{wire} --lcm-url {url} --duration-s $(( frames / 30 + 60 ))"
if [[ -x $build/tools/synth/hullpose-synth && -x $build/fusion_host/service/hullpose-fusion-live ]]; then
  # Real silhouettes (hullpose-synth, the thesis' 8-camera 800x600 rig) through the real carve ->
  # clean-up -> thin. Until camera_node/app takes a trigger input, the nodes are the stand-in
  # (real trigger stage, replaying the rendered masks); the pose stage has not landed yet.
  "$build/tools/synth/hullpose-synth" --motion walk --frames "$frames" --fps 30 --out "$work/data" --seed 1 > /dev/null
  cp "$work/data/rig.yaml" "$work/rig.yaml"
  node="$node --masks $work/data"
  host="$build/fusion_host/service/hullpose-fusion-live --rig {rig} --min-cameras 6"
  nodes="stand-in, replaying hullpose-synth masks (800x600)" pipeline="carve+clean-up+thin at 64 voxels (pose stage pending)"
else
  "$build/tests/rig/rig_write_test_rig" "$work/rig.yaml" 8 320 240 rigA
  host="$build/tests/rig/rig_stub_fusion_host --rig {rig} --min-cameras 5"
  nodes="stand-in, synthetic masks" pipeline="sequence-check stand-in"
fi
"$root/tools/demo/rig-loopback.sh" "$build" "$work" "$frames" 30 8 "$node" "$host"
/usr/bin/python3 - "$work/summary.json" "$frames" "$nodes" "$pipeline" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
lat = s["latency_ms"]
common = {"frames": int(sys.argv[2]), "skeletons": s["skeletons"], "missing_sequences": s["missing_sequences"],
          "cameras": 8, "rate_hz": 30, "nodes": sys.argv[3], "pipeline": sys.argv[4]}
for stage in ("received", "fused", "published"):
    l = lat[stage]
    print(json.dumps({"name": f"rig_trigger_to_{stage}_8cam_30hz", "median_ms": l["p50"], "p99_ms": l["p99"],
                      "max_ms": l["max"], **common}))
PY
