#!/usr/bin/env bash
# make fuzz: runs every libFuzzer target built in BUILD (listed in BUILD/fuzz/targets.txt) with
# its seed corpus, for SECONDS each (FUZZ_RUNS=N: stop at N executions, or SECONDS if sooner); fails if any target
# finds a crash. Prints one JSON line per target (executions, seconds, rate) and keeps them in
# BUILD/fuzz/results.jsonl. FUZZ_JOBS=N runs N targets at a time.
set -euo pipefail
build=${1:-build-fuzz}
seconds=${2:-60}
runs=${FUZZ_RUNS:-}
jobs=${FUZZ_JOBS:-1}
out="$build/fuzz"
: > "$out/results.jsonl"
one() {
  local exe=$1 name corpus log limit rc=0
  name=$(basename "$exe")
  corpus="$out/corpus/$name"
  log="$out/$name.log"
  mkdir -p "$corpus"
  "$exe"_seeds "$corpus"
  limit=(-max_total_time="$seconds")
  [[ -n $runs ]] && limit+=(-runs="$runs")
  echo "fuzz: $name (${seconds}s${runs:+ or $runs runs})" >&2
  "$exe" "${limit[@]}" -seed=1 -print_final_stats=1 -artifact_prefix="$out/$name-" "$corpus" > "$log" 2>&1 || rc=$?
  local done_runs done_s
  done_runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  done_s=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -n 1)
  /usr/bin/python3 -c 'import json,sys; n,s,rc=int(sys.argv[2] or 0),int(sys.argv[3] or 0),int(sys.argv[4]); print(json.dumps({"name": "fuzz/"+sys.argv[1], "executions": n, "seconds": s, "execs_per_s": round(n/max(s,1)), "crashed": rc != 0}))' \
    "$name" "${done_runs:-0}" "${done_s:-0}" "$rc" | tee -a "$out/results.jsonl"
  if (( rc != 0 )); then tail -n 30 "$log" >&2; return 1; fi
}
status=0
pids=()
while read -r exe; do
  [[ -n "$exe" ]] || continue
  one "$exe" & pids+=($!)
  if (( ${#pids[@]} >= jobs )); then wait "${pids[0]}" || status=1; pids=("${pids[@]:1}"); fi
done < "$out/targets.txt"
for p in "${pids[@]}"; do wait "$p" || status=1; done
exit $status
