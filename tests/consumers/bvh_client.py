#!/usr/bin/python3
"""Test client for hullpose-stream's BVH lines: TCP (plain: HIERARCHY first, then motion lines;
axis: "0 hullpose <values> ||" lines, Axis Neuron style) or UDP (one line per datagram).

usage: bvh_client.py tcp PORT | udp PORT  --format plain|axis --frames N [--channels C]
               [--ready FILE] [--out FILE.json] [--timeout-s 30]
Writes FILE when connected/bound, reads N frames, checks every line (channel count, finite
numbers, root inside the rig's reach) and prints/writes a JSON summary; exit 1 on a bad line.
"""
import json, math, socket, sys, time


def arg(name, default=None):
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default


def main():
    kind, port = sys.argv[1], int(sys.argv[2])
    fmt, frames = arg("--format", "plain"), int(arg("--frames"))
    channels = int(arg("--channels", "0"))
    deadline = time.monotonic() + float(arg("--timeout-s", "30"))  # a bound on waiting only
    if kind == "tcp":
        sock = socket.create_connection(("127.0.0.1", port))
        stream = sock.makefile("r")
        def lines():
            for line in stream:
                yield line
    else:
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        sock.bind(("127.0.0.1", port))
        def lines():
            while True:
                data, _ = sock.recvfrom(65536)
                yield data.decode()
    sock.settimeout(max(1.0, deadline - time.monotonic()))
    if arg("--ready"):
        open(arg("--ready"), "w").write("ready\n")
    it = lines()
    header = []
    if fmt == "plain" and kind == "tcp":
        for line in it:
            header.append(line.strip())
            if line.startswith("Frame Time:"):
                break
        channels = sum(int(l.split()[1]) for l in header if l.startswith("CHANNELS"))
        assert header[0] == "HIERARCHY" and "MOTION" in header, header[:3]
    got, roots = 0, []
    for line in it:
        words = line.split()
        if fmt == "axis":
            if words[:2] != ["0", "hullpose"] or words[-1] != "||":
                sys.exit(f"FAIL: line {got}: not an Axis Neuron style line: {line[:60]!r}")
            words = words[2:-1]
        values = [float(w) for w in words]
        if channels and len(values) != channels:
            sys.exit(f"FAIL: line {got}: {len(values)} values, the hierarchy has {channels} channels")
        if not all(math.isfinite(v) for v in values):
            sys.exit(f"FAIL: line {got}: a value is not finite")
        roots.append(values[:3])
        got += 1
        if got == frames:
            break
    if got < frames:
        sys.exit(f"FAIL: {got} of {frames} lines")
    moved = math.dist(roots[0], roots[-1])
    summary = {"kind": kind, "format": fmt, "frames": got, "channels": len(values), "root_moved_cm": round(moved, 2),
               "root_height_cm": round(roots[0][1], 2)}
    print(json.dumps(summary))
    if arg("--out"):
        open(arg("--out"), "w").write(json.dumps(summary) + "\n")
    if not (50 < roots[0][1] < 150) or moved <= 1:
        sys.exit(f"FAIL: the pelvis should be 0.5-1.5 m up and move while walking: {summary}")


main()
