# Shared harness of the network-namespace rig tests (sourced, not run): a rig of real processes
# in namespaces made by deploy/netns-rig.sh, each process's log and pid kept, cleaned up on exit.
#
#   source rig_lib.sh; rig_init BUILD_DIR NAME     root check (exit 77 = skipped), $prefix, $port,
#                                                  $url, $work, $wire, $root, $netns, cleanup trap
#   spawn LOG NS CMD...                            start CMD in namespace $prefix-NS; pid in $spawned
#   wait_until SECONDS CMD...                      poll a condition (fails the test on timeout)
#   rows FILE / have_rows FILE N                   data rows of a CSV written by hullpose-listen
#   sample_start FILE PERIOD_S / sample_stop       RSS and CPU time of every spawned process
#   wait_for FILE [SECONDS] ...                    and the rest of proc_lib.sh
# Conditions are polled, never slept for: tests assert on what the processes wrote, not on time.
source "$(dirname "${BASH_SOURCE[0]}")/proc_lib.sh"

rig_init() {
  build=$(cd "$1" && pwd)
  root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
  netns="$root/deploy/netns-rig.sh"
  if [[ $(id -u) -ne 0 ]] || ! ip netns add "hpchk$$" 2>/dev/null; then
    echo "SKIP: network namespaces need root"; exit 77
  fi
  ip netns del "hpchk$$"
  prefix="${3:-hp}$(( $$ % 100000 ))"
  port=$(( 7500 + $$ % 400 ))
  url="udpm://239.255.76.67:$port?ttl=1"
  proc_init "$2"
  wire="$work/wire.sock"
  : > "$work/pids"
  sampler=""
  trap rig_cleanup EXIT
}

rig_cleanup() {
  [[ -n $sampler ]] && kill "$sampler" 2>/dev/null || true
  kill_started
  "$netns" destroy "$prefix" || true
  drop_work
}

spawn() {
  local log=$1 ns=$2; shift 2
  ip netns exec "$prefix-$ns" "$@" 2>> "$log" &
  spawned=$!; pids+=("$spawned")
  echo "$spawned" >> "$work/pids"
}

wait_until() {
  local deadline=$(( SECONDS + $1 )); shift
  until "$@"; do
    (( SECONDS < deadline )) || { echo "FAIL: timed out waiting for: $*"; tail -n 5 "$work"/*.log; exit 1; }
    sleep 0.05
  done
}

rows() { [[ -f $1 ]] && echo $(( $(wc -l < "$1") - 1 )) || echo 0; }
have_rows() { (( $(rows "$1") >= $2 )); }

# Every PERIOD_S: "t_s pid rss_kb cpu_ticks name" for each live spawned process (/proc; `ip
# netns exec` execs the command, so a spawned pid is the program's). Processes spawned later
# (restarts) are picked up from $work/pids.
sample_start() {
  local out=$1 period=$2
  ( t0=$SECONDS
    while true; do
      while read -r p; do
        rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$p/status" 2>/dev/null) || continue
        cpu=$(awk '{print $14 + $15}' "/proc/$p/stat" 2>/dev/null) || continue
        name=$(cat "/proc/$p/comm" 2>/dev/null) || continue
        [[ -n $rss ]] && echo "$(( SECONDS - t0 )) $p $rss $cpu $name"
      done < "$work/pids"
      sleep "$period"
    done >> "$out" ) &
  sampler=$!
}
sample_stop() { [[ -n $sampler ]] && kill "$sampler" 2>/dev/null; wait "$sampler" 2>/dev/null || true; sampler=""; }
