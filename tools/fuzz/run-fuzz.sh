#!/usr/bin/env bash
# make fuzz / make fuzz-long: runs the libFuzzer targets built in BUILD (BUILD/fuzz/targets.txt:
# one "executable max_len" line per target) with their seed corpora, for SECONDS each
# (FUZZ_RUNS=N: stop at N executions, or SECONDS if sooner); fails if any target finds a crash.
# Prints one JSON line per target (executions, seconds, rate) and keeps them in
# BUILD/fuzz/results.jsonl. FUZZ_JOBS=N runs N targets at a time; FUZZ_TARGETS="fuzz_bvh fuzz_meta"
# runs only those. Corpora and crash artifacts stay in BUILD/fuzz (never in the tree).
#
# ASAN_OPTIONS (unless set): malloc_context_size=2 records two frames of each allocation's stack
# instead of 30 (the YAML readers allocate per token; only a report prints these stacks: rerun a
# crash artifact without it to see them); quarantine_size_mb=16 instead of 256 keeps a fuzzer at
# ~60 MB instead of ~450 MB, and one execution's frees are far below 16 MB, so a use after free
# within an execution is still caught. The JSON line has the CPU seconds too (user + sys):
# execs_per_cpu_s is the rate on a machine of one's own.
set -euo pipefail
build=${1:-build-fuzz}
seconds=${2:-60}
runs=${FUZZ_RUNS:-}
jobs=${FUZZ_JOBS:-1}
only=${FUZZ_TARGETS:-}
out="$build/fuzz"
export ASAN_OPTIONS=${ASAN_OPTIONS:-malloc_context_size=2:quarantine_size_mb=16}
: > "$out/results.jsonl"
one() {
  local exe=$1 max_len=$2 name corpus log limit rc=0
  name=$(basename "$exe")
  corpus="$out/corpus/$name"
  log="$out/$name.log"
  mkdir -p "$corpus"
  "$exe"_seeds "$corpus"
  limit=(-max_total_time="$seconds")
  [[ -n $runs ]] && limit+=(-runs="$runs")
  (( max_len > 0 )) && limit+=(-max_len="$max_len")
  echo "fuzz: $name (${seconds}s${runs:+ or $runs runs}, max_len ${max_len/#0/default})" >&2
  local TIMEFORMAT="%U %S" cpu
  cpu=$( { time "$exe" "${limit[@]}" -seed=1 -print_final_stats=1 -artifact_prefix="$out/$name-" \
             "$corpus" > "$log" 2>&1 || echo "rc $?" >&2; } 2>&1 )
  [[ $cpu == *"rc "* ]] && rc=1
  cpu=$(tail -n 1 <<< "$cpu")
  local done_runs done_s
  done_runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  done_s=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -n 1)
  /usr/bin/python3 -c 'import json,sys; n,s,rc,ml=int(sys.argv[2] or 0),int(sys.argv[3] or 0),int(sys.argv[4]),int(sys.argv[5]); cpu=sum(map(float,sys.argv[6].split())); print(json.dumps({"name": "fuzz/"+sys.argv[1], "executions": n, "seconds": s, "execs_per_s": round(n/max(s,1)), "cpu_s": round(cpu,1), "execs_per_cpu_s": round(n/max(cpu,1e-3)), "max_len": ml or None, "crashed": rc != 0}))' \
    "$name" "${done_runs:-0}" "${done_s:-0}" "$rc" "$max_len" "$cpu" | tee -a "$out/results.jsonl"
  if (( rc != 0 )); then tail -n 30 "$log" >&2; return 1; fi
}
status=0
pids=()
# In FUZZ_TARGETS' order when given, else in targets.txt's.
if [[ -n $only ]]; then
  list=$(for t in $only; do grep -E "/$t [0-9]+\$" "$out/targets.txt" || { echo "fuzz: no target $t" >&2; exit 2; }; done)
else
  list=$(cat "$out/targets.txt")
fi
while read -r exe max_len; do
  [[ -n "$exe" ]] || continue
  one "$exe" "${max_len:-0}" & pids+=($!)
  if (( ${#pids[@]} >= jobs )); then wait "${pids[0]}" || status=1; pids=("${pids[@]:1}"); fi
done <<< "$list"
for p in "${pids[@]}"; do wait "$p" || status=1; done
exit $status
