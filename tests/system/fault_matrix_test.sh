#!/usr/bin/env bash
# The fault matrix (issue 19): one fault per run of a small rig in network namespaces (trigger
# master at 30 Hz, NUM camera nodes replaying sequence-coded masks, the sequence-checking fusion
# host, hullpose-listen), every process authenticating its messages with the rig's key. Faults
# are applied at positions in the skeleton stream (rows received), never after a sleep.
# Every run asserts: no frame mixes views of different trigger instants, frames that lack views
# say so (cameras mask, view count), and the stream recovers (full frames again after the fault).
#
#   host_restart    the fusion host is killed (SIGKILL) a third of the way in and started again
#   master_restart  the trigger master is killed a third of the way in and started again (new
#                   epoch, sequences from 0); the nodes resynchronise
#   sigstop         camera 2 is stopped (SIGSTOP) for 90 triggers (3 s) and resumed: its stale
#                   frames are dropped and counted (host: late), it rejoins
#   clock_step      camera 4's board clock steps by +500 ms a third of the way in (injected:
#                   trigger.clock_step_ms/clock_step_after); the node re-learns its offset
#   reorder_dup     every datagram to the host passes tests/rig/datagram_relay.cpp: every 7th
#                   is sent after its successor, every 5th twice (this kernel has no netem)
#   two_rigs        rigs A and B (different rig ids and keys) on the same group and port: each
#                   host fuses only its own rig, the other's messages are counted (auth_wrong_key)
#
# usage: fault_matrix_test.sh BUILD_DIR SCENARIO [FRAMES=300] [NUM=5]
source "$(dirname "$0")/rig_lib.sh"
scenario=${2:?scenario}
rig_init "$1" "fault-$scenario" fm
frames=${3:-300} num=${4:-5} rate=30
third=$(( frames / 3 ))
seconds=$(( frames / rate + 30 ))

# AUTH=0: the same runs without keys (to compare costs).
auth=${AUTH:-1}
key() { if (( auth )); then echo "--rig-key $1/rig.key"; fi; }
rig_files() {  # rig_files RIG_ID DIR URL WIRE: rig, masks, node configs, key
  mkdir -p "$2"
  "$build/tests/rig/rig_write_test_rig" "$2/rig.yaml" "$num" 160 120 "$1" "$frames"
  "$build/tools/rig_key/hullpose-rig-key" --output "$2/rig.key" > /dev/null
  RIG_KEY=$( (( auth )) && echo "$2/rig.key") "$root/tools/demo/node-configs.sh" "$2" "$num" "$2/rig.yaml" "$3" "$4" masks:seq
}
start_host() {  # start_host DIR URL [LOG]
  rm -f "$1/host.ready"
  spawn "${3:-$1/host.log}" fusion "$build/tests/rig/rig_stub_fusion_host" --rig "$1/rig.yaml" --lcm-url "$2" \
    $(key "$1") --min-cameras $(( num - 2 )) --duration-s "$seconds" --ready-file "$1/host.ready"
  host=$spawned
  wait_until 20 test -f "$1/host.ready"
}
start_listener() {  # start_listener DIR URL COUNT
  spawn "$1/listen.log" fusion "$build/tools/listen/hullpose-listen" --lcm-url "$2" $(key "$1") \
    --output "$1/skeletons.csv" --count "$3" --duration-s "$seconds" --ready-file "$1/listen.ready"
  listener=$spawned
  wait_until 20 test -f "$1/listen.ready"
}
start_master() {  # start_master DIR RIG_ID URL WIRE COUNT [WAIT_NODES]
  spawn "$1/master.log" master "$build/firmware_sync/trigger_master/hullpose-trigger-master" --rig-id "$2" \
    --rate "$rate" --line "wire:$4" --lcm-url "$3" $(key "$1") --count "$5" --wait-nodes "${6:-0}"
  master=$spawned
}
declare -A cam_pid
start_cams() {  # start_cams DIR [NS_OFFSET]
  for ((c = 0; c < num; c++)); do
    spawn "$1/cam$c.log" "cam$(( c + ${2:-0} ))" "$build/camera_node/app/hullpose-camera-node" --config "$1/node$c.yaml"
    cam_pid[$1/$c]=$spawned
  done
}
finish() {  # stop everything cleanly so each process prints its counters
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  pids=()
}
csv=$work/a/skeletons.csv
marks=()  # stream positions of the fault, passed to the checks

namespaces=$num
[[ $scenario == two_rigs ]] && namespaces=$(( 2 * num ))
"$netns" create "$prefix" "$namespaces" > /dev/null
master_url=$url host_url=$url
if [[ $scenario == reorder_dup ]]; then
  host_url="udpm://239.255.76.68:$(( port + 1 ))?ttl=0"
  spawn "$work/relay.log" fusion "$build/tests/rig/rig_datagram_relay" --from "239.255.76.67:$port" \
    --to "239.255.76.68:$(( port + 1 ))" --swap-every 7 --duplicate-every 5 --duration-s "$seconds"
fi
rig_files rigA "$work/a" "$url" "$wire"
case $scenario in
  clock_step) printf '  clock_step_ms: 500\n  clock_step_after: %d\n' "$third" >> "$work/a/node4.yaml" ;;
esac
start_host "$work/a" "$host_url"
start_listener "$work/a" "$host_url" 0
if [[ $scenario == two_rigs ]]; then
  rig_files rigB "$work/b" "$url" "$work/b/wire.sock"
  start_host "$work/b" "$url" "$work/b/host.log"
  start_listener "$work/b" "$url" 0
  start_master "$work/b" rigB "$url" "$work/b/wire.sock" "$frames" "$num"
  master_b=$spawned
  wait_until 10 test -S "$work/b/wire.sock"
  start_cams "$work/b" "$num"
fi
start_master "$work/a" rigA "$master_url" "$wire" "$([[ $scenario == master_restart ]] && echo 0 || echo "$frames")" "$num"
wait_until 10 test -S "$wire"
start_cams "$work/a"

case $scenario in
  host_restart)
    wait_until "$seconds" have_rows "$csv" "$third"
    kill -KILL "$host"; wait "$host" || true
    marks=("$(rows "$csv")")
    start_host "$work/a" "$host_url" "$work/a/host2.log"
    marks+=("$(rows "$csv")") ;;
  master_restart)
    wait_until "$seconds" have_rows "$csv" "$third"
    kill -KILL "$master"; wait "$master" || true
    marks=("$(rows "$csv")")
    rm -f "$wire"
    start_master "$work/a" rigA "$master_url" "$wire" "$frames" 0 ;;
  sigstop)
    wait_until "$seconds" have_rows "$csv" "$third"
    kill -STOP "${cam_pid[$work/a/2]}"
    marks=("$(rows "$csv")")
    wait_until "$seconds" have_rows "$csv" $(( marks[0] + 90 ))
    kill -CONT "${cam_pid[$work/a/2]}"
    marks+=("$(rows "$csv")") ;;
esac
wait "$master" || { echo "FAIL: trigger master failed"; cat "$work/a/master.log"; exit 1; }
[[ $scenario == two_rigs ]] && { wait "$master_b" || { echo "FAIL: rig B's trigger master failed"; exit 1; }; }
last_seq() { [[ -f $1 ]] && tail -n 1 "$1" | cut -d, -f1; }
deadline=$(( SECONDS + 20 ))  # the last skeletons follow the last trigger
until [[ $(last_seq "$csv") == $(( frames - 1 )) ]] || (( SECONDS > deadline )); do sleep 0.05; done
if [[ $scenario == two_rigs ]]; then
  until [[ $(last_seq "$work/b/skeletons.csv") == $(( frames - 1 )) ]] || (( SECONDS > deadline )); do sleep 0.05; done
fi
finish

grep -h "stopped after\|rig-stub\|rig_datagram\|hullpose-listen: {" "$work"/a/*.log "$work"/*.log 2>/dev/null | sed 's/^/  /' || true
/usr/bin/python3 - "$scenario" "$work" "$frames" "$num" "$third" "${marks[@]}" <<'PY'
import csv, glob, re, sys
scenario, work, frames, num, third = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
marks = [int(m) for m in sys.argv[6:]]
fail = []
def load(d): return list(csv.DictReader(open(f"{work}/{d}/skeletons.csv")))
def counters(path_glob):
    out = {}
    for p in glob.glob(path_glob):
        for line in open(p):
            if "skeletons published" in line or "stopped after" in line:
                for k, v in re.findall(r"\b([a-z_]+)=(-?\d+)", line): out[k] = out.get(k, 0) + int(v)
    return out
has = lambda r, c: (int(r["cameras_mask"]) >> c) & 1
full = lambda r: r["valid"] == "1" and int(r["num_cameras"]) == num
def common(rows, label, tail_from):
    mixed = [r for r in rows if r["reason"] == "5" and float(r["HeadTop_x"]) == -1]
    if mixed: fail.append(f"{label}: {len(mixed)} frames mixed views of different trigger instants")
    # A frame is flagged by what it says: its view count and mask agree, and a frame without
    # every camera is never presented as full.
    bad = [r for r in rows if bin(int(r["cameras_mask"])).count("1") != int(r["num_cameras"])]
    if bad: fail.append(f"{label}: {len(bad)} frames whose cameras mask and view count disagree")
    tail = rows[tail_from:]
    ok = sum(1 for r in tail if full(r))
    print(f"  {label}: {len(rows)} skeletons, {sum(r['valid'] == '1' for r in rows)} valid, "
          f"{ok}/{len(tail)} full frames after the fault")
    if not tail or ok < 0.9 * len(tail): fail.append(f"{label}: the stream did not recover ({ok}/{len(tail)} full frames at the end)")
rows = load("a")
seqs = [int(r["trigger_seq"]) for r in rows]
host = counters(f"{work}/a/host*.log")
print(f"fault_matrix {scenario}: host counters {host}")
if scenario == "host_restart":
    killed, back = marks
    if len(seqs) != len(set(seqs)): fail.append("a sequence was published twice across the restart")
    if sorted(seqs) != seqs: fail.append("sequences out of order across the restart")
    after = [s for s in seqs[back:]]
    if not after or after[-1] != frames - 1: fail.append("the restarted host did not follow the stream to its end")
    print(f"  host killed after {killed} skeletons, back after {back}; {frames - len(set(seqs))} sequences unpublished while it was down")
    common(rows, "rig A", back + 30)
elif scenario == "master_restart":
    cut = next((i for i in range(1, len(seqs)) if seqs[i] < seqs[i - 1]), None)
    if cut is None: fail.append("no restart of the sequence seen")
    else:
        second = seqs[cut:]
        if second != list(range(second[0], second[0] + len(second))) or second[0] > 10 or second[-1] != frames - 1:
            fail.append(f"the restarted master's sequence was not followed: {second[:5]}...{second[-3:]}")
        first = seqs[:cut]
        if len(first) != len(set(first)): fail.append("a sequence of the first run was published twice")
        print(f"  first run {len(first)} skeletons (to seq {first[-1]}), second run {len(second)} from seq {second[0]}")
        common(rows, "rig A", cut + 30)
    if "resynchronising" not in "".join(open(p).read() for p in glob.glob(f"{work}/a/cam*.log")):
        fail.append("no camera resynchronised on the new epoch")
elif scenario == "sigstop":
    stopped, resumed = marks
    if sorted(seqs) != list(range(frames)): fail.append("not every sequence was published exactly once")
    during = rows[stopped + 10:resumed - 5]
    without = [r for r in during if not has(r, 2)]
    print(f"  camera 2 stopped at row {stopped}, resumed at {resumed}: {len(without)}/{len(during)} frames in between without it, "
          f"all with {sorted(set(r['num_cameras'] for r in without))} views")
    if len(without) < 0.9 * len(during) or any(int(r["num_cameras"]) == num for r in without): fail.append("frames while camera 2 was stopped should be fused without it")
    # Every frame of the stop that has the other cameras' views is valid. A frame whose other
    # views missed the deadline too (a scheduling stall of the whole 2-core machine, not the
    # fault: seen once, in a run beside a compile) says so in its view count, and stays rare.
    short = [r for r in during if int(r["num_cameras"]) < num - 1]
    if any(r["valid"] != "1" for r in during if int(r["num_cameras"]) >= num - 1):
        fail.append("frames without camera 2 should still be valid")
    if len(short) > 0.05 * len(during):
        fail.append(f"{len(short)}/{len(during)} frames of the stop lost other cameras too (allowed: 5 %)")
    cam2 = counters(f"{work}/a/cam2.log")
    stale = host.get("late", 0) + sum(v for k, v in cam2.items() if k in ("trigger_overrun", "trigger_tag_after_timeout", "no_trigger", "trigger_unmatched", "trigger_no_sync", "queue_full"))
    print(f"  camera 2's stale frames dropped and counted: host late={host.get('late', 0)}, camera 2 {cam2}")
    if stale < 1: fail.append("camera 2's stale frames were not counted as dropped")
    common(rows, "rig A", resumed + 30)
elif scenario == "clock_step":
    if sorted(seqs) != list(range(frames)): fail.append("not every sequence was published exactly once")
    cam4 = counters(f"{work}/a/cam4.log")
    missing = [int(r["trigger_seq"]) for r in rows if not has(r, 4)]
    print(f"  camera 4 missing from {len(missing)} frames (seqs {missing[:3]}..{missing[-3:]}), its counters {cam4}")
    if "board clock stepped" not in open(f"{work}/a/cam4.log").read(): fail.append("camera 4's clock did not step")
    common(rows, "rig A", third + 60)
elif scenario == "reorder_dup":
    if sorted(seqs) != list(range(frames)): fail.append("not every sequence was published exactly once")
    relay = open(f"{work}/relay.log").read()
    m = re.search(r"(\d+) datagrams, (\d+) sent after their successor, (\d+) sent twice", relay)
    dropped = host.get("auth_replayed", 0) + host.get("duplicate", 0)
    print(f"  relay: {m.group(0) if m else relay.strip()}; host dropped duplicates: auth_replayed={host.get('auth_replayed', 0)} duplicate={host.get('duplicate', 0)}")
    if not m or int(m.group(2)) < 10 or int(m.group(3)) < 10: fail.append("the relay did not reorder and duplicate")
    elif dropped < 0.5 * int(m.group(3)): fail.append("duplicated datagrams were not counted as dropped")
    common(rows, "rig A", 30)
elif scenario == "two_rigs":
    rows_b = load("b")
    host_b = counters(f"{work}/b/host*.log")
    print(f"fault_matrix two_rigs: rig B host counters {host_b}")
    for label, rs, h in (("rig A", rows, host), ("rig B", rows_b, host_b)):
        s = [int(r["trigger_seq"]) for r in rs]
        if sorted(s) != list(range(frames)): fail.append(f"{label}: not every sequence published exactly once")
        if h.get("auth_wrong_key", 0) < frames: fail.append(f"{label}: the other rig's messages were not counted (auth_wrong_key)")
        common(rs, label, 30)
if fail: print("FAIL: " + "; ".join(fail)); sys.exit(1)
print("PASS")
PY
