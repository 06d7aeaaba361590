#!/usr/bin/env bash
# The trigger master restarts mid-run (new epoch, sequence numbers from 0 again): the camera
# nodes resynchronise on the new epoch (and reconnect to the trigger wire), the fusion host
# follows the restarted sequence, and the frames of both runs are fused from matching views.
# Real processes over loopback LCM. usage: master_restart_test.sh BUILD_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
source "$(dirname "$0")/../system/proc_lib.sh"
proc_init restart
port=$(( 8800 + $$ % 300 ))
url="udpm://239.255.76.69:$port?ttl=0"
master() {
  "$build/firmware_sync/trigger_master/hullpose-trigger-master" --rig-id rigA --rate 30 --line "wire:$work/wire.sock" \
    --lcm-url "$url" --count 60 2>> "$work/master.log"
}

"$build/tests/rig/rig_write_test_rig" "$work/rig.yaml" 3 96 72 rigA 60
"$(dirname "$0")/../../tools/demo/node-configs.sh" "$work" 3 "$work/rig.yaml" "$url" "$work/wire.sock" masks:seq
"$build/tests/rig/rig_stub_fusion_host" --rig "$work/rig.yaml" --lcm-url "$url" --min-cameras 2 --duration-s 30 \
  --ready-file "$work/host.ready" 2> "$work/host.log" & host=$!; pids+=($host)
"$build/tools/listen/hullpose-listen" --lcm-url "$url" --format csv --output "$work/skeletons.csv" --count 120 --duration-s 30 \
  --ready-file "$work/listen.ready" 2> "$work/listen.log" & listener=$!; pids+=($listener)
wait_for "$work/host.ready"; wait_for "$work/listen.ready"
master & first=$!; pids+=($first)
wait_for "$work/wire.sock"
for c in 0 1 2; do
  "$build/camera_node/app/hullpose-camera-node" --config "$work/node$c.yaml" 2> "$work/cam$c.log" & pids+=($!)
done
wait "$first"
master  # the restart: a new process, a new epoch, sequences from 0
wait "$listener" || true
kill -INT "$host" 2>/dev/null || true; wait "$host" || true

grep -h "stopped after\|rig-stub" "$work"/*.log || true
/usr/bin/python3 - "$work/skeletons.csv" "$work/cam0.log" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
seqs = [int(r["trigger_seq"]) for r in rows]
cut = next(i for i in range(1, len(seqs)) if seqs[i] < seqs[i - 1])  # where the sequence restarted
first, second = rows[:cut], rows[cut:]
print(f"master_restart_test: {len(first)} skeletons before the restart, {len(second)} after")
fail = []
mixed = [r for r in rows if r["reason"] == "5"]
if mixed: fail.append(f"{len(mixed)} frames mixed sequences")
if [int(r["trigger_seq"]) for r in second] != list(range(len(second))) or len(second) < 50:
    fail.append("the restarted run was not followed from sequence 0")
valid2 = [r for r in second if r["valid"] == "1" and int(r["trigger_seq"]) >= 10]
if len(valid2) < 0.9 * (len(second) - 10): fail.append(f"only {len(valid2)} valid frames after resynchronising")
if "resynchronising" not in open(sys.argv[2]).read(): fail.append("camera 0 did not resynchronise on the new epoch")
if fail: print("FAIL: " + "; ".join(fail)); sys.exit(1)
print("PASS")
PY
