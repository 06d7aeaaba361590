#!/usr/bin/python3
"""TRC and C3D files from hullpose-export checked against their published layouts, and their
points against the take they came from. No C3D reader is packaged in Debian 12, so the C3D part
is read here from the c3d.org specification (header record words 1-12 and 150, parameter
section header, group and parameter records chained by their "next" offsets, floating-point
3D data with the residual word), independently of the C++ writer.

usage: check_markers.py POSES.csv GAPS.json FILE.trc FILE.c3d --fps F
"""
import csv, json, math, struct, sys

NAMES = ["HeadTop", "Head", "Neck", "Chest", "LSho", "RSho", "LElb", "RElb", "LHand", "RHand", "LFTip", "RFTip", "UBack",
         "Back", "LBack", "LHip", "RHip", "LKne", "RKne", "LAnk", "RAnk", "LFoot", "RFoot", "LToe", "RToe"]


def fail(msg):
    sys.exit("FAIL: " + msg)


def y_up(p):
    return (p[0], p[2], -p[1])


def check_trc(path, poses, states, fps):
    lines = open(path).read().split("\n")
    f = [l.split("\t") for l in lines]
    if f[0][:3] != ["PathFileType", "4", "(X/Y/Z)"]:
        fail(f"TRC line 1: {f[0]}")
    if f[1] != ["DataRate", "CameraRate", "NumFrames", "NumMarkers", "Units", "OrigDataRate", "OrigDataStartFrame", "OrigNumFrames"]:
        fail(f"TRC line 2: {f[1]}")
    rate, cam, n, markers, units = float(f[2][0]), float(f[2][1]), int(f[2][2]), int(f[2][3]), f[2][4]
    if (abs(rate - fps) > 0.01 or abs(cam - fps) > 0.01 or n != len(poses) or markers != 25 or units != "mm"):
        fail(f"TRC line 3: {f[2]}")
    if f[3][:2] != ["Frame#", "Time"] or [x for x in f[3][2:] if x] != NAMES or len(f[3]) != 2 + 3 * 25:
        fail(f"TRC line 4 (marker names, each over three columns): {f[3][:8]}...")
    if f[4][2:5] != ["X1", "Y1", "Z1"] or f[4][-3:] != ["X25", "Y25", "Z25"] or len(f[4]) != 2 + 3 * 25:
        fail(f"TRC line 5: {f[4][:6]}...")
    if lines[5] != "":
        fail("TRC line 6 must be empty")
    rows = [r for r in f[6:] if r != [""]]
    if len(rows) != n:
        fail(f"TRC: {len(rows)} data rows for NumFrames {n}")
    worst = 0.0
    for i, (r, p, s) in enumerate(zip(rows, poses, states)):
        if len(r) != 2 + 75 or int(r[0]) != i + 1 or abs(float(r[1]) - i / rate) > 2e-6:
            fail(f"TRC row {i + 1}: {r[:3]}")
        if s == "missing":
            if any(r[2:]):
                fail(f"TRC row {i + 1}: a flagged frame must leave its marker fields empty")
            continue
        if s == "filled":
            continue  # interpolated: not the estimate's own values
        for j, name in enumerate(NAMES):
            want = y_up([float(p[f"{name}_{a}"]) for a in "xyz"])
            got = [float(v) for v in r[2 + 3 * j:5 + 3 * j]]
            worst = max(worst, math.dist(want, got))
    if worst > 0.01:
        fail(f"TRC: a marker is {worst:.4f} mm from the estimate")
    return {"rows": len(rows), "max_mm": round(worst, 4)}


class C3d:
    def __init__(self, path):
        self.b = open(path, "rb").read()

    def word(self, k):  # 1-based 16-bit word of the header
        return struct.unpack_from("<h", self.b, 2 * (k - 1))[0]

    def float_word(self, k):
        return struct.unpack_from("<f", self.b, 2 * (k - 1))[0]

    def parameters(self):
        start = (self.b[0] - 1) * 512
        if self.b[start + 1] != 0x50 or self.b[start + 3] != 84:
            fail(f"C3D parameter header: key {self.b[start + 1]:#x}, processor {self.b[start + 3]} (want 0x50, 84 = Intel)")
        blocks = self.b[start + 2]
        end = start + blocks * 512
        groups, params, at = {}, {}, start + 4
        while True:
            name_len = abs(struct.unpack_from("b", self.b, at)[0])
            gid = struct.unpack_from("b", self.b, at + 1)[0]
            name = self.b[at + 2:at + 2 + name_len].decode()
            next_at = at + 2 + name_len
            nxt = struct.unpack_from("<h", self.b, next_at)[0]
            body = next_at + 2
            if gid < 0:
                groups[-gid] = name
            else:
                kind, ndim = struct.unpack_from("bB", self.b, body)
                dims = list(self.b[body + 2:body + 2 + ndim])
                data_at = body + 2 + ndim
                count = math.prod(dims) if dims else 1
                size = abs(kind) * count
                raw = self.b[data_at:data_at + size]
                if kind == -1:
                    width = dims[0] if dims else 1
                    value = [raw[i:i + width].decode().rstrip() for i in range(0, len(raw), width)] if len(dims) > 1 else raw.decode()
                elif kind == 2:
                    value = struct.unpack(f"<{count}h", raw)
                elif kind == 4:
                    value = struct.unpack(f"<{count}f", raw)
                else:
                    value = raw
                if isinstance(value, tuple) and len(value) == 1:
                    value = value[0]
                params[(gid, name)] = value
            if nxt == 0:
                break
            at = next_at + nxt
            if not start < at < end:
                fail(f"C3D parameter chain leaves the parameter section at byte {at}")
        return blocks, {f"{groups[g]}:{n}": v for (g, n), v in params.items()}


def check_c3d(path, poses, states, fps):
    c = C3d(path)
    n = len(poses)
    if len(c.b) % 512:
        fail("C3D size is not a whole number of 512-byte blocks")
    if c.b[0] != 2 or c.b[1] != 0x50:
        fail(f"C3D header word 1: {c.b[0]}, {c.b[1]:#x} (want parameter block 2, key 0x50)")
    header = {"points": c.word(2), "analog": c.word(3), "first": c.word(4), "last": c.word(5) & 0xFFFF,
              "scale": c.float_word(7), "data_start": c.word(9), "analog_per_frame": c.word(10), "rate": c.float_word(11),
              "word150": c.word(150)}
    if (header["points"] != 25 or header["analog"] != 0 or header["first"] != 1 or header["last"] != n or header["scale"] >= 0
            or abs(header["rate"] - fps) > 0.01 or header["word150"] != 0x3039):
        fail(f"C3D header record: {header}")
    blocks, p = c.parameters()
    want = {"POINT:USED": 25, "POINT:FRAMES": n, "POINT:DATA_START": header["data_start"], "POINT:UNITS": "mm",
            "ANALOG:USED": 0}
    for k, v in want.items():
        if p.get(k) != v:
            fail(f"C3D parameter {k} = {p.get(k)!r}, want {v!r}")
    if abs(p["POINT:RATE"] - header["rate"]) > 1e-6 or abs(p["POINT:SCALE"] - header["scale"]) > 1e-9:
        fail(f"C3D POINT:RATE {p['POINT:RATE']} / SCALE {p['POINT:SCALE']} disagree with the header")
    if p["POINT:LABELS"] != NAMES:
        fail(f"C3D POINT:LABELS {p['POINT:LABELS']}")
    if header["data_start"] != 2 + blocks:
        fail(f"C3D data starts at block {header['data_start']}, after {blocks} parameter blocks it should be {2 + blocks}")
    at = (header["data_start"] - 1) * 512
    worst, counts = 0.0, {"measured": 0, "filled": 0, "missing": 0}
    for i, (pose, s) in enumerate(zip(poses, states)):
        for j, name in enumerate(NAMES):
            x, y, z, res = struct.unpack_from("<4f", c.b, at + 16 * (25 * i + j))
            want_res = {"missing": -1.0, "filled": 0.0}.get(s)
            if (want_res is not None and res != want_res) or (want_res is None and res <= 0):
                fail(f"C3D frame {i + 1} {name}: residual {res} for a {s} frame")
            if s == "measured":
                worst = max(worst, math.dist(y_up([float(pose[f"{name}_{a}"]) for a in "xyz"]), (x, y, z)))
        counts[s] += 1
    if at + 16 * 25 * n > len(c.b):
        fail("C3D data section is short")
    if worst > 0.01:
        fail(f"C3D: a point is {worst:.4f} mm from the estimate")
    return {"header": header, "parameter_blocks": blocks, "max_mm": round(worst, 4), "frames": counts}


def main():
    poses_path, gaps_path, trc, c3d = sys.argv[1:5]
    fps = float(sys.argv[sys.argv.index("--fps") + 1])
    poses = list(csv.DictReader(open(poses_path)))
    states = json.load(open(gaps_path))["frames"]
    if len(poses) != len(states):
        fail(f"{len(poses)} poses, {len(states)} gap states")
    print(json.dumps({"trc": check_trc(trc, poses, states, fps), "c3d": check_c3d(c3d, poses, states, fps)}))


main()
