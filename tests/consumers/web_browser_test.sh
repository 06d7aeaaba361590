#!/usr/bin/env bash
# hullpose-web in a real browser: consumers_sim_rig publishes SKELETON and STATUS over real LCM
# (loopback multicast), hullpose-web serves the page, headless Chromium loads it
# (browser_check.py): skeletons must arrive (page state), the panel must list the nodes, and the
# screenshot must show the bone colour at the projected bones. Then the same page plays back a
# recorded take (--play of an lcm-logger log of that traffic).
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
/usr/bin/python3 "$here/browser_check.py" "$(field "$work/web.json" url)" "$shots/web.png" --min-skeletons 30 | tee "$work/live.json"
grep -q '"panel_rows": 9' "$work/live.json" || { echo "FAIL: the panel does not list 8 cameras + the fusion host"; exit 1; }
kill "$rig" "$web"; wait "$rig" "$web" 2>/dev/null || true
kill -INT "$logger"; wait "$logger" || true

# Playback of the recorded take, no LCM.
"$build/tools/web/hullpose-web" --rig "$work/rig.yaml" --play "$work/take.lcmlog" --port 0 --ready-file "$work/play.json" \
  2> "$work/play.log" & play=$!; pids+=($play)
wait_for_data "$work/play.json"
/usr/bin/python3 "$here/browser_check.py" "$(field "$work/play.json" url)" "$shots/web-playback.png" --min-skeletons 10
echo "PASS: screenshots in $shots"
