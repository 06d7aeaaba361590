#!/usr/bin/env bash
# make fuzz: runs every libFuzzer target built in BUILD (listed in BUILD/fuzz/targets.txt)
# for SECONDS each, with its seed corpus; fails if any target finds a crash.
set -euo pipefail
build=${1:-build-fuzz}
seconds=${2:-60}
status=0
while read -r exe; do
  [[ -n "$exe" ]] || continue
  name=$(basename "$exe")
  corpus="$build/fuzz/corpus/$name"
  mkdir -p "$corpus"
  "$exe"_seeds "$corpus"
  echo "fuzz: $name for ${seconds}s" >&2
  "$exe" -max_total_time="$seconds" -seed=1 -artifact_prefix="$build/fuzz/$name-" "$corpus" || status=1
done < "$build/fuzz/targets.txt"
exit $status
