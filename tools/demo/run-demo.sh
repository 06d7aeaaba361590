#!/usr/bin/env bash
# make demo: the distributed rig on this machine. Trigger master, 8 camera nodes, the fusion
# host and a listener run as separate processes over real LCM (loopback multicast, ttl=0); the
# listener shows live fps and latency; at the end hullpose-eval scores the skeletons against the
# ground truth and writes the HTML report. Under 2 minutes.
#
# Each part uses the real program when it has landed, else the rig's stand-in, and says so:
#   data         hullpose-synth renders the built-in 'walk' (masks; RGB + backgrounds when the
#                camera nodes can replay them)
#   camera nodes hullpose-camera-node with a trigger input (RGB replay + real background
#                subtraction) | stand-in node: real trigger stage, replays the rendered masks
#   fusion host  hullpose-fusion-host --live | hullpose-fusion-live (carve -> clean-up -> thin;
#                pose stage pending) | fusion service with the sequence-check pipeline
set -euo pipefail
build=$(cd "${1:-build}" && pwd)
root=$(cd "$(dirname "$0")/../.." && pwd)
work=${HULLPOSE_DEMO_DIR:-$build/demo}
frames=${HULLPOSE_DEMO_FRAMES:-300} rate=30 num=8
rm -rf "$work"; mkdir -p "$work"
bin() { if [[ -x $build/$1 ]]; then echo "$build/$1"; fi; }
has_opt() { [[ -n $1 ]] && "$1" --help 2>&1 | grep -q -- "$2"; }
say() { echo "hullpose demo: $*" >&2; }
start=$SECONDS
synth=$(bin tools/synth/hullpose-synth)
node=$(bin camera_node/app/hullpose-camera-node)
host=$(bin fusion_host/app/hullpose-fusion-host)
live=$(bin fusion_host/service/hullpose-fusion-live)
eval_tool=$(bin tools/eval/hullpose-eval)
stand_in="$build/tests/rig/rig_stand_in_camera_node"
real_nodes=0; has_opt "$node" trigger && real_nodes=1

data=""
if [[ -n $synth ]]; then
  rgb=(); [[ $real_nodes == 1 ]] && rgb=(--rgb)
  say "rendering $frames frames of 'walk' for $num cameras (hullpose-synth ${rgb[*]})"
  "$synth" --motion walk --frames "$frames" --fps "$rate" --out "$work/data" --seed 1 "${rgb[@]}" >&2
  data="$work/data"
  cp "$data/rig.yaml" "$work/rig.yaml"
else
  say "hullpose-synth missing: the stand-in nodes draw sequence-coded masks instead"
  "$build/tests/rig/rig_write_test_rig" "$work/rig.yaml" "$num" 320 240 rigA
fi

node_args="--rig {rig} --camera-id {cam} --edges wire:{wire} --lcm-url {url} --duration-s $(( frames / rate + 60 ))"
if [[ $real_nodes == 1 && -n $data ]]; then
  for ((c = 0; c < num; c++)); do
    cat > "$work/node$c.yaml" <<YAML
camera_id: $c
rig_file: data/rig.yaml
source: { type: file, pattern: data/cam$c/rgb_%06d.png }
bgs: { method: sobs, learn_frames: 10, background: data/cam$c/background_%06d.png }
post: { open_radius: 1, close_radius: 2, min_blob_area: 64 }
lcm: { url: "{url}", queue_depth: 4, status_period_ms: 1000 }
trigger: { edges: "wire:{wire}" }
YAML
  done
  node_cmd="$node --config $work/node{cam}.yaml"
  say "camera nodes: hullpose-camera-node (RGB replay, background subtraction)"
elif [[ -n $data ]]; then
  node_cmd="$stand_in $node_args --masks $data"
  say "camera nodes: stand-in (real trigger stage; replays the rendered masks: no background subtraction yet)"
else
  node_cmd="$stand_in $node_args"
fi

if has_opt "$host" --live; then
  host_cmd="$host --live --rig {rig}"; say "fusion host: hullpose-fusion-host --live"
elif [[ -n $live && -n $data ]]; then
  host_cmd="$live --rig {rig} --min-cameras 6"
  say "fusion host: hullpose-fusion-live (carve -> clean-up -> thin; the pose stage has not landed: no joints yet)"
else
  host_cmd="$build/tests/rig/rig_stub_fusion_host --rig {rig} --min-cameras 5"
  say "fusion host: the fusion service with the sequence-check stand-in pipeline"
fi

say "starting the rig: trigger master at $rate Hz, $num camera nodes, fusion host, listener (LCM loopback, ttl=0)"
LIVE=1 "$root/tools/demo/rig-loopback.sh" "$build" "$work" "$frames" "$rate" "$num" "$node_cmd" "$host_cmd"
/usr/bin/python3 - "$work/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
l, f = s["latency_ms"]["published"], s["latency_ms"]["fused"]
print(f"hullpose demo: {s['skeletons']} skeletons, {s['valid']} valid, {s['missing_sequences']} sequences missing, reasons {s['reasons']}; "
      f"trigger -> fused p50 {f['p50']:.1f} ms p99 {f['p99']:.1f} ms; trigger -> published p50 {l['p50']:.1f} ms p99 {l['p99']:.1f} ms",
      file=sys.stderr)
PY
if [[ -n $eval_tool && -n $data ]] && grep -q ',1,' <(cut -d, -f1-3 "$work/estimates.csv"); then
  "$eval_tool" --gt "$data" --est "$work/estimates.csv" --report "$work/report.html"
  say "HTML report: $work/report.html"
else
  say "accuracy: not reported (needs valid skeletons from the pose stage, ground truth and hullpose-eval)"
fi
say "done in $(( SECONDS - start )) s; skeletons in $work/skeletons.csv, logs in $work"
