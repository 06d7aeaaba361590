#!/usr/bin/env bash
# make demo: the distributed rig on this machine. The trigger master, 8 hullpose-camera-node
# processes, the fusion host and a listener run as separate processes over real LCM (loopback
# multicast, ttl=0); the listener shows live fps and latency; at the end hullpose-eval scores the
# skeletons against the ground truth and writes the HTML report. Under 2 minutes after the build.
#
#   data         hullpose-synth renders the built-in 'walk' for the thesis' 8-camera 800x600 rig:
#                RGB frames (soft shadows, illumination drift, sensor noise) + empty-room frames
#   camera nodes hullpose-camera-node, one per camera, each a simulated sensor on the trigger
#                master's wire: it exposes one frame per trigger edge (the frame of that trigger's
#                sequence, replayed from the RGB files), subtracts the background (Horprasert,
#                learnt from the empty-room frames), cleans the mask up and publishes it stamped
#                with the master's sequence and utime (tools/demo/node-configs.sh writes the configs)
#   fusion host  hullpose-fusion-host: assembly per trigger -> carve -> clean-up -> thin -> pose
#                tree -> fit -> SKELETON
#   listener     hullpose-listen: live fps and latency, skeletons to CSV
#   live view    hullpose-web: the URL is printed; open it to watch the rig (tools/web/README.md)
#   key          hullpose-rig-key makes the rig's key; every process signs and checks every message
# The rate: 8 nodes subtracting 800x600 backgrounds and a fusion host share this machine's cores
# (a real rig has a board per camera), so the demo triggers at HULLPOSE_DEMO_RATE (default 10 Hz;
# measured: 15 Hz keeps every view, at 30 Hz a few views miss the host's deadline while other
# work shares the machine) and plays the 30 fps motion slowed down to it; every trigger is fused or accounted for. The
# host waits up to 90 % of a trigger period for a frame's views (the default, 33 ms, is for 30 Hz).
# HULLPOSE_DEMO_FRAMES (default 90: rendering 8 RGB views per frame takes most of the demo's time).
# HULLPOSE_DEMO_HOST_ARGS: more hullpose-fusion-host options (e.g. "--tolerance 1", "--backend cuda").
set -euo pipefail
build=$(cd "${1:-build}" && pwd)
root=$(cd "$(dirname "$0")/../.." && pwd)
work=${HULLPOSE_DEMO_DIR:-$build/demo}
frames=${HULLPOSE_DEMO_FRAMES:-90} rate=${HULLPOSE_DEMO_RATE:-10} num=8
rm -rf "$work"; mkdir -p "$work"
say() { echo "hullpose demo: $*" >&2; }
start=$SECONDS
synth="$build/tools/synth/hullpose-synth"
node="$build/camera_node/app/hullpose-camera-node"
host="$build/fusion_host/app/hullpose-fusion-host"
eval_tool="$build/tools/eval/hullpose-eval"

say "rendering $frames frames of 'walk' (RGB + empty-room backgrounds) for $num cameras (hullpose-synth --rgb)"
"$synth" --motion walk --frames "$frames" --fps 30 --out "$work/data" --seed 1 --rgb --backgrounds 10 >&2
cp "$work/data/rig.yaml" "$work/rig.yaml"
# The rig's key: every message of the demo is authenticated (docs/messages.md).
"$build/tools/rig_key/hullpose-rig-key" --output "$work/rig.key" >&2
RIG_KEY="$work/rig.key" "$root/tools/demo/node-configs.sh" "$work" "$num" "$work/data/rig.yaml" "{url}" "{wire}" rgb
say "camera nodes: hullpose-camera-node x $num (RGB replay, one frame per trigger edge, Horprasert background subtraction)"
say "fusion host: hullpose-fusion-host (carve -> clean-up -> thin -> pose tree -> fit)"
# The live view: hullpose-web on the rig's LCM URL (rig-loopback.sh takes its port from
# HULLPOSE_RIG_PORT), on HULLPOSE_DEMO_WEB_PORT (default 8080; any free port if that is taken).
export HULLPOSE_RIG_PORT=${HULLPOSE_RIG_PORT:-$(( 7200 + $$ % 300 ))}
web_url="udpm://239.255.76.67:$HULLPOSE_RIG_PORT?ttl=0"
start_web() {
  rm -f "$work/web.json"
  "$build/tools/web/hullpose-web" --rig "$work/rig.yaml" --lcm-url "$web_url" --rig-key "$work/rig.key" --port "$1" --ready-file "$work/web.json" \
    2> "$work/web.log" & web_pid=$!
  for _ in $(seq 100); do [[ -s $work/web.json ]] && return 0; kill -0 "$web_pid" 2>/dev/null || return 1; sleep 0.05; done
  return 1
}
start_web "${HULLPOSE_DEMO_WEB_PORT:-8080}" || start_web 0 || { cat "$work/web.log" >&2; exit 1; }
trap 'kill "$web_pid" 2>/dev/null || true' EXIT
say "live view: open $(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['url'])" "$work/web.json") in a browser (hullpose-web)"
say "starting the rig: trigger master at $rate Hz, $num camera nodes, fusion host, listener (LCM loopback, ttl=0)"
LIVE=1 "$root/tools/demo/rig-loopback.sh" "$build" "$work" "$frames" "$rate" "$num" \
  "$node --config $work/node{cam}.yaml" "$host --rig {rig} --min-cameras 6 --deadline-ms $(( 900 / rate )) ${HULLPOSE_DEMO_HOST_ARGS:-}"
/usr/bin/python3 - "$work/summary.json" "$frames" <<'PY'
import json, sys
s, frames = json.load(open(sys.argv[1])), int(sys.argv[2])
l, f = s["latency_ms"]["published"], s["latency_ms"]["fused"]
print(f"hullpose demo: {s['skeletons']} skeletons for {frames} triggers, {s['valid']} valid, {s['missing_sequences']} sequences missing, "
      f"reasons {s['reasons']}; trigger -> fused p50 {f['p50']:.1f} ms p99 {f['p99']:.1f} ms; "
      f"trigger -> published p50 {l['p50']:.1f} ms p99 {l['p99']:.1f} ms", file=sys.stderr)
PY
say "accuracy of the live rig against the ground truth (hullpose-eval):"
"$eval_tool" --gt "$work/data" --est "$work/estimates.csv" --report "$work/report"
say "HTML report: $work/report/report.html"
say "for reference, the same frames offline on the exact rendered masks (hullpose-fusion-host --replay, no background subtraction):"
"$host" --replay "$work/data" --out "$work/replay.csv" > /dev/null
"$eval_tool" --gt "$work/data" --est "$work/replay.csv" --json > "$work/replay_eval.json"
"$eval_tool" --gt "$work/data" --est "$work/estimates.csv" --json > "$work/live_eval.json"
/usr/bin/python3 - "$work/live_eval.json" "$work/replay_eval.json" <<'PY'
import json, sys
live, replay = (json.load(open(p)) for p in sys.argv[1:3])
for key in ("mpjpe_mm", "hands_feet_mpjpe_mm", "pck100_pct", "valid_pct"):
    if key in live and key in replay:
        print(f"  {key:22s} live (background subtraction) {live[key]:8.2f}   offline (exact masks) {replay[key]:8.2f}", file=sys.stderr)
PY
"$build/tools/export/hullpose-export" --in "$work/estimates.csv" --fps "$rate" --bvh "$work/take.bvh" --trc "$work/take.trc" \
  --c3d "$work/take.c3d" 2> "$work/export.log"
say "the take exported (hullpose-export): $work/take.bvh (Blender, game engines), take.trc (OpenSim), take.c3d"
say "watch it again: $build/tools/web/hullpose-web --rig $work/rig.yaml --play $work/estimates.csv --fps $rate"
say "done in $(( SECONDS - start )) s; skeletons in $work/skeletons.csv, logs in $work"
