#!/usr/bin/python3
"""Peer of ck3/N and d6i1d/N: scikit-image skeletonize_3d (Lee 1994) on the same hull volumes,
written by bench_fusion to $HULLPOSE_BUILD/bench/volumes/hull_N_fF.npy (CMU 55_01 frames F).
Prints JSON lines {"name": "skimage/skeletonize_3d/N", "median_ms": ...}: the mean over the
frames of each frame's median time, like bench_fusion, which cycles through the same frames."""
import glob
import json
import os
import re
import statistics
import sys
import time

import numpy as np

try:
    from skimage.morphology import skeletonize_3d
except ImportError:  # newer scikit-image: skeletonize handles 3-D volumes
    from skimage.morphology import skeletonize as skeletonize_3d

build = os.environ.get("HULLPOSE_BUILD", "build")
reps = int(os.environ.get("HULLPOSE_BENCH_REPS", "5"))
paths = sorted(glob.glob(os.path.join(build, "bench", "volumes", "hull_*_f*.npy")))
if not paths:
    print(json.dumps({"name": "skimage/skeletonize_3d", "error": "no volumes in " + build + "/bench/volumes (run bench_fusion first)"}))
    sys.exit(0)
by_resolution = {}
for path in paths:
    m = re.search(r"hull_(\d+)_f(\d+)\.npy$", path)
    if m:
        by_resolution.setdefault(int(m.group(1)), []).append(path)
for n in sorted(by_resolution):
    medians, hull_voxels, skeleton_voxels = [], 0, 0
    for path in by_resolution[n]:
        volume = np.load(path).astype(np.uint8)
        times = []
        for _ in range(max(3, reps)):
            t0 = time.perf_counter()
            skeleton = skeletonize_3d(volume)
            times.append((time.perf_counter() - t0) * 1e3)
        medians.append(statistics.median(times))
        hull_voxels += int(volume.sum())
        skeleton_voxels += int((skeleton > 0).sum())
    k = len(by_resolution[n])
    print(json.dumps({"name": "skimage/skeletonize_3d/" + str(n), "median_ms": round(sum(medians) / k, 4),
                      "frames": k, "hull_voxels": hull_voxels // k, "skeleton_voxels": skeleton_voxels // k}))
