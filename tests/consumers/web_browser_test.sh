#!/usr/bin/env bash
# hullpose-web in a real browser: consumers_sim_rig publishes SKELETON and STATUS over real LCM
# (loopback multicast), hullpose-web serves the page, headless Chromium loads it
# (browser_check.py): skeletons must arrive (page state), the panel must list the nodes, and the
# screenshot must show the bone colour at the projected bones; the hull channel is off, so the
# page must get no hull and the lcm-logger log of the traffic no HULL event. Then the rig runs
# again with --hull-rate (the fusion host's HullPublisher): the page must draw the hull (page
# state + hull-coloured pixels at its voxels, web-hull.png) and, toggled off, the skeleton. Last,
# the same page plays back the recorded take (--play of that lcm-logger log).
# usage: web_browser_test.sh BUILD_DIR [SCREENSHOT_DIR]   (KEEP_WORK=1 keeps the work dir)
set -euo pipefail
build=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
source "$here/../system/proc_lib.sh"
proc_init web
shots=${2:-$work}
mkdir -p "$shots"
port=$(( 7600 + $$ % 300 ))
url="udpm://239.255.76.69:$port?ttl=0"
field() { /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }

# Live: the rig file first (hullpose-web draws its cameras), then the server, then the rig.
"$build/tests/consumers/consumers_sim_rig" --lcm-url "$url" --count 0 --rig-out "$work/rig.yaml"
lcm-logger --lcm-url="$url" -f "$work/take.lcmlog" 2> "$work/logger.log" & logger=$!; pids+=($logger)
"$build/tools/web/hullpose-web" --rig "$work/rig.yaml" --lcm-url "$url" --port 0 --ready-file "$work/web.json" \
  2> "$work/web.log" & web=$!; pids+=($web)
wait_for_data "$work/web.json"
"$build/tests/consumers/consumers_sim_rig" --lcm-url "$url" --rate 30 --count 100000 2> "$work/rig.log" & rig=$!; pids+=($rig)
/usr/bin/python3 "$here/browser_check.py" "$(field "$work/web.json" url)" "$shots/web.png" --min-skeletons 30 --no-hull | tee "$work/live.json"
grep -q '"panel_rows": 9' "$work/live.json" || { echo "FAIL: the panel does not list 8 cameras + the fusion host"; exit 1; }
kill "$rig"; wait "$rig" 2>/dev/null || true
kill -INT "$logger"; wait "$logger" || true
# The log's channels (lcm-logger's event layout: sync, number, time, channel and data lengths).
/usr/bin/python3 - "$work/take.lcmlog" <<'PY'
import struct, sys
data, at, channels = open(sys.argv[1], "rb").read(), 0, {}
while at + 28 <= len(data):
    sync, _, _, clen, dlen = struct.unpack(">IqqII", data[at:at + 28])
    assert sync == 0xEDA1DA01, "bad lcm log"
    name = data[at + 28:at + 28 + clen].decode()
    channels[name] = channels.get(name, 0) + 1
    at += 28 + clen + dlen
print("logged channels (hull off):", channels)
sys.exit("FAIL: HULL was sent with the hull channel off" if "HULL" in channels or not channels.get("SKELETON") else 0)
PY

# The hull on: the rig publishes it through the fusion host's HullPublisher at 5 Hz, each hull
# followed by hostile ones (a bad field of each kind, and one cut short) that must be dropped.
"$build/tests/consumers/consumers_sim_rig" --lcm-url "$url" --rate 30 --count 100000 --hull-rate 5 --hostile-hulls \
  2> "$work/rig-hull.log" & rig=$!; pids+=($rig)
/usr/bin/python3 "$here/browser_check.py" "$(field "$work/web.json" url)" "$shots/web.png" --min-skeletons 30 --hull | tee "$work/live-hull.json"
kill "$rig" "$web"; wait "$rig" "$web" 2>/dev/null || true
for c in invalid_hull_bad_dims invalid_hull_bad_count invalid_hull_bad_geometry invalid_hull_bad_payload malformed_hull; do
  grep -q "hullpose-web: $c=[1-9]" "$work/web.log" || { echo "FAIL: hullpose-web did not count hostile hulls as $c"; cat "$work/web.log"; exit 1; }
done

# Playback of the recorded take, no LCM.
"$build/tools/web/hullpose-web" --rig "$work/rig.yaml" --play "$work/take.lcmlog" --port 0 --ready-file "$work/play.json" \
  2> "$work/play.log" & play=$!; pids+=($play)
wait_for_data "$work/play.json"
/usr/bin/python3 "$here/browser_check.py" "$(field "$work/play.json" url)" "$shots/web-playback.png" --min-skeletons 10
echo "PASS: screenshots in $shots"
