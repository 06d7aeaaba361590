#!/usr/bin/env bash
# make bench: runs every benchmark executable (listed by CMake in BUILD/bench/benches.txt) and
# every peer script in tools/bench/peers/, prints JSON lines and keeps them in
# BUILD/bench/results.jsonl. HULLPOSE_BENCH_REPS (default 5) sets the repetitions.
set -euo pipefail
build=${1:-build}
root=$(cd "$(dirname "$0")/../.." && pwd)
out="$build/bench"
mkdir -p "$out"
raw="$out/raw.jsonl"
: > "$raw"
reps=${HULLPOSE_BENCH_REPS:-5}
while read -r exe; do
  [[ -n "$exe" ]] || continue
  echo "bench: $(basename "$exe")" >&2
  "$exe" --benchmark_repetitions="$reps" --benchmark_min_time=0.05 >> "$raw"
done < "$out/benches.txt"
shopt -s nullglob
for peer in "$root"/tools/bench/peers/*; do
  echo "bench: peer $(basename "$peer")" >&2
  HULLPOSE_BUILD="$build" "$peer" >> "$raw"
done
/usr/bin/python3 "$root/tools/bench/merge_peers.py" "$raw" > "$out/results.jsonl"
cat "$out/results.jsonl"
echo "bench: results in $out/results.jsonl" >&2
