#!/usr/bin/env bash
# hullpose-calibrate on the real Utrecht floor-board videos (../shared/data/real/utrecht-4cam/
# cam<N>/checkerboard.avi: the 8x6-corner, 115 mm board lying on the floor, seen by all four
# cameras), compared with the shipped config.xml calibration (hullpose-import rig). No detector
# finds this board (a few pixels a square, edge-on, blurred; and symmetric, so its order is
# unknown to a detector), so its corners are marked by hand: utrecht-floor-marks.yaml, on the
# first frame (the board lies still: every instant is the same floor view).
#   1. extrinsics with the given intrinsics (--intrinsics: the imported rig's K and distortion);
#   2. intrinsics too: tried, and refused with the reason when the views do not allow it.
# usage: calibrate-utrecht.sh BUILD
set -euo pipefail
build=$(cd "${1:-build}" && pwd)
root=$(cd "$(dirname "$0")/../.." && pwd)
data=$(cd "$root/../shared/data/real/utrecht-4cam" && pwd)
work=${HULLPOSE_UTRECHT_DIR:-$build/utrecht-calibration}
rm -rf "$work"; mkdir -p "$work"
say() { echo "hullpose utrecht calibration: $*" >&2; }
"$build/tools/import/hullpose-import" rig --opencv "$data/cam{N}/config.xml" --size 644x486 --units mm --up -z \
  --floor 0 --rig-id utrecht --out "$work/shipped.yaml" >&2
configs=()
for id in 1 2 3 4; do
  cat > "$work/node$id.yaml" <<YAML
%YAML:1.0
camera_id: $id
rig_file: "$work/shipped.yaml"
source: { type: file, path: "$data/cam$id/checkerboard.avi", fps: 50 }
bgs: { method: threshold, learn_frames: 1 }
YAML
  configs+=(--node-config "$work/node$id.yaml")
done
common=("${configs[@]}" --frames 1 --board 8x6 --square-mm 115 --corners "$root/tools/demo/utrecht-floor-marks.yaml"
  --floor-view live00000 --rig-id utrecht --quiet)
say "1. extrinsics with the shipped intrinsics"
"$build/tools/calibrate/hullpose-calibrate" "${common[@]}" --intrinsics "$work/shipped.yaml" \
  --compare "$work/shipped.yaml" --out "$work/extrinsics.yaml"
say "2. intrinsics too, from the same views"
if "$build/tools/calibrate/hullpose-calibrate" "${common[@]}" --min-views 3 --compare "$work/shipped.yaml" \
     --out "$work/full.yaml"; then
  say "intrinsics estimated"
else
  say "intrinsics not estimated: the views do not allow it (message above)"
fi
