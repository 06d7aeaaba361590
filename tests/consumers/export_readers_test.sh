#!/usr/bin/env bash
# hullpose-export against readers not written here.
#  1. CMU 55_01 (first 150 frames) rendered by hullpose-synth and replayed by the fusion host:
#     the estimate file -> BVH, TRC, C3D. three.js's BVHLoader (Debian libjs-three, under node)
#     does the forward kinematics: every joint of every frame of the held body model (model >= 1:
#     from ~2.3 s on, at least 50 of the 150 frames) within 1 mm of ours; the provisional frames
#     before the hold within 1 mm plus their bone-length change along the joint's chain
#     (bvh_compare.py says why); the ground truth (which keeps
#     its bone lengths) exported the same way: every joint within 1 mm. TRC and C3D follow their
#     published layouts and hold the estimate's points (check_markers.py).
#  2. An lcm-logger log of a simulated rig (every 10th frame invalid) -> BVH: the same reader
#     gives back the published joints within 1 mm; the inner one-frame gaps are interpolated,
#     the invalid last frame is flagged.
# usage: export_readers_test.sh BUILD_DIR SHARED_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
shared=$2
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d /tmp/hullpose-export.XXXXXX)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  if [[ ${KEEP_WORK:-0} == 1 ]]; then echo "work dir: $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
export_tool="$build/tools/export/hullpose-export"
gt_as_estimates() {  # ground_truth.csv -> estimate layout (frame,valid,reason,...)
  /usr/bin/python3 -c "
import csv, sys
r = list(csv.DictReader(open(sys.argv[1])))
w = csv.writer(open(sys.argv[2], 'w'))
names = [k for k in r[0] if k not in ('frame', 'utime')]
w.writerow(['frame', 'valid', 'reason'] + names)
for x in r: w.writerow([x['frame'], 1, 0] + [x[n] for n in names])" "$1" "$2"
}

# 1. CMU 55_01
"$build/tools/synth/hullpose-synth" --motion "$shared/data/mocap/55_01.bvh" --frames 150 --out "$work/d55" > /dev/null
"$build/fusion_host/app/hullpose-fusion-host" --replay "$work/d55" --out "$work/est.csv" > /dev/null
"$export_tool" --in "$work/est.csv" --bvh "$work/est.bvh" --trc "$work/est.trc" --c3d "$work/est.c3d" --gaps "$work/est.gaps.json"
node "$here/bvh_fk.js" "$work/est.bvh" > "$work/est.fk.csv"
/usr/bin/python3 "$here/bvh_compare.py" "$work/est.fk.csv" "$work/est.csv" "$work/est.gaps.json" --held 50
/usr/bin/python3 "$here/check_markers.py" "$work/est.csv" "$work/est.gaps.json" "$work/est.trc" "$work/est.c3d" --fps 30
gt_as_estimates "$work/d55/ground_truth.csv" "$work/gt.csv"
"$export_tool" --in "$work/gt.csv" --bvh "$work/gt.bvh" --gaps "$work/gt.gaps.json"
node "$here/bvh_fk.js" "$work/gt.bvh" > "$work/gt.fk.csv"
/usr/bin/python3 "$here/bvh_compare.py" "$work/gt.fk.csv" "$work/gt.csv" "$work/gt.gaps.json" --exact

# 2. lcm-logger log of a simulated rig; hullpose-listen records the same skeletons as an estimate file.
port=$(( 7900 + $$ % 300 ))
url="udpm://239.255.76.72:$port?ttl=0"
lcm-logger --lcm-url="$url" -f "$work/take.lcmlog" 2> "$work/logger.log" & logger=$!; pids+=($logger)
"$build/tools/listen/hullpose-listen" --lcm-url "$url" --format none --estimates "$work/take.csv" --count 60 --duration-s 30 \
  --ready-file "$work/listen.ready" 2> "$work/listen.log" & listen=$!; pids+=($listen)
until [[ -e $work/listen.ready ]]; do sleep 0.05; done
"$build/tests/consumers/consumers_sim_rig" --lcm-url "$url" --count 60 --rate 60
wait "$listen"
kill -INT "$logger"; wait "$logger" || true
"$export_tool" --in "$work/take.lcmlog" --bvh "$work/take.bvh" --c3d "$work/take.c3d" --trc "$work/take.trc" --gaps "$work/take.gaps.json" \
  | tee /dev/stderr
grep -q '"filled_frames":5,.*"missing_frames":1,.*"missing_ranges":\[\[59,59\]\]' "$work/take.gaps.json" \
  || { echo "FAIL: the log's 5 inner one-frame gaps should be interpolated and the last frame flagged"; exit 1; }
node "$here/bvh_fk.js" "$work/take.bvh" > "$work/take.fk.csv"
/usr/bin/python3 "$here/bvh_compare.py" "$work/take.fk.csv" "$work/take.csv" "$work/take.gaps.json" --exact
/usr/bin/python3 "$here/check_markers.py" "$work/take.csv" "$work/take.gaps.json" "$work/take.trc" "$work/take.c3d" --fps 60
echo PASS
