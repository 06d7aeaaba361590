#!/usr/bin/env bash
# make bench peer: latency hullpose-web and hullpose-stream (VMC, BVH over TCP) add beyond
# SKELETON at 30 Hz, over real LCM on loopback (tests/consumers/consumers_bench.cpp says how it
# is measured). Prints one JSON line per consumer (median_ms = p50, p99_ms).
set -euo pipefail
root=$(cd "$(dirname "$0")/../../.." && pwd)
build=${HULLPOSE_BUILD:-$root/build}
frames=${HULLPOSE_CONSUMERS_BENCH_FRAMES:-300}
work=$(mktemp -d /tmp/hullpose-consumers-bench.XXXXXX)
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; rm -rf "$work"; }
trap cleanup EXIT
port=$(( 7300 + $$ % 300 ))
url="udpm://239.255.76.73:$port?ttl=0"
vmc=$(( port + 1000 ))
wait_for() { local n=0; until [[ -s $1 ]]; do ((n++ < 400)) || { echo "consumers bench: no $1" >&2; exit 1; }; sleep 0.05; done; }
"$build/tools/web/hullpose-web" --lcm-url "$url" --port 0 --bind 127.0.0.1 --ready-file "$work/web.json" 2> "$work/web.log" & pids+=($!)
"$build/tools/stream/hullpose-stream" --lcm-url "$url" --vmc "127.0.0.1:$vmc" --bvh-tcp 0 --bvh-bind 127.0.0.1 \
  --ready-file "$work/stream.json" 2> "$work/stream.log" & pids+=($!)
wait_for "$work/web.json"; wait_for "$work/stream.json"
get() { /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }
"$build/tests/consumers/consumers_bench" --lcm-url "$url" --web-port "$(get "$work/web.json" port)" --vmc-port "$vmc" \
  --bvh-port "$(get "$work/stream.json" bvh_tcp_port)" --frames "$frames" --rate 30
