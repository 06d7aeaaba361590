#!/usr/bin/env bash
# make bench peer: latency hullpose-web and hullpose-stream (VMC, BVH over TCP) add beyond
# SKELETON at 30 Hz, over real LCM on loopback (tests/consumers/consumers_bench.cpp says how it
# is measured). One pass per consumer, each with only that consumer's process running, so they
# never compete with each other for the cores. Prints one JSON line per consumer: median_ms
# (= p50), p99_ms, max_ms, and what tells cost from noise: the consumer's CPU per frame, the time
# its threads waited runnable for a core, its preemptions, the load average before and after.
# Then, where the scheduler allows it (root or CAP_SYS_NICE), the same three passes again with
# every measured process under SCHED_FIFO (chrt -f 10; names end in _sched_fifo): the waits for
# a core that other work on a shared machine causes are taken out, what is left is the
# consumers' own cost. Compare the two in one run.
# usage: consumers_latency.sh   (HULLPOSE_BUILD=DIR, HULLPOSE_CONSUMERS_BENCH_FRAMES=300,
#        HULLPOSE_BENCH_RT=auto|0|1: the SCHED_FIFO passes if allowed | never | only them)
set -euo pipefail
root=$(cd "$(dirname "$0")/../../.." && pwd)
build=${HULLPOSE_BUILD:-$root/build}
frames=${HULLPOSE_CONSUMERS_BENCH_FRAMES:-300}
mode=${HULLPOSE_BENCH_RT:-auto}
work=$(mktemp -d /tmp/hullpose-consumers-bench.XXXXXX)
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; rm -rf "$work"; }
trap cleanup EXIT
port=$(( 7300 + $$ % 300 ))
url="udpm://239.255.76.73:$port?ttl=0"
vmc=$(( port + 1000 ))
wait_for() { local n=0; until [[ -s $1 ]]; do ((n++ < 400)) || { echo "consumers bench: no $1" >&2; exit 1; }; sleep 0.05; done; }
get() { /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }
bench() { "${rt[@]}" "$build/tests/consumers/consumers_bench" --lcm-url "$url" --frames "$frames" --rate 30 --name-suffix "$suffix" "$@"; }
stop() { kill "$1"; wait "$1" 2>/dev/null || true; }

passes() {  # the three consumers, one process at a time
  rm -f "$work"/*.json
  "${rt[@]}" "$build/tools/web/hullpose-web" --lcm-url "$url" --port 0 --bind 127.0.0.1 --ready-file "$work/web.json" \
    2> "$work/web.log" & web=$!; pids+=($web)
  wait_for "$work/web.json"
  bench --only web --pid "$web" --web-port "$(get "$work/web.json" port)"
  stop "$web"

  "${rt[@]}" "$build/tools/stream/hullpose-stream" --lcm-url "$url" --vmc "127.0.0.1:$vmc" --ready-file "$work/vmc.json" \
    2> "$work/vmc.log" & vmcp=$!; pids+=($vmcp)
  wait_for "$work/vmc.json"
  bench --only vmc --pid "$vmcp" --vmc-port "$vmc"
  stop "$vmcp"

  "${rt[@]}" "$build/tools/stream/hullpose-stream" --lcm-url "$url" --bvh-tcp 0 --bvh-bind 127.0.0.1 \
    --ready-file "$work/bvh.json" 2> "$work/bvh.log" & bvhp=$!; pids+=($bvhp)
  wait_for "$work/bvh.json"
  bench --only bvh_tcp --pid "$bvhp" --bvh-port "$(get "$work/bvh.json" bvh_tcp_port)"
  stop "$bvhp"
}

if [[ $mode != 1 ]]; then rt=() suffix=""; passes; fi
if [[ $mode != 0 ]]; then
  if chrt -f 10 true 2> /dev/null; then
    rt=(chrt -f 10) suffix="_sched_fifo"; passes
  elif [[ $mode == 1 ]]; then
    echo "consumers bench: SCHED_FIFO not allowed here (needs root or CAP_SYS_NICE)" >&2; exit 1
  else
    echo "consumers bench: SCHED_FIFO not allowed here: only the normal-priority passes" >&2
  fi
fi
