#!/usr/bin/python3
"""Reads an lcm-logger log of the rig (the event format: sync word 0xEDA1DA01, event number,
timestamp, channel and data lengths) and counts its TRIGGER sequences, or checks the skeletons a
replay of it produced (JSON lines from hullpose-listen).
usage: lcm_log_summary.py LOG --count-triggers | LOG --check SKELETONS.jsonl"""
import json, struct, sys
data = open(sys.argv[1], "rb").read()
pos, triggers, views = 0, set(), {}
closed_with = {}  # seq -> views it had when the fusion host closes it (in order: a newer complete frame closes it)
while pos < len(data):
    sync, _, _, clen, dlen = struct.unpack_from(">IqqII", data, pos)
    assert sync == 0xEDA1DA01, f"bad sync word at {pos}"
    chan = data[pos + 28:pos + 28 + clen].decode()
    msg = data[pos + 28 + clen:pos + 28 + clen + dlen]
    pos += 28 + clen + dlen
    if chan in ("TRIGGER", "SILHOUETTE"):
        slen = struct.unpack_from(">i", msg, 16)[0]
        at = 20 + slen
        if chan == "TRIGGER":
            triggers.add(struct.unpack_from(">q", msg, at)[0])
        else:
            cam, seq = struct.unpack_from(">iq", msg, at)
            if seq in closed_with:
                continue
            views.setdefault(seq, set()).add(cam)
            if len(views[seq]) == 3:
                for older in [x for x in views if x <= seq and x not in closed_with]:
                    closed_with[older] = len(views[older])
if sys.argv[2] == "--count-triggers":
    print(len(triggers)); sys.exit(0)
sk = [json.loads(l) for l in open(sys.argv[3])]
seqs = [s["trigger_seq"] for s in sk]
complete = {s for s, n in closed_with.items() if n == 3}
print(f"lcm_log_replay_test: log has {len(triggers)} triggers, {len(complete)} complete frames; replay gave {len(sk)} skeletons, "
      f"{sum(s['valid'] for s in sk)} valid")
fail = []
if len(triggers) < 60: fail.append("the log holds too few triggers")
if sorted(seqs) != sorted(set(seqs)): fail.append("a sequence was published twice")
if not triggers <= set(seqs): fail.append(f"sequences in the log without a skeleton: {sorted(triggers - set(seqs))[:10]}")
bad = [s["trigger_seq"] for s in sk if s["trigger_seq"] in complete and not (s["valid"] and s["cameras"] == 3)]
if bad: fail.append(f"complete frames not fused from all views: {bad[:10]}")
if fail: print("FAIL: " + "; ".join(fail)); sys.exit(1)
print("PASS")
