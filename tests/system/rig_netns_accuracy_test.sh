#!/usr/bin/env bash
# Issue 7's accuracy criterion in network namespaces: a rendered dataset (hullpose-synth, 8
# cameras) goes through the distributed rig — trigger master, 8 camera nodes and the fusion host
# (hullpose-fusion-host: carve -> thin -> tree -> fit) each in its own namespace, LCM multicast
# across a bridge — and through `hullpose-fusion-host --replay` offline. Every trigger sequence
# must come out as one skeleton, and hullpose-eval must score live and replay within 1 %. The
# live host also sends its carved hull on HULL at 2 Hz (--hull-rate; issue 16's view): recorded
# by lcm-logger beside it, every hull must be a real coarse hull of its frame, about 2 a second,
# and the skeletons must be none the worse for it.
# The nodes are the real hullpose-camera-node replaying the rendered masks as simulated sensors on
# the trigger wire (one frame per edge, the frame of that trigger's sequence), passed through
# unchanged (threshold method, no clean-up), so live and replay see the same silhouettes and must
# agree: what is tested is the distributed rig (trigger, transport, assembly), not the background
# subtraction (make demo runs that, on RGB). The host waits up to 500 ms for a frame's views (not
# the default 33): on this shared 2-core machine a node may lag a frame behind now and then, and
# a view dropped as late would change the answer; latency is make bench's business.
# usage: rig_netns_accuracy_test.sh BUILD_DIR [FRAMES=300] [RATE=30]
set -euo pipefail
source "$(dirname "$0")/rig_lib.sh"
rig_init "$1" netns-acc ha
frames=${2:-300} rate=${3:-30} num=8

"$build/tools/synth/hullpose-synth" --motion walk --frames "$frames" --fps "$rate" --out "$work/data" --seed 1 > /dev/null
"$netns" create "$prefix" "$num" > /dev/null
"$root/tools/demo/node-configs.sh" "$work" "$num" "$work/data/rig.yaml" "$url" "$work/wire.sock" masks:mask
seconds=$(( frames / rate + 60 ))
spawn "$work/host.log" fusion "$build/fusion_host/app/hullpose-fusion-host" --rig "$work/data/rig.yaml" --lcm-url "$url" \
  --min-cameras 6 --deadline-ms 500 --max-open 24 --duration-s "$seconds" --ready-file "$work/host.ready" --hull-rate 2
host=$spawned
spawn "$work/hull-logger.log" fusion lcm-logger --lcm-url="$url" -c HULL -f "$work/hull.lcmlog"
hull_logger=$spawned
spawn "$work/listen.log" fusion "$build/tools/listen/hullpose-listen" --lcm-url "$url" --output "$work/live-log.csv" --count "$frames" \
  --estimates "$work/live.csv" --summary "$work/summary.json" --duration-s "$seconds" --ready-file "$work/listen.ready"
listener=$spawned
wait_for "$work/host.ready" 60; wait_for "$work/listen.ready" 60
spawn "$work/master.log" master "$build/firmware_sync/trigger_master/hullpose-trigger-master" --rig-id "$(sed -n 's/^rig_id: *//p' "$work/data/rig.yaml" | tr -d '"')" \
  --rate "$rate" --line "wire:$work/wire.sock" --lcm-url "$url" --count "$frames" --wait-nodes "$num"
master=$spawned
cams=()
for ((c = 0; c < num; c++)); do
  spawn "$work/cam$c.log" "cam$c" "$build/camera_node/app/hullpose-camera-node" --config "$work/node$c.yaml"
  cams+=("$spawned")
done
wait "$master" || { echo "FAIL: trigger master"; cat "$work/master.log"; exit 1; }
wait "$listener" || true
# Stopped cleanly, every process prints its counters (read below).
kill "$host" "${cams[@]}" 2>/dev/null || true; wait "$host" "${cams[@]}" || true
kill -INT "$hull_logger" 2>/dev/null || true; wait "$hull_logger" || true

# The replay is given what the live host fused, frame by frame: the pose tracker carries state
# from frame to frame, so one frame fused differently would start the two down different paths.
# A view missing live (a stall of the whole 2-core machine) changes what the live host fused:
# - A frame with too few views never reached its pose stage. It is left out of the replay's
#   input and scored as lost in both. Such frames must stay under 1 %, or under 5 % when every
#   view missing live is a counted drop: a node that fell behind its trigger (fewer silhouettes
#   published than triggers; trigger_overrun and kin in its log) or a view that reached the host
#   after its frame had closed (`late`). Then the machine stalled and the rig said so; an
#   uncounted loss is a fault of the rig.
# - A frame fused from fewer than all views (`cameras_mask` in the listener's log) is replayed
#   from those views only.
# The replay's input is a dataset of links to the masks so chosen.
/usr/bin/python3 - "$work" "$frames" <<'PY'
import csv, json, os, re, shutil, sys
work, frames = sys.argv[1], int(sys.argv[2])
short = {int(r["frame"]) for r in csv.DictReader(open(f"{work}/live.csv")) if r["reason"] == "1"}
used = {int(r["trigger_seq"]): int(r["cameras_mask"]) for r in csv.DictReader(open(f"{work}/live-log.csv"))}
src, dst = f"{work}/data", f"{work}/replay-data"
meta = json.load(open(f"{src}/meta.json"))
missing = sum(len(meta["camera_ids"]) - bin(mask).count("1") for mask in used.values())
def last_count(path, pattern, missing_line):  # a process that printed no summary counted nothing
    found = re.findall(pattern, open(path).read())
    return int(found[-1]) if found else missing_line
late = last_count(f"{work}/host.log", r"\blate=(\d+)", 0)
behind = sum(frames - last_count(f"{work}/cam{c}.log", r"stopped after (\d+) silhouettes", frames)
             for c in range(len(meta["camera_ids"])))
print(f"rig_netns_accuracy_test: {len(short)} frames with too few views live, left out of both scores;"
      f" {missing} views missing live, counted as dropped: {behind} by nodes behind their trigger, {late} late at the host")
allowed = 0.05 if missing <= behind + late else 0.01
if len(short) > allowed * frames:
    sys.exit(f"FAIL: {len(short)} frames lost views live (allowed: {allowed:.0%}; {missing} missing views,"
             f" {behind + late} counted as dropped)")
kept = [f for f in range(frames) if f not in short]
meta["frames"] = len(kept)
os.makedirs(dst)
json.dump(meta, open(f"{dst}/meta.json", "w"))
shutil.copy(f"{src}/rig.yaml", dst)
everyone = sum(1 << cam for cam in meta["camera_ids"])
partial = [f for f in kept if used.get(f, everyone) != everyone]
print(f"rig_netns_accuracy_test: {len(partial)} frames fused from fewer views live, replayed from the same views")
for cam in meta["camera_ids"]:
    os.makedirs(f"{dst}/cam{cam}")
    for k, f in enumerate(kept):
        if used.get(f, everyone) >> cam & 1:
            os.symlink(f"{src}/cam{cam}/mask_{f:06d}.png", f"{dst}/cam{cam}/mask_{k:06d}.png")
json.dump(kept, open(f"{work}/kept.json", "w"))
PY
"$build/fusion_host/app/hullpose-fusion-host" --replay "$work/replay-data" --out "$work/replay.csv" > /dev/null
/usr/bin/python3 - "$work" <<'PY'
import csv, json, sys
work = sys.argv[1]
kept = json.load(open(f"{work}/kept.json"))
rows = list(csv.DictReader(open(f"{work}/replay.csv")))
for r in rows: r["frame"] = str(kept[int(r["frame"])])
lost = sorted(set(range(kept[-1] + 1)) - set(kept))
for f in lost: rows.append(dict(rows[0], frame=str(f), valid="0", reason="1"))
rows.sort(key=lambda r: int(r["frame"]))
with open(f"{work}/replay_same.csv", "w", newline="") as out:
    w = csv.DictWriter(out, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)
PY
"$build/tools/eval/hullpose-eval" --gt "$work/data" --est "$work/live.csv" --json > "$work/live.json"
"$build/tools/eval/hullpose-eval" --gt "$work/data" --est "$work/replay_same.csv" --json > "$work/replay.json"
grep -v INFO "$work/host.log" | tail -n 2 || true
/usr/bin/python3 - "$work" "$frames" "$rate" <<'PY'
import csv, json, struct, sys
work, frames, rate = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
rows = list(csv.DictReader(open(f"{work}/live.csv")))
seqs = [int(r["frame"]) for r in rows]
fail = []
if sorted(seqs) != list(range(frames)): fail.append(f"{len(set(seqs))} distinct sequences published, expected 0..{frames-1} once each")
# HULL events (lcm-logger layout), each hull_t read up to its payload (hull_t.lcm).
data, at, hulls = open(f"{work}/hull.lcmlog", "rb").read(), 0, []
while at + 28 <= len(data):
    _, _, _, clen, dlen = struct.unpack(">IqqII", data[at:at + 28])
    m, p = data[at + 28 + clen:at + 28 + clen + dlen], 16
    p += 4 + struct.unpack(">i", m[p:p + 4])[0]
    seq, nx, ny, nz = struct.unpack(">qiii", m[p:p + 20])
    voxel, carved, occupied = struct.unpack(">ffi", m[p + 32:p + 44])
    hulls.append((seq, (nx, ny, nz), voxel / carved, occupied, dlen))
    at += 28 + clen + dlen
expected = 2 * frames / rate
if len(hulls) < 0.8 * expected or len(hulls) > expected + 1: fail.append(f"{len(hulls)} hulls on HULL, expected about {expected:.0f}")
if any(max(d) > 64 or o < 50 or f != 2 for _, d, f, o, _ in hulls): fail.append(f"a hull is not a coarse body: {hulls[:3]}")
if any(b[0] - a[0] < rate // 2 - 1 for a, b in zip(hulls, hulls[1:])): fail.append("hulls come faster than 2 Hz")
if hulls: print(f"rig_netns_accuracy_test: {len(hulls)} hulls, {hulls[0][1]} voxels, {min(h[3] for h in hulls)}..{max(h[3] for h in hulls)} occupied, {max(h[4] for h in hulls)} bytes at most")
print(f"rig_netns_accuracy_test: {len(rows)} skeletons over {frames} triggers")
if fail: print("FAIL: " + "; ".join(fail)); sys.exit(1)
PY
/usr/bin/python3 "$root/tools/demo/compare_eval.py" "$work/live.json" "$work/replay.json" || { echo "FAIL: live and replay accuracy differ by more than 1 %"; exit 1; }
echo PASS
