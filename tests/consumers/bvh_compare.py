#!/usr/bin/python3
"""Joints from a BVH reader's forward kinematics (bvh_fk.js) against the joints they were made of.

usage: bvh_compare.py FK.csv POSES.csv GAPS.json [--exact] [--held MIN]
POSES.csv: an estimate or ground-truth file (docs/conventions.md). Frames the exporter marked
"measured" are compared. Our BVH holds one set of bone lengths for the whole take (the held body
model's, else the median), so a joint can differ from a frame whose bones are longer or shorter by at most the sum of those
length differences along its chain from the pelvis; with directions right it differs by no
more. --exact: the poses have the subject's lengths (ground truth), every joint within 1 mm.
Otherwise: every joint within 1 mm plus its chain's length difference. --held MIN: frames whose
`model` column (skeleton_t.model_version: the fusion host's held body model, whose bone lengths
every such frame has exactly) is >= 1 must be within 1 mm, and there must be at least MIN of
them; the provisional frames before the hold keep the chain bound. Prints a JSON summary.
"""
import csv, json, math, sys

NAMES = ["HeadTop", "Head", "Neck", "Chest", "LSho", "RSho", "LElb", "RElb", "LHand", "RHand", "LFTip", "RFTip", "UBack",
         "Back", "LBack", "LHip", "RHip", "LKne", "RKne", "LAnk", "RAnk", "LFoot", "RFoot", "LToe", "RToe"]
BONES = [("Chest", "Neck"), ("Neck", "Head"), ("Head", "HeadTop"), ("Chest", "LSho"), ("Chest", "RSho"), ("LSho", "LElb"),
         ("RSho", "RElb"), ("LElb", "LHand"), ("RElb", "RHand"), ("LHand", "LFTip"), ("RHand", "RFTip"), ("Chest", "UBack"),
         ("UBack", "Back"), ("Back", "LBack"), ("LBack", "LHip"), ("LBack", "RHip"), ("LHip", "LKne"), ("RHip", "RKne"),
         ("LKne", "LAnk"), ("RKne", "RAnk"), ("LAnk", "LFoot"), ("RAnk", "RFoot"), ("LFoot", "LToe"), ("RFoot", "RToe")]
END_SITES = {"Head.end": "HeadTop", "LHand.end": "LFTip", "RHand.end": "RFTip", "LFoot.end": "LToe", "RFoot.end": "RToe"}


def chains():
    """For each joint, the bones from the pelvis (LBack) to it."""
    adj = {n: [] for n in NAMES}
    for a, b in BONES:
        adj[a].append(b)
        adj[b].append(a)
    path, todo = {"LBack": []}, ["LBack"]
    while todo:
        j = todo.pop()
        for k in adj[j]:
            if k not in path:
                path[k] = path[j] + [(j, k)]
                todo.append(k)
    return path


def main():
    fk_path, poses_path, gaps_path = sys.argv[1:4]
    exact = "--exact" in sys.argv
    min_held = int(sys.argv[sys.argv.index("--held") + 1]) if "--held" in sys.argv else None
    fk = list(csv.DictReader(open(fk_path)))
    poses = list(csv.DictReader(open(poses_path)))
    states = json.load(open(gaps_path))["frames"]
    assert len(fk) == len(poses) == len(states), (len(fk), len(poses), len(states))

    def joint(row, name):
        return [float(row[f"{name}_{a}"]) for a in "xyz"]

    def fk_joint(row, name):  # BVH cm, Y up -> rig mm, z up
        src = next((k for k, v in END_SITES.items() if v == name), name)
        x, y, z = (float(row[f"{src}_{a}"]) for a in "xyz")
        return [10 * x, -10 * z, 10 * y]

    valid = [r for r, s in zip(poses, states) if s == "measured"]
    # The exporter's lengths (skeleton_io::subject_bone_lengths): the upper median over the frames
    # of the newest held body model when there is one, else over every measured frame.
    held_model = max((int(r.get("model", 0) or 0) for r in valid), default=0)
    basis = [r for r in valid if int(r.get("model", 0) or 0) == held_model] if held_model > 0 else valid
    lengths = {b: sorted(math.dist(joint(r, b[0]), joint(r, b[1])) for r in basis) for b in BONES}
    subject = {b: v[len(v) // 2] for b, v in lengths.items()}
    path = chains()
    errors, held_errors, excess, worst = [], [], -1e9, None
    for f, (a, p, s) in enumerate(zip(fk, poses, states)):
        if s != "measured":
            continue
        held = min_held is not None and int(p.get("model", 0)) >= 1
        for n in NAMES:
            e = math.dist(fk_joint(a, n), joint(p, n))
            if held:
                held_errors.append(e)
            bound = 1.0 if exact or held else 1.0 + sum(abs(math.dist(joint(p, u), joint(p, v)) - subject[(u, v) if (u, v) in subject else (v, u)])
                                                for u, v in path[n])
            errors.append(e)
            if e - bound > excess:
                excess, worst = e - bound, (f, n, round(e, 3), round(bound, 3))
    errors.sort()
    summary = {"frames_compared": len(valid), "joints": len(NAMES), "max_mm": round(errors[-1], 4),
               "p50_mm": round(errors[len(errors) // 2], 4), "p99_mm": round(errors[int(0.99 * (len(errors) - 1))], 4),
               "worst_against_bound": worst, "exact": exact}
    if min_held is not None:
        held_errors.sort()
        summary.update({"held_frames": len(held_errors) // len(NAMES),
                        "held_max_mm": round(held_errors[-1], 4) if held_errors else None,
                        "held_p99_mm": round(held_errors[int(0.99 * (len(held_errors) - 1))], 4) if held_errors else None})
    print(json.dumps(summary))
    if min_held is not None and len(held_errors) // len(NAMES) < min_held:
        sys.exit(f"FAIL: {len(held_errors) // len(NAMES)} frames of a held body model, expected at least {min_held}")
    if excess > 0:
        sys.exit(f"FAIL: frame {worst[0]} joint {worst[1]}: {worst[2]} mm off, allowed {worst[3]} mm")


main()
