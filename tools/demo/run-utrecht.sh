#!/usr/bin/env bash
# The real Utrecht capture (../shared/data/real/utrecht-4cam, SOURCES.md there) live: its 4 colour
# videos played by 4 hullpose-camera-node processes (file source, one frame per trigger edge,
# background learnt from each camera's empty-room video, METHOD background subtraction), the
# trigger master, the fusion host and a listener, all over real LCM on loopback (rig-loopback.sh,
# as make demo). Then the same node configs once more in-process (hullpose-import recording) to
# keep every frame's colour image and silhouette, and hullpose-eval scores the live skeletons
# against those silhouettes (no ground truth) with pictures of the skeleton over each camera.
#
# usage: run-utrecht.sh BUILD [horprasert|codebook|sobs]
#   HULLPOSE_UTRECHT_FRAMES (default 300 of the ~426), HULLPOSE_UTRECHT_RATE (default 6 Hz: four
#   nodes and the host share this machine's two cores, and these rough 4-camera hulls take the
#   host ~100 ms a frame; the videos are 50 fps).
set -euo pipefail
build=$(cd "${1:-build}" && pwd) method=${2:-horprasert}
root=$(cd "$(dirname "$0")/../.." && pwd)
data=$(cd "$root/../shared/data/real/utrecht-4cam" && pwd)
work=${HULLPOSE_UTRECHT_DIR:-$build/utrecht-$method}
frames=${HULLPOSE_UTRECHT_FRAMES:-300} rate=${HULLPOSE_UTRECHT_RATE:-6}
say() { echo "hullpose utrecht: $*" >&2; }
rm -rf "$work"; mkdir -p "$work"
import="$build/tools/import/hullpose-import"
node="$build/camera_node/app/hullpose-camera-node"
host="$build/fusion_host/app/hullpose-fusion-host"

# The capture volume: 2.4 x 2.4 x 2.2 m (the thesis rig's size) around where the subject sits. The
# default, the box all four cameras see, is 8.8 x 7.3 m here (three of the cameras stand along
# one wall and see the whole room): 69 mm voxels at 128³ and large ghost volumes. A 4-camera rig
# like this one needs its capture volume stated, as any rig's setup does.
say "importing the rig from the OpenCV config.xml files (mm, the board's z axis points down into the floor)"
"$import" rig --opencv "$data/cam{N}/config.xml" --size 644x486 --units mm --up -z --floor 0 --rig-id utrecht \
  --volume-min-mm -900,-1450,0 --volume-max-mm 1500,950,2200 --out "$work/rig.yaml" >&2
configs=()
for c in 0 1 2 3; do
  id=$((c + 1))
  cat > "$work/node$c.yaml" <<YAML
%YAML:1.0
camera_id: $id
rig_file: "$work/rig.yaml"
source: { type: file, path: "$data/cam$id/video.avi", fps: 50 }
bgs: { method: $method, learn_frames: 100, background: "$data/cam$id/background.avi" }
post: { open_radius: 1, close_radius: 0, min_blob_area: 64, max_hole_area: 64 }
lcm: { url: "{url}", queue_depth: 8, status_period_ms: 1000 }
trigger:
  edges: wire
  path: "{wire}"
  connect_timeout_ms: 60000
YAML
  configs+=(--node-config "$work/node$c.yaml")
done
say "live: trigger master at $rate Hz, 4 camera nodes ($method), fusion host, listener (LCM loopback)"
LIVE=1 "$root/tools/demo/rig-loopback.sh" "$build" "$work" "$frames" "$rate" 4 \
  "$node --config $work/node{cam}.yaml" "$host --rig {rig} --min-cameras 3 --deadline-ms $(( 900 / rate ))"
/usr/bin/python3 - "$work/summary.json" "$frames" <<'PY'
import json, sys
s, frames = json.load(open(sys.argv[1])), int(sys.argv[2])
f = s["latency_ms"]["fused"]
print(f"hullpose utrecht: {s['skeletons']} skeletons for {frames} triggers, {s['valid']} valid, reasons {s['reasons']}; "
      f"trigger -> fused p50 {f['p50']:.1f} ms p99 {f['p99']:.1f} ms", file=sys.stderr)
PY
say "the same node configs in-process: every frame's colour image and silhouette (hullpose-import recording)"
"$import" recording "${configs[@]}" --out "$work/data" --fps 50 --frames "$frames" >&2
say "live skeletons against the silhouettes (hullpose-eval, no ground truth):"
"$build/tools/eval/hullpose-eval" --gt "$work/data" --est "$work/estimates.csv" --report "$work/report"
say "done: report $work/report/report.html, logs in $work"
