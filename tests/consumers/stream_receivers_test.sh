#!/usr/bin/env bash
# hullpose-stream against receivers: oscdump (liblo-tools, not written here) gets the VMC
# bundles; bvh_client.py reads the BVH lines over TCP (plain, with the hierarchy) and, from a
# second run, over TCP and UDP in the Axis Neuron framing. consumers_sim_rig publishes 30
# skeletons (every 10th invalid) over real LCM for each run.
# usage: stream_receivers_test.sh BUILD_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
source "$here/../system/proc_lib.sh"
proc_init stream
base=$(( 9200 + $$ % 500 ))
url="udpm://239.255.76.71:$base?ttl=0"
osc=$(( base + 1 )) udp=$(( base + 2 ))
port_of() { /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['bvh_tcp_port'])" "$1"; }
frames=30 valid=27

# Run A: VMC to oscdump, plain BVH over TCP.
oscdump -L "$osc" > "$work/osc.txt" 2> "$work/oscdump.log" & oscdump=$!; pids+=($oscdump)
"$build/tools/stream/hullpose-stream" --lcm-url "$url" --vmc "127.0.0.1:$osc" --bvh-tcp 0 --bvh-bind 127.0.0.1 --bvh-format plain \
  --ready-file "$work/a.json" --stats "$work/a.stats.json" 2> "$work/a.log" & stream=$!; pids+=($stream)
wait_for_data "$work/a.json"
/usr/bin/python3 "$here/bvh_client.py" tcp "$(port_of "$work/a.json")" --format plain --frames $valid --ready "$work/a.client" \
  --out "$work/a.client.json" & client=$!; pids+=($client)
wait_for_data "$work/a.client"
"$build/tests/consumers/consumers_sim_rig" --lcm-url "$url" --count $frames
wait "$client"
kill "$stream"; wait "$stream" || true
sleep 0.2  # let oscdump print the last bundle before it is stopped (not a timing assertion)
kill "$oscdump"; wait "$oscdump" 2>/dev/null || true
channels=$(/usr/bin/python3 -c "import json; print(json.load(open('$work/a.client.json'))['channels'])")

/usr/bin/python3 - "$work/osc.txt" $frames $valid <<'PY'
import sys
lines = open(sys.argv[1]).read().splitlines()
frames, valid = int(sys.argv[2]), int(sys.argv[3])
ok = [l for l in lines if " /VMC/Ext/OK " in l]
tracked = [l for l in ok if l.endswith(" 1 3 0 1")]
lost = [l for l in ok if l.endswith(" 1 3 0 0")]
bones = [l for l in lines if " /VMC/Ext/Bone/Pos sfffffff " in l]
names = {l.split('"')[1] for l in bones}
want = {"Hips", "Spine", "Chest", "UpperChest", "Neck", "Head", "LeftShoulder", "LeftUpperArm", "LeftLowerArm", "LeftHand",
        "RightShoulder", "RightUpperArm", "RightLowerArm", "RightHand", "LeftUpperLeg", "LeftLowerLeg", "LeftFoot",
        "RightUpperLeg", "RightLowerLeg"}
print(f"oscdump: {len(ok)} bundles ({len(tracked)} tracked, {len(lost)} lost), {len(bones)} bone messages, {len(names)} bone names")
assert len(ok) == frames, f"FAIL: {len(ok)} /VMC/Ext/OK for {frames} skeletons"
assert len(tracked) == valid and len(lost) == frames - valid, "FAIL: tracking status does not follow validity"
assert len(bones) == valid * len(want) and names == want, f"FAIL: bones {sorted(names ^ want)}"
hips = [float(v) for v in next(l for l in bones if '"Hips"' in l).split('"Hips"')[1].split()]
assert 0.5 < hips[1] < 1.5 and abs(sum(q * q for q in hips[3:]) - 1) < 1e-3, f"FAIL: Hips {hips}"
PY

# Run B: Axis Neuron framing over TCP and UDP.
"$build/tools/stream/hullpose-stream" --lcm-url "$url" --bvh-tcp 0 --bvh-bind 127.0.0.1 --bvh-udp "127.0.0.1:$udp" --bvh-format axis \
  --ready-file "$work/b.json" --stats "$work/b.stats.json" 2> "$work/b.log" & stream=$!; pids+=($stream)
wait_for_data "$work/b.json"
/usr/bin/python3 "$here/bvh_client.py" tcp "$(port_of "$work/b.json")" --format axis --frames $valid --channels "$channels" \
  --ready "$work/b.tcp" & tcp=$!; pids+=($tcp)
/usr/bin/python3 "$here/bvh_client.py" udp "$udp" --format axis --frames $valid --channels "$channels" --ready "$work/b.udp" & udpc=$!; pids+=($udpc)
wait_for_data "$work/b.tcp"; wait_for_data "$work/b.udp"
"$build/tests/consumers/consumers_sim_rig" --lcm-url "$url" --count $frames
wait "$tcp"; wait "$udpc"
kill "$stream"; wait "$stream" || true
cat "$work/a.stats.json" "$work/b.stats.json"
grep -q '"dropped":0' "$work/a.stats.json" || { echo "FAIL: a fast client lost lines"; exit 1; }
echo PASS
