#!/usr/bin/env bash
# The Debian packages of a build, as a board gets them (issue 17): cpack makes them from the
# install() rules; lintian reports nothing beyond deploy/debian/lintian-overrides.txt; they hold
# only the files of the packaging plan; unpacked into a throw-away root (with systemd's own units,
# as on a Debian board) the units pass `systemd-analyze verify`; and a rig runs from that root —
# the trigger master, 4 camera nodes and the fusion host started from their installed units'
# command lines (tests/deploy/run_unit.py), with the installed /etc/hullpose files edited the way
# the README tells a person to — and publishes one skeleton per trigger, authenticated with a rig
# key made by the installed hullpose-rig-key (a listener with another key hears nothing), to a
# listener and to the installed web view (hullpose-web.service, serving the installed page).
# usage: package_test.sh BUILD_DIR [FRAMES=10] [RATE=5]
set -euo pipefail
build=$(cd "$1" && pwd)
frames=${2:-10} rate=${3:-5} num=4
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
source "$here/../system/proc_lib.sh"
proc_init package-test
root=$work/root
fail() { echo "FAIL: $*"; exit 1; }

# 1. The packages.
# gzip instead of the packages' xz: the same files, compressed faster (a test, not a release).
(cd "$build" && cpack -G DEB -D CPACK_DEBIAN_COMPRESSION_TYPE=gzip -B "$work/packages" > "$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack"; }
debs=("$work"/packages/*.deb)
names=$(for d in "${debs[@]}"; do dpkg-deb -f "$d" Package; done | sort | tr '\n' ' ')
[[ $names == "hullpose-camera-node hullpose-common hullpose-consumers hullpose-fusion-host hullpose-tools hullpose-trigger-master " ]] \
  || fail "packages: $names"
echo "packages: $names"

# 2. lintian: nothing but the tags explained in the overrides file.
lintian --fail-on error,warning --suppress-tags-from-file "$src/deploy/debian/lintian-overrides.txt" "${debs[@]}" > "$work/lintian.log" 2>&1 || { cat "$work/lintian.log"; fail "lintian"; }
if grep -E '^[EWI]: ' "$work/lintian.log"; then fail "lintian reports the lines above"; fi
echo "lintian: clean (with deploy/debian/lintian-overrides.txt)"

# 3. Nothing else of the build tree: every file is on the packaging plan's paths.
for d in "${debs[@]}"; do dpkg-deb -c "$d"; done | awk '$1 !~ /^d/ {print $6}' | sed 's|^\./||' > "$work/files.txt"
if grep -v -E '^(usr/bin/hullpose-[a-z-]+|usr/lib/systemd/system/hullpose-[a-z-]+@?\.service|usr/lib/(sysusers|sysctl)\.d/[a-z0-9-]+\.conf|usr/lib/udev/rules\.d/60-hullpose-gpio\.rules|usr/share/doc/hullpose-[a-z-]+/(copyright|changelog\.Debian\.gz|README\.deploy\.md)|usr/share/hullpose/web/(index\.html|app\.js)|etc/hullpose/[a-z0-9-]+\.(conf|yaml))$' "$work/files.txt"; then
  fail "files outside the packaging plan (above)"
fi
for d in "${debs[@]}"; do
  conf=$(dpkg-deb -I "$d" conffiles 2>/dev/null || true)
  for f in $(dpkg-deb -c "$d" | awk '{print $6}' | sed -n 's|^\./etc/|/etc/|p' | grep -v '/$'); do
    grep -qx "$f" <<<"$conf" || fail "$f of $(basename "$d") is not a conffile"
  done
done
for d in "${debs[@]}"; do
  mkdir -p "$work/control/$(basename "$d")" && dpkg-deb -e "$d" "$work/control/$(basename "$d")"
  for s in postinst prerm postrm; do
    sh -n "$work/control/$(basename "$d")/$s" || fail "$s of $(basename "$d") is not valid sh"
  done
done
echo "files: $(wc -l < "$work/files.txt") files, all on the plan; /etc files are conffiles; maintainer scripts parse"

# 4. A throw-away root: systemd's own units (as on any Debian board) + the unpacked packages.
mkdir -p "$root/usr/lib/systemd"
cp -a /lib/systemd/system "$root/usr/lib/systemd/"
for d in "${debs[@]}"; do dpkg-deb -x "$d" "$root"; done
units=(hullpose-trigger-master.service hullpose-fusion-host.service hullpose-camera-node@3.service hullpose-web.service)
if ! systemd-analyze verify --root="$root" "${units[@]}" > "$work/verify.log" 2>&1 || [[ -s $work/verify.log ]]; then
  cat "$work/verify.log"; fail "systemd-analyze verify"
fi
echo "systemd-analyze verify: ${units[*]} clean"
# Every installed program starts (its libraries resolve) and answers --help.
for p in "$root"/usr/bin/*; do "$p" --help > /dev/null 2>&1 || fail "$(basename "$p") --help"; done
echo "programs: $(ls "$root/usr/bin" | wc -l) installed, each answers --help"

# 5. The rig from the installed files. Data: a rendered walk for a 4-camera ring (hullpose-synth).
bin=$root/usr/bin etc=$root/etc/hullpose
"$bin/hullpose-synth" --motion walk --frames "$frames" --fps "$rate" --rig "ring:cameras=$num,ceiling=0" \
  --out "$work/data" --seed 1 > /dev/null
cp "$work/data/rig.yaml" "$etc/rig.yaml"  # "copy the calibrated rig.yaml to /etc/hullpose/"
# "make the rig's key once, copy it to every board" (HULLPOSE_RIG_KEY and lcm.rig_key name it).
"$bin/hullpose-rig-key" --output "$etc/rig.key" > /dev/null
[[ $(stat -c %a "$etc/rig.key") == 600 ]] || fail "rig key mode $(stat -c %a "$etc/rig.key"), not 600"
"$bin/hullpose-rig-key" --output "$work/other.key" > /dev/null  # an intruder's
rig_id=$(sed -n 's/^rig_id: *//p' "$etc/rig.yaml" | tr -d '"')
port=$(( 7600 + $$ % 200 ))
url="udpm://239.255.76.67:$port?ttl=0&recv_buf_size=1048576"  # this machine only
sed_url=${url//&/\\&}  # '&' is the match in a sed replacement
# The edits of the README's steps, on the installed files: LCM URL and rig id, the trigger line
# (here the simulated wire), the fusion host's options, one camera file per camera.
sed -i "s|^HULLPOSE_LCM_URL=.*|HULLPOSE_LCM_URL=\"$sed_url\"|; s|^HULLPOSE_RIG_ID=.*|HULLPOSE_RIG_ID=$rig_id|" "$etc/hullpose.conf"
sed -i "s|^HULLPOSE_TRIGGER_LINE=.*|HULLPOSE_TRIGGER_LINE=wire:$work/wire.sock|; s|^HULLPOSE_TRIGGER_RATE=.*|HULLPOSE_TRIGGER_RATE=$rate|;
        s|^HULLPOSE_TRIGGER_ARGS=.*|HULLPOSE_TRIGGER_ARGS=\"--count $frames --wait-nodes $num\"|" "$etc/trigger-master.conf"
sed -i "s|^HULLPOSE_FUSION_ARGS=\"|HULLPOSE_FUSION_ARGS=\"--duration-s 120 --ready-file $work/host.ready --max-open 16 |;
        s|--min-cameras [0-9]*|--min-cameras $num|; s|--deadline-ms [0-9]*|--deadline-ms 500|; s|--resolution [0-9]*|--resolution 64|" "$etc/fusion-host.conf"
for ((c = 0; c < num; c++)); do
  # A simulated sensor on the wire: the rendered masks, passed through (threshold).
  sed -e "s|^camera_id: .*|camera_id: $c|" \
      -e "s|^source: .*|source: { type: file, path: \"$work/data/cam$c/mask_%06d.png\" }|" \
      -e "s|^bgs: .*|bgs: { method: threshold, learn_frames: 1 }|" \
      -e "s|^post: .*|post: { open_radius: 0, close_radius: 0, min_blob_area: 0, max_hole_area: 0 }|" \
      -e "s|url: \"[^\"]*\"|url: \"$sed_url\"|" \
      -e "s|^  edges: gpiod|  edges: wire|; s|^  chip: .*|  path: \"$work/wire.sock\"|; s|^  line: .*|  connect_timeout_ms: 60000|" \
      "$etc/camera0.yaml" > "$etc/camera$c.yaml.new"
  mv "$etc/camera$c.yaml.new" "$etc/camera$c.yaml"
done
# The web view on this machine only, on a free port; a marker in the installed page shows that
# the page came from the package, not from the source tree.
sed -i "s|^HULLPOSE_WEB_ARGS=.*|HULLPOSE_WEB_ARGS=\"--port 0 --bind 127.0.0.1 --ready-file $work/web.ready\"|" "$etc/web.conf"
echo "<!-- installed page -->" >> "$root/usr/share/hullpose/web/index.html"
run_unit() { local log=$1; shift; "$here/run_unit.py" "$root" "$@" --pre-log "$work/pre.log" 2> "$log" & pids+=($!); }

"$bin/hullpose-listen" --lcm-url "$url" --format none --count "$frames" --estimates "$work/live.csv" \
  --rig-key "$etc/rig.key" --summary "$work/summary.json" --duration-s 120 --ready-file "$work/listen.ready" \
  2> "$work/listen.log" & listener=$!
pids+=($listener)
"$bin/hullpose-listen" --lcm-url "$url" --format none --rig-key "$work/other.key" --duration-s 120 \
  --ready-file "$work/intruder.ready" 2> "$work/intruder.log" & intruder=$!
pids+=($intruder)
run_unit "$work/host.log" hullpose-fusion-host.service
run_unit "$work/web.log" hullpose-web.service
wait_for "$work/listen.ready" 30; wait_for "$work/intruder.ready" 30; wait_for "$work/host.ready" 30
wait_for "$work/web.ready" 30
web_port=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["port"])' "$work/web.ready")
/usr/bin/python3 "$here/web_client.py" "$web_port" "$frames" "$work/web.json" 2> "$work/web_client.log" & web_client=$!
pids+=($web_client)
wait_for "$work/web.json.ready" 30
run_unit "$work/master.log" hullpose-trigger-master.service; master=${pids[-1]}
wait_for "$work/wire.sock" 30
for ((c = 0; c < num; c++)); do run_unit "$work/cam$c.log" hullpose-camera-node@.service --instance "$c"; done
wait "$master" || { cat "$work/master.log" "$work"/cam*.log; fail "trigger master (from its unit)"; }
wait "$listener" || true
wait "$web_client" || { cat "$work/web_client.log" "$work/web.log"; fail "web view (from its unit)"; }
kill -TERM "$intruder"; wait "$intruder" || true
grep -q 'hullpose-doctor --startup' "$work/pre.log" || fail "the units' start-up checks did not run"
/usr/bin/python3 - "$work" "$frames" <<'PY'
import csv, sys
work, frames = sys.argv[1], int(sys.argv[2])
seqs = sorted(int(r["frame"]) for r in csv.DictReader(open(f"{work}/live.csv")))
print(f"rig from the installed units: {len(seqs)} skeletons for {frames} triggers")
if seqs != list(range(frames)):
    print(f"FAIL: sequences {seqs}, expected 0..{frames - 1} once each"); sys.exit(1)
PY
grep -q 'installed page' "$work/web.json.page" || fail "hullpose-web did not serve the installed page"
echo "web view from the installed unit and page: $(cat "$work/web.json")"
# The rig is keyed: a listener with another key drops every message as from another key.
grep -Eq 'auth_wrong_key=[1-9]' "$work/intruder.log" && grep -q '"skeletons":0,' "$work/intruder.log" \
  || { cat "$work/intruder.log"; fail "a listener with another rig key heard the rig"; }
echo "rig key: a listener with another key received nothing ($(grep -Eo 'auth_wrong_key=[0-9]+' "$work/intruder.log"))"
# The recorded take exported by the installed hullpose-export.
"$bin/hullpose-export" --in "$work/live.csv" --fps "$rate" --bvh "$work/take.bvh" > /dev/null 2>&1 || fail "hullpose-export"
grep -q '^MOTION' "$work/take.bvh" || fail "hullpose-export wrote no BVH motion"
echo "export: $(sed -n 's/^Frames: *//p' "$work/take.bvh") BVH frames from the recorded take"
echo "start-up checks on this machine (ExecStartPre, advisory here):"
grep -E '^\[(FAIL|warn)\]' "$work/pre.log" | sort | uniq -c | sed 's/^/  /' || true
echo PASS
