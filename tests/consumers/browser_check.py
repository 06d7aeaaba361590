#!/usr/bin/python3
"""Loads hullpose-web's page in headless Chromium and checks that the skeleton is drawn.

usage: browser_check.py URL SCREENSHOT.png [--min-skeletons N] [--timeout-s S] [--hull | --no-hull]

Chromium is driven over the DevTools protocol on a pipe (--remote-debugging-pipe: JSON messages
ending in NUL on file descriptors 3 and 4), so nothing but the Python standard library and PIL
is needed. Steps: open the page; wait until window.hullpose has counted N skeletons (page state);
pause the view, wait for a drawn frame, read the projected joints and bone midpoints; take a
screenshot; then every long bone's midpoint must show the bone colour and every joint must be
drawn (not background). --hull (the fusion host sends HULL): first wait for 2 hulls, and with
the hull shown, most sampled voxel centres of the drawn hull not under the drawn skeleton must
show the hull's colour (lit: a shade of it) in a screenshot of their own (SCREENSHOT-hull.png); then hide it with the page's
toggle and check the skeleton as above. --no-hull: the page must have received no hull at all.
Prints a JSON summary; exits 1 on failure.
"""
import base64, fcntl, io, json, math, os, shutil, subprocess, sys, tempfile, time

from PIL import Image

BACKGROUND = (0x15, 0x18, 0x1C)


class Browser:
    def __init__(self, profile):
        to_chrome_r, self.to_chrome = os.pipe()
        self.from_chrome, from_chrome_w = os.pipe()
        exe = shutil.which("chromium") or shutil.which("chromium-browser")
        if not exe:
            sys.exit("FAIL: chromium not found (Debian package 'chromium', deploy/packages.txt)")
        flags = ["--headless=new", "--remote-debugging-pipe", "--no-sandbox", "--no-first-run", "--disable-gpu",
                 "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--window-size=1280,800", "--hide-scrollbars",
                 f"--user-data-dir={profile}", "about:blank"]
        # Chromium reads commands from fd 3 and writes replies to fd 4; bash puts the pipe ends there.
        # (moved above 9 first: the pipe's own numbers may be 3 or 4)
        r, w = fcntl.fcntl(to_chrome_r, fcntl.F_DUPFD, 10), fcntl.fcntl(from_chrome_w, fcntl.F_DUPFD, 10)
        os.close(to_chrome_r)
        os.close(from_chrome_w)
        shell = f'exec "$0" "$@" 3<&{r} 4>&{w} {r}<&- {w}>&-'
        self.proc = subprocess.Popen(["bash", "-c", shell, exe, *flags], pass_fds=(r, w), stdout=subprocess.DEVNULL,
                                     stderr=open(os.path.join(profile, "chromium.log"), "w"))
        os.close(r)
        os.close(w)
        self.next_id, self.buffer, self.session = 0, b"", None

    def send(self, method, params=None, session=True):
        self.next_id += 1
        msg = {"id": self.next_id, "method": method, "params": params or {}}
        if session and self.session:
            msg["sessionId"] = self.session
        os.write(self.to_chrome, json.dumps(msg).encode() + b"\0")
        while True:
            reply = self.read()
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})

    def read(self):
        while b"\0" not in self.buffer:
            chunk = os.read(self.from_chrome, 1 << 16)
            if not chunk:
                sys.exit("FAIL: chromium closed the DevTools pipe (see chromium.log)")
            self.buffer += chunk
        msg, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(msg)

    def evaluate(self, expression):
        r = self.send("Runtime.evaluate", {"expression": expression, "awaitPromise": True, "returnByValue": True})
        if "exceptionDetails" in r:
            raise RuntimeError(f"page: {r['exceptionDetails']}")
        return r["result"].get("value")

    def close(self):
        try:
            self.send("Browser.close", session=False)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()


SKELETON_PX = 8


def near(c, ref, tol=12):
    return all(abs(a - b) <= tol for a, b in zip(c, ref))


def main():
    url, shot = sys.argv[1], sys.argv[2]
    min_skeletons = int(sys.argv[sys.argv.index("--min-skeletons") + 1]) if "--min-skeletons" in sys.argv else 10
    timeout = float(sys.argv[sys.argv.index("--timeout-s") + 1]) if "--timeout-s" in sys.argv else 60
    want_hull, no_hull = "--hull" in sys.argv, "--no-hull" in sys.argv
    hull_png, hull_proj = None, None
    profile = tempfile.mkdtemp(prefix="hullpose-chromium.")
    b = Browser(profile)
    try:
        targets = b.send("Target.getTargets", session=False)["targetInfos"]
        page = next(t for t in targets if t["type"] == "page")
        b.session = b.send("Target.attachToTarget", {"targetId": page["targetId"], "flatten": True}, session=False)["sessionId"]
        b.send("Page.enable")
        b.send("Page.navigate", {"url": url})
        deadline = time.monotonic() + timeout  # a bound on waiting, not a timing assertion
        state = None
        while time.monotonic() < deadline:
            state = b.evaluate("window.hullpose ? {skeletons: hullpose.skeletons, valid: hullpose.valid, invalid: hullpose.invalid,"
                               " statuses: hullpose.statuses, cameras: document.querySelectorAll('#cameras tbody tr').length,"
                               " rig: !!hullpose.rig, hulls: hullpose.hulls} : null")
            if state and state["skeletons"] >= min_skeletons and state["valid"] > 0 and (not want_hull or state["hulls"] >= 2):
                break
            time.sleep(0.1)
        if not state or state["skeletons"] < min_skeletons:
            sys.exit(f"FAIL: the page counted {state and state['skeletons']} skeletons, expected >= {min_skeletons}")
        if want_hull:
            # The hull shown, the view frozen: where its voxels are on screen, and how they look.
            hull_proj = b.evaluate("""(async () => {
                hullpose.setHull(true); hullpose.pause(); await hullpose.rendered();
                return {points: hullpose.projectedHull(200), colour: hullpose.hullColour, shown: hullpose.hullShown.occupied,
                        panel: document.getElementById('panel').getBoundingClientRect().toJSON(), skeleton: hullpose.projected()};
            })()""")
            hull_png = base64.b64decode(b.send("Page.captureScreenshot", {"format": "png"})["data"])
            b.evaluate("(async () => { hullpose.setHull(false); hullpose.resume(); await hullpose.rendered(); })()")
        # Freeze the view on a valid pose, then read where its joints are on screen.
        proj = b.evaluate("""(async () => {
            for (let i = 0; i < 200 && !(hullpose.shown && hullpose.shown.valid); ++i) await hullpose.rendered();
            hullpose.pause(); await hullpose.rendered();
            return {proj: hullpose.projected(), colour: hullpose.boneColour,
                    banner: document.getElementById('banner').textContent, latency: document.getElementById('latency').textContent,
                    panel: document.querySelector('#cameras tbody').innerText};
        })()""")
        png = base64.b64decode(b.send("Page.captureScreenshot", {"format": "png"})["data"])
    finally:
        b.close()
    with open(shot, "wb") as f:
        f.write(png)
    hull_summary, problems = {}, []
    if want_hull:
        hull_shot = shot[:-4] + "-hull.png" if shot.endswith(".png") else shot + "-hull.png"
        with open(hull_shot, "wb") as f:
            f.write(hull_png)
        himg = Image.open(io.BytesIO(hull_png)).convert("RGB")
        hc = hull_proj["colour"]
        ref = ((hc >> 16) & 255, (hc >> 8) & 255, hc & 255)
        p = hull_proj["panel"]

        def is_hull(c):  # the hull's colour times a shade in (0, 1]: same ratios, not dark
            return c[2] >= 40 and abs(c[0] / c[2] - ref[0] / ref[2]) < 0.08 and abs(c[1] / c[2] - ref[1] / ref[2]) < 0.08

        # The skeleton is drawn with the hull and may be a few frames ahead of it (the view
        # freezes on the latest of each; 3 in the failing run), so a limb can cover hull voxels: samples within
        # SKELETON_PX of a drawn bone or joint (joint spheres 22 mm, about 5 px in this view) are
        # not the hull's to show. Without this the check failed on 177 of 200 in one CI run.
        skel = hull_proj["skeleton"] or {"joints": [], "bones": []}
        at = {j["name"]: (j["x"], j["y"]) for j in skel["joints"]}
        segments = [(at[a], at[b]) for a, b in (bone["name"].split("-") for bone in skel["bones"])]

        def near_skeleton(q):
            for (ax, ay), (bx, by) in segments:
                dx, dy = bx - ax, by - ay
                t = max(0.0, min(1.0, ((q["x"] - ax) * dx + (q["y"] - ay) * dy) / (dx * dx + dy * dy or 1)))
                if math.hypot(q["x"] - ax - t * dx, q["y"] - ay - t * dy) <= SKELETON_PX:
                    return True
            return False

        seen = [q for q in hull_proj["points"] if 0 <= q["x"] < himg.size[0] and 0 <= q["y"] < himg.size[1]
                and not (p["left"] <= q["x"] <= p["right"] and p["top"] <= q["y"] <= p["bottom"])
                and not near_skeleton(q)]
        hits = [q for q in seen if is_hull(himg.getpixel((int(q["x"]), int(q["y"]))))]
        hull_summary = {"hulls": state["hulls"], "hull_voxels": hull_proj["shown"], "hull_points": len(seen),
                        "hull_drawn": len(hits), "hull_screenshot": hull_shot}
        if len(seen) < 20:
            problems.append(f"only {len(seen)} hull voxels project into the view")
        if len(hits) < 0.9 * len(seen):
            problems.append(f"hull colour at {len(hits)} of {len(seen)} hull voxel centres")
        if is_hull(himg.getpixel((himg.size[0] - 3, himg.size[1] - 3))):
            problems.append("the screen corner has the hull colour: the check cannot tell")
    if no_hull and state["hulls"] != 0:
        problems.append(f"the page received {state['hulls']} hulls with the hull channel off")
    img = Image.open(io.BytesIO(png)).convert("RGB")
    w, h = img.size
    colour = ((proj["colour"] >> 16) & 255, (proj["colour"] >> 8) & 255, proj["colour"] & 255)

    def window(x, y, r=2):
        return [img.getpixel((min(w - 1, max(0, int(x) + dx)), min(h - 1, max(0, int(y) + dy))))
                for dx in range(-r, r + 1) for dy in range(-r, r + 1)]

    joints = {j["name"]: j for j in proj["proj"]["joints"]}
    long_bones = []
    for bone in proj["proj"]["bones"]:
        a, c = (joints[n] for n in bone["name"].split("-"))
        if ((a["x"] - c["x"]) ** 2 + (a["y"] - c["y"]) ** 2) ** 0.5 >= 20:  # long enough on screen to be seen past the joints
            long_bones.append(bone)
    on_screen = [p for p in long_bones if 0 <= p["x"] < w and 0 <= p["y"] < h]
    bone_hits = [p["name"] for p in on_screen if any(near(c, colour) for c in window(p["x"], p["y"]))]
    joint_hits = [j["name"] for j in joints.values() if 0 <= j["x"] < w and 0 <= j["y"] < h
                  and any(not near(c, BACKGROUND, 6) for c in window(j["x"], j["y"], 1))]
    # A pixel of a screen corner is no bone: the check can tell drawn from not drawn.
    corner_is_bone = near(img.getpixel((w - 3, h - 3)), colour)
    summary = {"state": state, "banner": proj["banner"], "latency": proj["latency"], "panel_rows": state["cameras"],
               "long_bones": len(long_bones), "bones_on_screen": len(on_screen), "bones_drawn": len(bone_hits),
               "joints_drawn": len(joint_hits), "screenshot": shot, "size": [w, h], **hull_summary}
    print(json.dumps(summary))
    shutil.rmtree(profile, ignore_errors=True)
    if len(on_screen) < 8:
        problems.append(f"only {len(on_screen)} long bones project into the view")
    if len(bone_hits) < 0.9 * len(on_screen):
        problems.append(f"bone colour at {len(bone_hits)} of {len(on_screen)} bone midpoints: missing "
                        f"{sorted(set(p['name'] for p in on_screen) - set(bone_hits))}")
    if len(joint_hits) < 0.9 * len(joints):
        problems.append(f"only {len(joint_hits)} of {len(joints)} joints drawn")
    if corner_is_bone:
        problems.append("the screen corner has the bone colour: the check cannot tell")
    if problems:
        sys.exit("FAIL: " + "; ".join(problems))


main()
