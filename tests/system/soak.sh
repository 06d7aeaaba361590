#!/usr/bin/env bash
# make soak: the rig for MINUTES (default 10) in network namespaces — trigger master at 30 Hz, 8
# hullpose-camera-node processes, the fusion host (sequence-checking pipeline, so a frame that
# mixes trigger instants is detected), hullpose-listen — with 1 % of the LCM datagrams in and out
# of every camera's namespace dropped (nftables). Every 10 s the RSS and CPU time of every
# process are sampled. Writes a JSON summary (stdout and WORK/soak.json) and fails unless:
# no process crashed, no frame mixed instants, every trigger was published (fused or with its
# reason), the RSS of every process grew < 5 % after the warm-up, and every view missing from a
# fused frame is accounted for by a counted drop (network loss counted by nftables, drops
# counted by nodes and host, by reason).
#
# usage: soak.sh BUILD_DIR [MINUTES=10] [OUT_JSON]     (root; KEEP_WORK=1 keeps the logs)
# The nodes replay a looping recording of 1024 sequence-coded masks (160x120, decoded into
# memory at start), so their memory is flat by construction and any growth is the code's.
# Every process authenticates its messages with the rig's key (AUTH=0: without, to compare).
source "$(dirname "$0")/rig_lib.sh"
rig_init "$1" soak sk
minutes=${2:-10} out_json=${3:-}
rate=30 num=8 period=1024
frames=$(( minutes * 60 * rate ))
warm_s=$(( minutes * 60 / 10 > 60 ? minutes * 60 / 10 : 60 ))  # RSS baseline after this

"$build/tests/rig/rig_write_test_rig" "$work/rig.yaml" "$num" 160 120 rigA "$period"
auth=${AUTH:-1} key=()
if (( auth )); then
  "$build/tools/rig_key/hullpose-rig-key" --output "$work/rig.key" > /dev/null
  key=(--rig-key "$work/rig.key")
fi
RIG_KEY=${key[1]:-} SOURCE_EXTRA="preload: true, loop: true" "$root/tools/demo/node-configs.sh" "$work" "$num" "$work/rig.yaml" "$url" "$wire" masks:seq
"$netns" create "$prefix" "$num" >/dev/null
for ((c = 0; c < num; c++)); do "$netns" loss "$prefix" "cam$c" "$port" 100; done

seconds=$(( frames / rate + 60 ))
spawn "$work/host.log" fusion "$build/tests/rig/rig_stub_fusion_host" --seq-period "$period" --rig "$work/rig.yaml" \
  --lcm-url "$url" "${key[@]}" --min-cameras $(( num - 3 )) --duration-s $(( seconds + 30 )) --ready-file "$work/host.ready"
host=$spawned
spawn "$work/listen.log" fusion "$build/tools/listen/hullpose-listen" --lcm-url "$url" "${key[@]}" --output "$work/skeletons.csv" \
  --count "$frames" --duration-s $(( seconds + 30 )) --summary "$work/summary.json" --ready-file "$work/listen.ready"
listener=$spawned
wait_until 20 test -f "$work/listen.ready"
wait_until 20 test -f "$work/host.ready"
spawn "$work/master.log" master "$build/firmware_sync/trigger_master/hullpose-trigger-master" --rig-id rigA --rate "$rate" \
  --line "wire:$wire" --lcm-url "$url" "${key[@]}" --count "$frames" --wait-nodes "$num"
master=$spawned
wait_until 10 test -S "$wire"
cams=()
for ((c = 0; c < num; c++)); do
  spawn "$work/cam$c.log" "cam$c" "$build/camera_node/app/hullpose-camera-node" --config "$work/node$c.yaml"
  cams+=("$spawned")
done
sample_start "$work/samples.txt" 10
echo "soak: $minutes min, $frames triggers at $rate Hz, $num cameras, 1 % loss; work dir $work" >&2

crashed=()
master_rc=0; wait "$master" || master_rc=$?
(( master_rc == 0 )) || crashed+=("trigger_master(rc=$master_rc)")
deadline=$(( SECONDS + 60 ))  # the last skeletons follow the last trigger
until have_rows "$work/skeletons.csv" "$frames" || (( SECONDS > deadline )); do sleep 0.2; done
sample_stop
# Alive at the end, then a clean stop (each prints its counters).
for p in "$host" "${cams[@]}"; do kill -0 "$p" 2>/dev/null || crashed+=("pid $p")
done
kill -TERM "${cams[@]}" "$host" 2>/dev/null || true
for p in "$host" "${cams[@]}"; do
  rc=0; wait "$p" || rc=$?
  (( rc == 0 || rc == 143 )) || crashed+=("pid $p(rc=$rc)")
done
wait "$listener" || true
pids=()
for ((c = 0; c < num; c++)); do echo "cam$c $("$netns" dropped "$prefix" "cam$c")"; done > "$work/nft_dropped.txt"

/usr/bin/python3 - "$work" "$frames" "$num" "$warm_s" "$minutes" "${crashed[*]:-}" "$out_json" <<'PY'
import csv, json, re, statistics, sys
work, frames, num, warm_s, minutes, crashed, out_json = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]), sys.argv[6], sys.argv[7]
fail = []
rows = list(csv.DictReader(open(f"{work}/skeletons.csv")))
seqs = [int(r["trigger_seq"]) for r in rows]
missing = frames - len(set(seqs))
mixed = sum(1 for r in rows if r["reason"] == "5" and float(r["HeadTop_x"]) == -1)
reasons = {}
for r in rows: reasons[r["reason"]] = reasons.get(r["reason"], 0) + 1
valid = reasons.get("0", 0)
views_missing = sum(num - int(r["num_cameras"]) for r in rows)
# Processes: RSS after the warm-up against the end, CPU time.
samples = {}
for line in open(f"{work}/samples.txt"):
    t, pid, rss, cpu, name = line.split()
    samples.setdefault((name, pid), []).append((int(t), int(rss), int(cpu)))
procs = {}
for (name, pid), s in samples.items():
    warm = [rss for t, rss, _ in s if warm_s <= t < warm_s + 60]
    end = [rss for t, rss, _ in s[-6:]]
    if not warm or not end: continue
    base, last = statistics.median(warm), statistics.median(end)
    span = max(1, s[-1][0] - s[0][0])
    procs[f"{name}:{pid}"] = {"rss_warm_kb": base, "rss_end_kb": last, "rss_max_kb": max(r for _, r, _ in s),
                              "rss_growth_pct": round(100 * (last - base) / base, 2),
                              "cpu_pct": round(100 * (s[-1][2] - s[0][2]) / 100 / span, 1)}
    if last > 1.05 * base: fail.append(f"{name} (pid {pid}) RSS grew {base} -> {last} kB")
# Drops by reason: nodes ("stopped after N silhouettes; k=v ..."), host, network (nftables).
def counters(text):
    return {k: int(v) for k, v in re.findall(r"\b([a-z_]+)=(-?\d+)", text)}
node = {}
for c in range(num):
    log = open(f"{work}/cam{c}.log").read()
    stop = [l for l in log.splitlines() if "stopped after" in l]
    if not stop: fail.append(f"camera {c} printed no final counters")
    else:
        for k, v in counters(stop[-1]).items():
            if k.startswith("trigger_offset") or k.startswith("trigger_residual") or k == "trigger_synced": continue
            node[k] = node.get(k, 0) + v
host_log = open(f"{work}/host.log").read()
host_line = [l for l in host_log.splitlines() if "skeletons published" in l]
host = counters(host_line[-1]) if host_line else {}
if not host_line: fail.append("the fusion host printed no final counters")
net_in = net_out = 0
for line in open(f"{work}/nft_dropped.txt"):
    _, i, o = line.split(); net_in += int(i); net_out += int(o)
listen = json.load(open(f"{work}/summary.json"))
# Views that never reached a fused frame must be explained by counted drops: a node's
# (publish_error is the kernel refusing a send: nftables' loss out of a camera namespace, i.e.
# the network; queue_full, no_trigger, ...) or the host's (late, duplicate, ...). Loss into a
# camera namespace costs triggers, which the nodes interpolate (trigger_interpolated).
node_drops = sum(v for k, v in node.items() if k != "trigger_interpolated")
host_drops = sum(v for k, v in host.items() if k not in ("fused_complete", "fused_partial", "skeleton_valid", "skeleton_too_few_cameras", "unseen_sequences"))
explained = node_drops + host_drops
summary = {
    "name": "soak", "minutes": minutes, "rate_hz": 30, "cameras": num, "loss_pct": 1, "triggers": frames,
    "skeletons": len(rows), "distinct_sequences": len(set(seqs)), "missing_sequences": missing,
    "valid": valid, "reasons": reasons, "mixed_instants": mixed, "crashes": crashed.split() if crashed else [],
    "views_missing_from_frames": views_missing, "drops_explaining_them": explained,
    "network_dropped": {"into_cameras": net_in, "out_of_cameras": net_out},
    "node_counters": node, "host_counters": host, "listener": listen, "processes": procs,
}
if crashed: fail.append(f"crashed: {crashed}")
if mixed: fail.append(f"{mixed} frames mixed instants")
if missing > 0.001 * frames: fail.append(f"{missing} trigger sequences never published")
if views_missing > explained: fail.append(f"{views_missing} views missing from frames, only {explained} drops counted")
summary["pass"] = not fail
summary["failures"] = fail
text = json.dumps(summary)
print(text)
if out_json: open(out_json, "w").write(text + "\n")
open(f"{work}/soak.json", "w").write(text + "\n")
if fail: print("FAIL: " + "; ".join(fail), file=sys.stderr); sys.exit(1)
print("PASS", file=sys.stderr)
PY
