#!/usr/bin/env bash
# Runs a whole rig on this machine as separate processes over real LCM (loopback multicast,
# ttl=0, a port of its own): hullpose-trigger-master on a simulated trigger wire, NUM camera
# nodes, a fusion host and hullpose-listen. Used by make demo and make bench.
#
# usage: rig-loopback.sh BUILD WORK FRAMES RATE NUM NODE_CMD HOST_CMD
#   NODE_CMD, HOST_CMD: command templates; {cam} {rig} {wire} {url} {work} are substituted.
# The master starts pulsing once all NUM nodes are connected to its wire (nodes may take a while
# to load), so no trigger is lost to start-up. Leaves in WORK: skeletons.csv, estimates.csv (frame = trigger_seq), summary.json, *.log.
# With LIVE=1 the listener prints fps and latency every second. If WORK/rig.key exists (the
# node configs name it too: node-configs.sh with RIG_KEY), every process authenticates with it.
set -euo pipefail
build=$(cd "$1" && pwd) work=$2 frames=$3 rate=$4 num=$5 node_cmd=$6 host_cmd=$7
port=${HULLPOSE_RIG_PORT:-$(( 7200 + $$ % 300 ))}
url="udpm://239.255.76.67:$port?ttl=0"
wire="$work/wire.sock"
rig="$work/rig.yaml"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; }
trap cleanup EXIT
fill() { local s=$1; s=${s//\{rig\}/$rig}; s=${s//\{wire\}/$wire}; s=${s//\{url\}/$url}; s=${s//\{work\}/$work}; echo "${s//\{cam\}/$2}"; }
wait_for() {  # wait_for SECONDS PATH: a process signals readiness by creating PATH
  local deadline=$(( SECONDS + $1 ))
  until [[ -e $2 ]]; do (( SECONDS < deadline )) || { echo "rig: $2 did not appear; logs in $work" >&2; exit 1; }; sleep 0.05; done
}
[[ -f $rig ]] || { echo "rig: $rig missing (the caller writes the rig file)" >&2; exit 2; }
rm -f "$work"/*.ready "$wire"
for f in "$work"/node*.yaml; do  # node config files may carry the templates too
  [[ -e $f ]] && sed -i "s|{url}|$url|g; s|{wire}|$wire|g" "$f"
done
duration=$(( frames / rate + 90 ))  # nodes may take a while to load before the master starts
live=(); [[ ${LIVE:-0} == 1 ]] && live=(--live)
key=(); [[ -f $work/rig.key ]] && key=(--rig-key "$work/rig.key")

"$build/tools/listen/hullpose-listen" --lcm-url "$url" --format csv --output "$work/skeletons.csv" --estimates "$work/estimates.csv" \
  --summary "$work/summary.json" --count "$frames" --duration-s "$duration" --ready-file "$work/listen.ready" "${live[@]}" "${key[@]}" \
  2> >(if [[ ${LIVE:-0} == 1 ]]; then tee "$work/listen.log" >&2; else cat > "$work/listen.log"; fi) & listener=$!; pids+=($listener)
# shellcheck disable=SC2046
$(fill "$host_cmd" -) --lcm-url "$url" "${key[@]}" --duration-s "$duration" --ready-file "$work/host.ready" 2> "$work/host.log" & host=$!; pids+=($host)
wait_for 20 "$work/listen.ready"; wait_for 20 "$work/host.ready"
"$build/firmware_sync/trigger_master/hullpose-trigger-master" --rig-id "$(sed -n 's/^rig_id: *//p' "$rig" | tr -d '"')" \
  --rate "$rate" --line "wire:$wire" --lcm-url "$url" "${key[@]}" --count "$frames" --wait-nodes "$num" 2> "$work/master.log" & master=$!; pids+=($master)
wait_for 10 "$wire"
for ((c = 0; c < num; c++)); do
  # shellcheck disable=SC2046
  $(fill "$node_cmd" "$c") 2> "$work/cam$c.log" & pids+=($!)
done
wait "$master" || { echo "rig: trigger master failed:" >&2; cat "$work/master.log" >&2; exit 1; }
[[ ${LIVE:-0} == 1 ]] && tail -n 1 "$work/master.log" >&2
wait "$listener" || true
kill "$host" 2>/dev/null || true; wait "$host" 2>/dev/null || true
