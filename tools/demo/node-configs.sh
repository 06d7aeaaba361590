#!/usr/bin/env bash
# Writes the hullpose-camera-node config files of a rig simulated on one machine: OUT/node<c>.yaml
# for cameras 0..NUM-1, each a simulated sensor on the trigger master's wire (one frame per edge,
# the frame of that trigger's sequence).
#
# usage: node-configs.sh OUT NUM RIG URL WIRE SOURCE
#   RIG, WIRE: absolute paths; URL: the LCM URL (rig-loopback.sh fills {url} and {wire} templates)
#   SOURCE masks:STEM   replay pre-segmented masks RIGDIR/cam<c>/STEM_%06d.png, passed through
#                       unchanged (threshold method, no clean-up): the published silhouettes are
#                       exactly the recorded ones
#          rgb          replay RIGDIR/cam<c>/rgb_%06d.png (hullpose-synth --rgb), Horprasert
#                       background subtraction learnt from RIGDIR/cam<c>/background_%06d.png, and
#                       the clean-up (opening, small blobs, pinholes; no closing). The frames are decoded into memory at start
#                       (1.4 MB each): decoding a noisy 800x600 PNG costs more than the background
#                       subtraction (~12 ms), and a real sensor has no such cost.
# RIG_KEY (environment): the rig's key file (lcm.rig_key; messages authenticated).
# RIGDIR is the folder of RIG. SOURCE_EXTRA (environment) is added to the source: mapping, e.g.
# "preload: true, loop: true" (frames decoded at start; trigger k shows frame k modulo the length). The trigger: section comes last and in block style, so a caller may
# append fields to it (e.g. echo "  clock_offset_ms: 2000" >> OUT/node5.yaml).
set -euo pipefail
[[ $# -eq 6 ]] || { echo "usage: $0 OUT NUM RIG URL WIRE SOURCE" >&2; exit 2; }
out=$1 num=$2 rig=$3 url=$4 wire=$5 source=$6
dir=$(dirname "$rig")
mkdir -p "$out"
key_field=""; [[ -n ${RIG_KEY:-} ]] && key_field=" rig_key: \"$RIG_KEY\","
for ((c = 0; c < num; c++)); do
  case $source in
    masks:*)
      stage="source: { type: file, path: \"$dir/cam$c/${source#masks:}_%06d.png\"${SOURCE_EXTRA:+, $SOURCE_EXTRA} }
bgs: { method: threshold, learn_frames: 1 }
post: { open_radius: 0, close_radius: 0, min_blob_area: 0, max_hole_area: 0 }" ;;
    rgb)
      stage="source: { type: file, path: \"$dir/cam$c/rgb_%06d.png\", preload: true${SOURCE_EXTRA:+, $SOURCE_EXTRA} }
bgs: { method: horprasert, learn_frames: 10, background: \"$dir/cam$c/background_%06d.png\" }
post: { open_radius: 1, close_radius: 0, min_blob_area: 64, max_hole_area: 64 }" ;;
    *) echo "node-configs: unknown SOURCE '$source' (masks:STEM or rgb)" >&2; exit 2 ;;
  esac
  cat > "$out/node$c.yaml" <<YAML
%YAML:1.0
camera_id: $c
rig_file: "$rig"
$stage
lcm: { url: "$url",$key_field queue_depth: 8, status_period_ms: 1000 }
trigger:
  edges: wire
  path: "$wire"
  connect_timeout_ms: 60000
YAML
done
