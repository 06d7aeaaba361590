#!/usr/bin/python3
"""make eval: the pose stage scored on every motion we have, both pose paths side by side.

Renders every clip of ../shared/data/mocap (and the built-in `tpose` and `run`) once with
hullpose-synth into BUILD/eval/clips (up to 300 frames each; a clip is re-rendered only when its
`.complete` stamp is missing), replays each with `hullpose-fusion-host --replay` at every
resolution and pose path (`--pose bottom-up`, the thesis' per-frame reading as fitted, with
`--lag-frames 0`; `--pose track` as the live host publishes it, one frame late and smoothed),
scores them with hullpose-eval
(frames whose true body leaves the capture volume in their own column, out of valid % and
MPJPE), adds the temporal figures (tpose jitter, run lag), pools the CMU clips per resolution
and pose path, prints one table and writes JSON lines (stdout after the table, and
BUILD/eval/results.jsonl).

Usage: run-eval.py BUILD [--res 64,128] [--pose bottom-up,track] [--clips 55_01,01_01]
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MAX_FRAMES = 300
# The real capture scored without ground truth (silhouette agreement, bone-length CV), imported
# with hullpose-import as tools/import/README.md describes.
CRANE = "vlasic-crane"
BUILTIN = {"tpose": 150, "run": 150}  # static pose (jitter) and a fast periodic motion (lag)


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, text=True, capture_output=True, **kw)


def render(build, name, motion, frames):
    out = os.path.join(build, "eval", "clips", name)
    stamp = os.path.join(out, ".complete")
    if os.path.exists(stamp):
        return out
    synth = os.path.join(build, "tools", "synth", "hullpose-synth")
    cmd = [synth, "--motion", motion, "--out", out, "--threads", "2"]
    print(f"eval: rendering {name}", file=sys.stderr)
    r = subprocess.run(cmd + ["--frames", str(frames)], text=True, capture_output=True)
    if r.returncode != 0:
        # A clip shorter than `frames` at the rig rate: render all of it.
        if not re.search(r"has \d+ frames", r.stderr):
            sys.exit(f"eval: hullpose-synth failed on {name}: {r.stderr.strip()}")
        run(cmd)
    open(stamp, "w").close()
    return out


def import_crane(build, shared):
    out = os.path.join(build, "eval", "clips", "crane")
    if os.path.exists(os.path.join(out, ".complete")):
        return out
    src = os.path.join(shared, "data", "real", CRANE)
    imp = os.path.join(build, "tools", "import", "hullpose-import")
    if not os.path.isdir(src) or not os.path.exists(imp):
        return None
    print("eval: importing the crane capture", file=sys.stderr)
    rig = os.path.join(build, "eval", "crane-rig.yaml")
    run([imp, "rig", "--projections", os.path.join(src, "calibration", "camera{N}.P"), "--size", "1600x1200",
         "--units", "m", "--up", "y", "--floor", "0", "--rig-id", "crane", "--out", rig])
    run([imp, "silhouettes", "--rig", rig, "--pattern", os.path.join(src, "silhouettes", "camera{N}_{FFFF}.png"),
         "--out", out, "--motion", CRANE])
    open(os.path.join(out, ".complete"), "w").close()
    return out


def median(values):
    v = sorted(x for x in values if x is not None)
    return None if not v else (v[len(v) // 2] if len(v) % 2 else 0.5 * (v[len(v) // 2 - 1] + v[len(v) // 2]))


def read_rows(path, valid_only):
    rows = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            if valid_only and row["valid"] != "1":
                continue
            rows[int(row["frame"])] = [float(row[k]) for k in row if k.endswith(("_x", "_y", "_z"))]
    return rows


def pooled(rows):
    """The clips' figures over all their in-volume frames together: valid % of all of them, and
    MPJPE and hands+feet weighted by each clip's scored (valid) frames. One clip's figure can move
    by ~10 mm when a single frame's arbitration sends its tracking down another path; pooled over
    every clip such swings partly cancel (about +-2 mm without the salsa pair), so a change to the
    pose stage is judged by these first (docs/perf-log.md, session 24)."""
    frames = sum(r["frames"] for r in rows)
    scored = [(r["frames"] * r["valid_pct"] / 100, r) for r in rows if r["valid_pct"] is not None]
    n = sum(w for w, _ in scored)
    def mean(key):
        pairs = [(w, r[key]) for w, r in scored if r[key] is not None and w > 0]
        total = sum(w for w, _ in pairs)
        return None if total == 0 else sum(w * v for w, v in pairs) / total
    return {"clips": len(rows), "frames": frames, "valid_pct": 100 * n / frames if frames else None,
            "mpjpe_mm": mean("mpjpe_mm"), "hands_feet_mm": mean("hands_feet_mm")}


def jitter_rms(est_csv, settle_frames=60):
    """RMS deviation of every joint from its mean over the valid frames (mm): a still subject.
    The body model settling is not jitter: the frames before its first held model (the
    estimates' model column, skeleton_t.model_version >= 1) are left out, or for estimates that
    hold none (the bottom-up path) the first settle_frames (2 s at 30 fps, BodyModelParams'
    convergence window)."""
    with open(est_csv) as f:
        held = [int(r["frame"]) for r in csv.DictReader(f) if int(r.get("model") or 0) >= 1]
    start = min(held) if held else settle_frames
    rows = [r for f, r in sorted(read_rows(est_csv, True).items()) if f >= start]
    if len(rows) < 2:
        return None
    n = len(rows[0]) // 3
    total = 0.0
    for j in range(n):
        pts = [r[3 * j:3 * j + 3] for r in rows]
        mean = [sum(p[a] for p in pts) / len(pts) for a in range(3)]
        total += sum(sum((p[a] - mean[a]) ** 2 for a in range(3)) for p in pts) / len(pts)
    return math.sqrt(total / n)


def lag_frames(gt_csv, est_csv, max_lag=5):
    """The shift (frames) that best aligns the estimate's joint velocities with the truth's."""
    gt, est = read_rows(gt_csv, False), read_rows(est_csv, True)
    best, best_lag = None, None
    for lag in range(-max_lag, max_lag + 1):
        num = den_a = den_b = 0.0
        for f in est:
            g0, g1 = f - lag, f - lag - 1
            if f - 1 not in est or g0 not in gt or g1 not in gt:
                continue
            for k in range(len(est[f])):
                a = est[f][k] - est[f - 1][k]
                b = gt[g0][k] - gt[g1][k]
                num += a * b
                den_a += a * a
                den_b += b * b
        if den_a > 0 and den_b > 0:
            c = num / math.sqrt(den_a * den_b)
            if best is None or c > best:
                best, best_lag = c, lag
    return best_lag


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--res", default="64,128")
    ap.add_argument("--pose", default="bottom-up,track")
    ap.add_argument("--clips", default="")
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    shared = os.environ.get("HULLPOSE_SHARED", os.path.join(ROOT, "..", "shared"))
    mocap = os.path.join(shared, "data", "mocap")
    clips = {f[:-4]: (os.path.join(mocap, f), MAX_FRAMES) for f in sorted(os.listdir(mocap)) if f.endswith(".bvh")}
    clips.update({k: (k, v) for k, v in BUILTIN.items()})
    if a.clips:
        clips = {k: v for k, v in clips.items() if k in a.clips.split(",")}
    host = os.path.join(build, "fusion_host", "app", "hullpose-fusion-host")
    evaluate = os.path.join(build, "tools", "eval", "hullpose-eval")
    outdir = os.path.join(build, "eval", "runs")
    os.makedirs(outdir, exist_ok=True)
    results = []

    def replay_and_score(name, data, res, pose):
        """The estimate file, the replay's summary and hullpose-eval's JSON for one run."""
        est = os.path.join(outdir, f"{name}_{res}_{pose}.csv")
        print(f"eval: {name} {res} {pose}", file=sys.stderr)
        # The bottom-up figures stay the old per-frame path's, unsmoothed (#14: the gain is
        # measured against them).
        lag = ["--lag-frames", "0"] if pose == "bottom-up" else []
        summary = json.loads(run([host, "--replay", data, "--out", est, "--resolution", res,
                                  "--pose", pose] + lag).stdout.strip().splitlines()[-1])
        return est, summary, json.loads(run([evaluate, "--gt", data, "--est", est, "--json"]).stdout)

    for name, (motion, frames) in clips.items():
        data = render(build, name, motion, frames)
        for res in a.res.split(","):
            for pose in a.pose.split(","):
                est, summary, e = replay_and_score(name, data, res, pose)
                line = {"name": f"eval/{name}/{res}/{pose}", "clip": name, "resolution": int(res), "pose": pose,
                        "frames": e["frames"], "out_of_volume_frames": e["out_of_volume_frames"],
                        "out_of_volume_invalid": e["out_of_volume_invalid"],
                        "valid_pct": e["valid_pct"], "mpjpe_mm": e["mpjpe_mm"],
                        "hands_feet_mm": e["hands_feet_mpjpe_mm"], "lr_correct_pct": e["lr_correct_pct"],
                        "stature_error_pct": None if e["stature_gt_mm"] is None or e["stature_est_mm"] is None
                        else 100.0 * e["stature_error_mm"] / e["stature_gt_mm"],
                        "bone_length_error_pct": e["bone_length_error_median_abs_pct"],
                        "pose_median_ms": summary["median_ms"]["tree"] + summary["median_ms"]["fit"]}
                if name == "tpose":
                    line["jitter_rms_mm"] = jitter_rms(est)
                if name == "run":
                    line["lag_frames"] = lag_frames(os.path.join(data, "ground_truth.csv"), est)
                results.append(line)
    mocap_clips = {k for k in clips if k not in BUILTIN}
    pooled_rows = []
    for res in a.res.split(","):
        for pose in a.pose.split(","):
            rows = [r for r in results if r["clip"] in mocap_clips and r["resolution"] == int(res) and r["pose"] == pose]
            if rows:
                pooled_rows.append({"name": f"eval/pooled/{res}/{pose}", "resolution": int(res), "pose": pose,
                                    **pooled(rows)})
    crane = import_crane(build, shared) if not a.clips or "crane" in a.clips.split(",") else None
    crane_rows = []
    if crane:
        for res in a.res.split(","):
            for pose in a.pose.split(","):
                est, summary, c = replay_and_score("crane", crane, res, pose)
                crane_rows.append({"name": f"eval/crane/{res}/{pose}", "clip": "crane", "resolution": int(res),
                                   "pose": pose, "frames": c["frames"], "valid_pct": c["valid_pct"],
                                   "inside_all_views_pct": c["inside_all_views_pct"],
                                   "frames_inside_n_minus_1_pct": c["frames_inside_n_minus_1_pct"],
                                   "bone_length_cv_median_pct": None if median(c["bone_length_cv"].values()) is None
                                   else 100 * median(c["bone_length_cv"].values()),
                                   "pose_median_ms": summary["median_ms"]["tree"] + summary["median_ms"]["fit"]})
    elif not a.clips:
        print("eval: crane skipped (no ../shared/data/real/vlasic-crane or no hullpose-import)", file=sys.stderr)
    fmt = lambda v, d=1: "-" if v is None else f"{v:.{d}f}"
    print("| clip | res | pose | in-vol frames | out-of-vol (flagged) | valid % | MPJPE mm | hands+feet mm | "
          "L/R % | stature err % | bone len err % | pose ms | jitter mm | lag frames |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        print(f"| {r['clip']} | {r['resolution']} | {r['pose']} | {r['frames']} | {r['out_of_volume_frames']} "
              f"({r['out_of_volume_invalid']}) | {fmt(r['valid_pct'])} | {fmt(r['mpjpe_mm'])} | "
              f"{fmt(r['hands_feet_mm'])} | {fmt(r['lr_correct_pct'])} | {fmt(r['stature_error_pct'])} | "
              f"{fmt(r['bone_length_error_pct'])} | "
              f"{fmt(r['pose_median_ms'], 3)} | {fmt(r.get('jitter_rms_mm'))} | {r.get('lag_frames', '-')} |")
    if pooled_rows:
        print("\n| CMU clips pooled | res | pose | clips | in-vol frames | valid % | MPJPE mm | hands+feet mm |")
        print("|---|---|---|---|---|---|---|---|")
        for r in pooled_rows:
            print(f"| all | {r['resolution']} | {r['pose']} | {r['clips']} | {r['frames']} | {fmt(r['valid_pct'])} | "
                  f"{fmt(r['mpjpe_mm'])} | {fmt(r['hands_feet_mm'])} |")
    if crane_rows:
        print("\n| real capture | res | pose | frames | valid % | bone points inside every view % | "
              "frames with all inside >= n-1 views % | median bone-length CV % | pose ms |")
        print("|---|---|---|---|---|---|---|---|---|")
        for r in crane_rows:
            print(f"| crane | {r['resolution']} | {r['pose']} | {r['frames']} | {fmt(r['valid_pct'])} | "
                  f"{fmt(r['inside_all_views_pct'])} | {fmt(r['frames_inside_n_minus_1_pct'])} | "
                  f"{fmt(r['bone_length_cv_median_pct'], 2)} | {fmt(r['pose_median_ms'], 3)} |")
    results += pooled_rows + crane_rows
    with open(os.path.join(build, "eval", "results.jsonl"), "w") as f:
        for r in results:
            print(json.dumps(r))
            f.write(json.dumps(r) + "\n")


if __name__ == "__main__":
    main()
