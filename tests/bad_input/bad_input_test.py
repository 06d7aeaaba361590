#!/usr/bin/env python3
"""Bad input never aborts (issue 19): every program that reads files is given a corpus of bad
ones -- empty, garbage, truncated, wrong types, huge and non-finite numbers, unknown keys,
corrupt and mis-sized PNGs -- and must exit 2 with a message that names the file and, where the
fault is in one field, that field. Never a signal (abort, segfault), never exit 3 (an unexpected
exception), never success. One frame of a stream (a dataset's mask, a camera node's recorded frame)
that cannot be read is not fatal: that camera is missing for that frame, counted and logged with the
file named, and the run goes on (run_drop).

The corpus is made from good files at test time (a small rig, a two-frame synthetic dataset, a
BVH clip from ../shared): each case changes one thing.

usage: bad_input_test.py BUILD_DIR [SHARED_DIR]    (-k NAME runs the cases whose name holds NAME)
"""
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile

build = os.path.abspath(sys.argv[1])
shared = os.path.abspath(sys.argv[2]) if len(sys.argv) > 2 and not sys.argv[2].startswith("-") else None
only = sys.argv[sys.argv.index("-k") + 1] if "-k" in sys.argv else ""
rng = random.Random(19)

EXE = {
    "camera-node": f"{build}/camera_node/app/hullpose-camera-node",
    "fusion-host": f"{build}/fusion_host/app/hullpose-fusion-host",
    "eval": f"{build}/tools/eval/hullpose-eval",
    "synth": f"{build}/tools/synth/hullpose-synth",
    "calibrate": f"{build}/tools/calibrate/hullpose-calibrate",
    "rig-key": f"{build}/tools/rig_key/hullpose-rig-key",
    "trigger-master": f"{build}/firmware_sync/trigger_master/hullpose-trigger-master",
    "listen": f"{build}/tools/listen/hullpose-listen",
}

work = tempfile.mkdtemp(prefix="hullpose-badinput.")
results = []


def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(path, mode) as f:
        f.write(data)
    return path


def run(name, argv, names, timeout=60, expect=2):
    """Runs argv; the case passes if it exits `expect` and stderr holds every string of `names`."""
    if only and only not in name:
        return
    try:
        p = subprocess.run(argv, capture_output=True, text=True, errors="replace", timeout=timeout, cwd=work,
                           env=dict(os.environ, HULLPOSE_LOG="*:warn"))
        rc, err = p.returncode, p.stderr.strip()
    except subprocess.TimeoutExpired:
        rc, err = "timeout", ""
    missing = [n for n in names if n.lower() not in err.lower()]
    ok = rc == expect and not missing
    why = "" if ok else (f"exit {rc}" if rc != expect else "") + (f" message lacks {missing}" if missing else "")
    results.append((ok, name, why.strip(), err.splitlines()[-1][:300] if err else ""))


def run_drop(name, argv, names):
    """A stream with one bad frame (a dataset's mask, a camera node's recorded frame): the frame is a
    counted, logged drop (issue 15: that camera is missing for that frame), so the run exits 0 and
    stderr names the file."""
    run(name, argv, names, expect=0)


def mutate_yaml(text, key, value):
    """Replaces the first `key: ...` scalar of a YAML text."""
    new, n = re.subn(rf"(^\s*-?\s*{key}:)[^\n]*", rf"\g<1> {value}", text, count=1, flags=re.M)
    assert n == 1, key
    return new


# ---- good templates -------------------------------------------------------------------------
os.makedirs(f"{work}/good")
subprocess.run([f"{build}/tests/rig/rig_write_test_rig", f"{work}/good/rig.yaml", "3", "64", "48", "rigA", "3"], check=True)
good_rig = open(f"{work}/good/rig.yaml").read()
subprocess.run([EXE["synth"], "--motion", "walk", "--frames", "2", "--out", f"{work}/ds", "--seed", "1"], check=True,
               capture_output=True)
good_meta = open(f"{work}/ds/meta.json").read()
good_gt = open(f"{work}/ds/ground_truth.csv").read()
good_png = open(f"{work}/ds/cam0/mask_000000.png", "rb").read()
small_png = open(f"{work}/good/cam0/seq_000000.png", "rb").read()
node_yaml = f"""%YAML:1.0
camera_id: 0
rig_file: "{work}/good/rig.yaml"
source: {{ type: file, path: "{work}/good/cam0/seq_%06d.png" }}
bgs: {{ method: threshold, learn_frames: 1 }}
post: {{ open_radius: 0, close_radius: 0, min_blob_area: 0, max_hole_area: 0 }}
lcm: {{ url: "memq://", queue_depth: 8, status_period_ms: 1000 }}
"""
# An estimate file: the ground truth's joints as estimates (frame,valid,reason,joints...).
gt_rows = [l.split(",") for l in good_gt.strip().splitlines()]
est_text = "frame,valid,reason," + ",".join(gt_rows[0][2:]) + "\n" + "".join(
    ",".join([r[0], "1", "0"] + r[2:]) + "\n" for r in gt_rows[1:])
good_est = write(f"{work}/good/est.csv", est_text)

GARBAGE = bytes(rng.randrange(256) for _ in range(700))
HUGE = "1e999"

# ---- rig files: every program that reads one ----------------------------------------------
rig_cases = {
    "empty": "", "garbage": GARBAGE, "truncated": good_rig[: len(good_rig) // 2],
    "fx_text": ("fx", '"abc"'), "fx_huge": ("fx", HUGE), "fx_nan": ("fx", ".nan"), "width_huge": ("width", "99999999999"),
    "width_float": ("width", "64.5"), "id_negative": ("id", "-3"), "rig_id_list": ("rig_id", "[1, 2]"),
    "version_2": ("version", "2"), "cameras_scalar": ("cameras", "7"),
}
for case, spec in rig_cases.items():
    if isinstance(spec, tuple):
        data, field = mutate_yaml(good_rig, *spec), spec[0]
    else:
        data, field = spec, None
    for prog in ("fusion-host", "camera-node", "synth", "replay"):
        d = f"{work}/rig_{case}_{prog}"
        names = [field] if field else []
        if prog == "fusion-host":
            f = write(f"{d}/rig.yaml", data)
            run(f"rig/{case}/fusion-host", [EXE["fusion-host"], "--rig", f, "--lcm-url", "memq://"], [f] + names)
        elif prog == "camera-node":
            f = write(f"{d}/rig.yaml", data)
            cfg = write(f"{d}/node.yaml", node_yaml.replace(f"{work}/good/rig.yaml", f))
            run(f"rig/{case}/camera-node", [EXE["camera-node"], "--config", cfg], [f] + names)
        elif prog == "synth":
            f = write(f"{d}/rig.yaml", data)
            run(f"rig/{case}/synth", [EXE["synth"], "--motion", "walk", "--frames", "1", "--rig", f, "--out", f"{d}/out"],
                [f] + names)
        else:
            shutil.copytree(f"{work}/ds", d)
            f = write(f"{d}/rig.yaml", data)
            run(f"rig/{case}/replay", [EXE["fusion-host"], "--replay", d, "--out", f"{d}/est.csv"], [f] + names)

# ---- camera node configs ------------------------------------------------------------------
node_cases = {
    "empty": "", "garbage": GARBAGE, "truncated": node_yaml[: len(node_yaml) // 2],
    "camera_id_text": ("camera_id", '"three"'), "camera_id_huge": ("camera_id", "1e20"),
    "camera_id_unknown": ("camera_id", "9"), "unknown_key": None, "queue_depth_negative": None,
    "source_unknown": None, "rig_file_missing": None,
}
for case, spec in node_cases.items():
    names = []
    if isinstance(spec, tuple):
        data, names = mutate_yaml(node_yaml, *spec), [spec[0]]
    elif spec is not None:
        data = spec
    elif case == "unknown_key":
        data, names = node_yaml + "exposure_us: 4000\n", ["exposure_us"]
    elif case == "queue_depth_negative":
        data, names = node_yaml.replace("queue_depth: 8", "queue_depth: -5"), ["queue_depth"]
    elif case == "source_unknown":
        data, names = node_yaml.replace("type: file", "type: webcam9000"), ["webcam9000"]
    else:
        data, names = node_yaml.replace(f"{work}/good/rig.yaml", f"{work}/nowhere/rig.yaml"), ["nowhere/rig.yaml"]
    f = write(f"{work}/node_{case}/node.yaml", data)
    run(f"node-config/{case}/camera-node", [EXE["camera-node"], "--config", f], [f] + names)

# ---- PNG frames: a camera node's recording, a dataset's masks, calibration images ----------
png_cases = {
    "empty": b"", "garbage": GARBAGE, "truncated": good_png[: len(good_png) // 2],
    "header_only": good_png[:33], "wrong_size": small_png, "text": b"not a png at all\n",
}
for case, data in png_cases.items():
    d = f"{work}/png_{case}_replay"
    shutil.copytree(f"{work}/ds", d)
    f = write(f"{d}/cam3/mask_000001.png", data)
    # A mask that does not match its camera is a dataset error (exit 2); an unreadable one is
    # that camera missing for that frame, counted and logged.
    (run if case == "wrong_size" else run_drop)(
        f"png/{case}/replay", [EXE["fusion-host"], "--replay", d, "--out", f"{d}/est.csv"], [f])
    if case != "wrong_size":
        d = f"{work}/png_{case}_node"
        shutil.copytree(f"{work}/good", d)
        f = write(f"{d}/cam0/seq_000000.png", data)
        cfg = write(f"{d}/node.yaml", node_yaml.replace(f"{work}/good/", f"{d}/"))
        run_drop(f"png/{case}/camera-node", [EXE["camera-node"], "--config", cfg], [f])
        d = f"{work}/png_{case}_calib"
        for k in range(3):
            write(f"{d}/images/cam0/img_{k:03d}.png", data)
        run(f"png/{case}/calibrate", [EXE["calibrate"], "--images", f"{d}/images", "--out", f"{d}/rig.yaml",
                                      "--board", "9x6", "--square-mm", "30", "--rig-id", "x"], [f"{d}/images"])

# ---- dataset meta.json --------------------------------------------------------------------
meta = json.loads(good_meta)
def meta_with(**kv):
    m = dict(meta); m.update(kv); return json.dumps(m, indent=2)
meta_cases = {
    "empty": ("", []), "garbage": (GARBAGE, []), "truncated": (good_meta[: len(good_meta) // 2], []),
    "seed_text": (meta_with(seed="abc"), ["seed"]), "seed_negative": (meta_with(seed="-1"), ["seed"]),
    "seed_huge": (meta_with(seed="99999999999999999999999"), ["seed"]),
    "start_utime_text": (meta_with(start_utime="soon"), ["start_utime"]),
    "frames_text": (meta_with(frames="ten"), ["frames"]), "frames_huge": (meta_with(frames=1e300), ["frames"]),
    "frames_negative": (meta_with(frames=-2), ["frames"]), "fps_zero": (meta_with(fps=0), ["fps"]),
    "camera_ids_text": (meta_with(camera_ids="all"), ["camera_ids"]),
    "camera_ids_huge": (meta_with(camera_ids=[0, 1e30]), ["camera_ids"]),
    "format_2": (meta_with(format=2), ["format"]), "array": ("[1, 2, 3]", []),
}
for case, (data, names) in meta_cases.items():
    for prog in ("replay", "eval"):
        d = f"{work}/meta_{case}_{prog}"
        shutil.copytree(f"{work}/ds", d)
        f = write(f"{d}/meta.json", data)
        argv = ([EXE["fusion-host"], "--replay", d, "--out", f"{d}/est.csv"] if prog == "replay"
                else [EXE["eval"], "--gt", d, "--est", good_est])
        run(f"meta/{case}/{prog}", argv, [f] + names)

# ---- CSV: ground truth and estimates (hullpose-eval) ---------------------------------------
def csv_cases(text):
    lines = text.splitlines()
    head, row = lines[0], lines[1].split(",")
    def row_with(i, v):
        r = list(row); r[i] = v; return "\n".join([head, ",".join(r)] + lines[2:]) + "\n"
    return {
        "empty": ("", []), "garbage": (GARBAGE, []), "header_only": (head + "\n", []),
        "wrong_header": ("a,b,c\n1,2,3\n", []), "short_row": ("\n".join([head, ",".join(row[:5])]) + "\n", [":2:"]),
        "long_row": ("\n".join([head, ",".join(row + ["7"])]) + "\n", [":2:"]),
        "text_number": (row_with(4, "abc"), [":2:"]), "huge_number": (row_with(4, HUGE), [":2:"]),
        "nan": (row_with(4, "nan"), [":2:"]), "frame_float": (row_with(0, "0.5"), [":2:"]),
        "frame_huge": (row_with(0, "99999999999999"), [":2:"]),
        "truncated": (text[: len(text) // 2 + 3], []),
    }
for case, (data, names) in csv_cases(good_gt).items():
    d = f"{work}/gt_{case}"
    shutil.copytree(f"{work}/ds", d)
    f = write(f"{d}/ground_truth.csv", data)
    run(f"csv/ground_truth/{case}/eval", [EXE["eval"], "--gt", d, "--est", good_est], [f] + names)
for case, (data, names) in csv_cases(est_text).items():
    f = write(f"{work}/est_{case}/est.csv", data)
    run(f"csv/estimates/{case}/eval", [EXE["eval"], "--gt", f"{work}/ds", "--est", f], [f] + names)

# ---- BVH clips (hullpose-synth --motion FILE.bvh) ------------------------------------------
bvh_src = f"{shared}/data/mocap/55_01.bvh" if shared else None
if bvh_src and os.path.exists(bvh_src):
    good_bvh = open(bvh_src).read()
    head, motion = good_bvh.split("MOTION", 1)
    mlines = motion.strip().splitlines()
    body = "\n".join(mlines[3:40])
    def bvh(frames="37", ftime="0.0083333", data=body, hier=head):
        return f"{hier}MOTION\nFrames: {frames}\nFrame Time: {ftime}\n{data}\n"
    first = body.splitlines()[0].split()
    bvh_cases = {
        "empty": ("", []), "garbage": (GARBAGE, []), "truncated_hierarchy": (head[: len(head) // 2], []),
        "truncated_motion": (bvh()[: len(bvh()) - 500], []), "frames_text": (bvh(frames="many"), ["Frames"]),
        "frames_huge": (bvh(frames="99999999999"), ["Frames"]), "frames_negative": (bvh(frames="-4"), ["Frames"]),
        "frame_time_zero": (bvh(ftime="0"), ["Frame Time"]), "frame_time_nan": (bvh(ftime="nan"), ["Frame Time"]),
        "value_text": (bvh(data="\n".join([" ".join(["x"] + first[1:])] + body.splitlines()[1:])), []),
        "value_huge": (bvh(data="\n".join([" ".join([HUGE] + first[1:])] + body.splitlines()[1:])), []),
        "channels_huge": (bvh(hier=head.replace("CHANNELS 6", "CHANNELS 600000000", 1)), ["CHANNELS"]),
        "channel_unknown": (bvh(hier=head.replace("Xposition", "Wposition", 1)), ["Wposition"]),
        "no_root": (bvh(hier=head.replace("ROOT", "BONE", 1)), []),
        "unbalanced_braces": (bvh(hier=head.replace("}", "", 3)), []),
    }
    for case, (data, names) in bvh_cases.items():
        f = write(f"{work}/bvh_{case}/clip.bvh", data)
        run(f"bvh/{case}/synth", [EXE["synth"], "--motion", f, "--frames", "2", "--out", f"{work}/bvh_{case}/out"], [f] + names)
else:
    print("bad_input_test: no ../shared/data/mocap/55_01.bvh: BVH cases skipped")

# ---- rig keys: every program that takes one -------------------------------------------------
key_cases = {"empty": ("", 0o600), "garbage": (GARBAGE, 0o600), "short": ("abcd\n", 0o600),
             "world_readable": ("00" * 32 + "\n", 0o644), "group_readable": ("00" * 32 + "\n", 0o640)}
for case, (data, mode) in key_cases.items():
    f = write(f"{work}/key_{case}/rig.key", data)
    os.chmod(f, mode)
    run(f"key/{case}/rig-key", [EXE["rig-key"], "--check", f], [f])
    run(f"key/{case}/fusion-host", [EXE["fusion-host"], "--rig", f"{work}/good/rig.yaml", "--lcm-url", "memq://",
                                    "--rig-key", f], [f])
    run(f"key/{case}/trigger-master", [EXE["trigger-master"], "--rig-id", "rigA", "--line", "sim", "--lcm-url", "memq://",
                                       "--rig-key", f, "--count", "1"], [f])
    run(f"key/{case}/listen", [EXE["listen"], "--lcm-url", "memq://", "--rig-key", f, "--count", "1"], [f])
    cfg = write(f"{work}/key_{case}/node.yaml", node_yaml.replace('url: "memq://"', f'url: "memq://", rig_key: "{f}"'))
    run(f"key/{case}/camera-node", [EXE["camera-node"], "--config", cfg], [f])

# ---- report -------------------------------------------------------------------------------
failed = [r for r in results if not r[0]]
for ok, name, why, last in results:
    if not ok or os.environ.get("VERBOSE"):
        print(f"{'ok  ' if ok else 'FAIL'} {name}: {why}\n       {last}")
print(f"bad_input_test: {len(results) - len(failed)}/{len(results)} cases exit 2 naming the file and field, or drop one bad frame naming it")
if os.environ.get("KEEP_WORK") == "1":
    print(f"work dir: {work}")
else:
    shutil.rmtree(work, ignore_errors=True)
sys.exit(1 if failed else 0)
