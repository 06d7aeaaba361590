#!/usr/bin/python3
"""Peer of ck3/N and d6i1d/N: scikit-image skeletonize_3d (Lee 1994) on the same hull volumes,
written by bench_fusion to $HULLPOSE_BUILD/bench/volumes/hull_N.npy. Prints JSON lines
{"name": "skimage/skeletonize_3d/N", "median_ms": ...}."""
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
paths = sorted(glob.glob(os.path.join(build, "bench", "volumes", "hull_*.npy")))
if not paths:
    print(json.dumps({"name": "skimage/skeletonize_3d", "error": "no volumes in " + build + "/bench/volumes (run bench_fusion first)"}))
    sys.exit(0)
for path in paths:
    n = re.search(r"hull_(\d+)\.npy$", path).group(1)
    volume = np.load(path).astype(np.uint8)
    times = []
    skeleton = None
    for _ in range(max(3, reps)):
        t0 = time.perf_counter()
        skeleton = skeletonize_3d(volume)
        times.append((time.perf_counter() - t0) * 1e3)
    print(json.dumps({"name": "skimage/skeletonize_3d/" + n, "median_ms": round(statistics.median(times), 4),
                      "iterations": len(times), "hull_voxels": int(volume.sum()),
                      "skeleton_voxels": int((skeleton > 0).sum())}))
