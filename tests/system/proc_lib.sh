# Shared preamble of the tests that run real processes (sourced, not run): one work dir, the
# pids of what the test started, and one clean-up on exit. rig_lib.sh (network namespaces)
# builds on it.
#
#   source proc_lib.sh; proc_init NAME      $work = /tmp/hullpose-NAME.XXXXXX, pids=(), the trap
#   some_program ... & pids+=($!)           killed (and waited for) on exit
#   wait_for FILE [SECONDS=20]              poll until FILE exists (a socket, a ready file)
#   wait_for_data FILE [SECONDS=20]         poll until FILE is not empty
# KEEP_WORK=1 keeps the work dir and prints where it is. Conditions are polled, never slept for.
set -euo pipefail

proc_init() {
  work=$(mktemp -d "/tmp/hullpose-$1.XXXXXX")
  pids=()
  trap proc_cleanup EXIT
}

kill_started() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
}

drop_work() {
  if [[ ${KEEP_WORK:-0} == 1 ]]; then echo "work dir: $work"; else rm -rf "$work"; fi
}

proc_cleanup() {
  kill_started
  drop_work
}

# wait_file TEST FILE SECONDS: poll `test TEST FILE` every 50 ms.
wait_file() {
  local n=0 tries=$(( ${3:-20} * 20 ))
  until test "$1" "$2"; do
    ((n++ < tries)) || { echo "FAIL: no $2"; exit 1; }
    sleep 0.05
  done
}
wait_for() { wait_file -e "$1" "${2:-20}"; }
wait_for_data() { wait_file -s "$1" "${2:-20}"; }
