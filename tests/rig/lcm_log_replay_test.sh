#!/usr/bin/env bash
# Recording and replay with LCM's own tools: a small rig (trigger master, 3 camera nodes
# replaying sequence-coded masks) runs over loopback multicast while lcm-logger records it; the log then replays through
# lcm-logplayer into a fusion host on another LCM URL. Every trigger sequence in the log must come
# out as exactly one skeleton, valid wherever the log holds all three silhouettes.
# usage: lcm_log_replay_test.sh BUILD_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
source "$(dirname "$0")/../system/proc_lib.sh"
proc_init logreplay
port_a=$(( 8000 + $$ % 400 )) port_b=$(( 8400 + $$ % 400 ))
url_a="udpm://239.255.76.68:$port_a?ttl=0" url_b="udpm://239.255.76.68:$port_b?ttl=0"

"$build/tests/rig/rig_write_test_rig" "$work/rig.yaml" 3 96 72 rigA 90
"$(dirname "$0")/../../tools/demo/node-configs.sh" "$work" 3 "$work/rig.yaml" "$url_a" "$work/wire.sock" masks:seq
lcm-logger --lcm-url="$url_a" -f "$work/rig.lcmlog" 2> "$work/logger.log" & logger=$!; pids+=($logger)
"$build/firmware_sync/trigger_master/hullpose-trigger-master" --rig-id rigA --rate 30 --line "wire:$work/wire.sock" \
  --lcm-url "$url_a" --count 90 --wait-nodes 3 2> "$work/master.log" & master=$!; pids+=($master)
wait_for "$work/wire.sock"
for c in 0 1 2; do
  "$build/camera_node/app/hullpose-camera-node" --config "$work/node$c.yaml" 2> "$work/cam$c.log" & pids+=($!)
done
wait "$master"
sleep 0.3  # let the last silhouettes reach the logger (not a timing assertion)
kill -INT "$logger"; wait "$logger" || true

# Sequences announced in the log: the replay must give one skeleton for each.
expected=$(/usr/bin/python3 "$(dirname "$0")/lcm_log_summary.py" "$work/rig.lcmlog" --count-triggers)
# A generous deadline: during start-up the nodes synchronise one after the other, so the views
# of the first frames lie far apart in the log (the live host fused those partially).
"$build/tests/rig/rig_stub_fusion_host" --rig "$work/rig.yaml" --lcm-url "$url_b" --min-cameras 2 --deadline-ms 300 --duration-s 20 \
  --ready-file "$work/host.ready" 2> "$work/host.log" & host=$!; pids+=($host)
"$build/tools/listen/hullpose-listen" --lcm-url "$url_b" --format jsonl --output "$work/replayed.jsonl" --duration-s 20 --count "$expected" \
  --ready-file "$work/listen.ready" 2> "$work/listen.log" & listener=$!; pids+=($listener)
wait_for "$work/host.ready"; wait_for "$work/listen.ready"
lcm-logplayer --lcm-url="$url_b" --speed=2 "$work/rig.lcmlog"
wait "$listener" || true  # exits after $expected skeletons (or after 20 s)
kill -INT "$host"; wait "$host" || true
/usr/bin/python3 "$(dirname "$0")/lcm_log_summary.py" "$work/rig.lcmlog" --check "$work/replayed.jsonl"

