#!/usr/bin/env bash
# The packages' maintainer scripts on a real Debian 12 system: mmdebstrap makes a minimal amd64
# root with the packages' dependencies (downloads ~150 MB, a few minutes: not part of make test),
# then dpkg installs the packages there (hullpose user and groups created), reinstalls them (the
# upgrade path), removes and purges them. With OLD_PACKAGES_DIR, an older release is installed
# first and upgraded (files that moved between packages: Replaces/Breaks). The installed user
# reads a rig key made and installed as the README says, and no other user can.
# Needs root and mmdebstrap.
# usage: chroot_install_test.sh PACKAGES_DIR [OLD_PACKAGES_DIR]   (e.g. build-package/packages)
set -euo pipefail
pkgs=$(cd "$1" && pwd)
old=${2:+$(cd "$2" && pwd)}
root=$(mktemp -d /tmp/hullpose-chroot.XXXXXX)
trap 'rm -rf "$root"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
deps=$(for d in "$pkgs"/*.deb ${old:+"$old"/*.deb}; do dpkg-deb -f "$d" Depends; done | tr ',' '\n' | sed 's/(.*)//; s/ //g' \
  | grep -v '^hullpose' | sort -u | paste -sd,)
mmdebstrap --quiet --variant=apt --include="$deps,systemd" bookworm "$root" \
  "deb http://deb.debian.org/debian bookworm main" "deb http://deb.debian.org/debian-security bookworm-security main"
mkdir -p "$root/tmp/pk" && cp "$pkgs"/*.deb "$root/tmp/pk/"
if [[ -n $old ]]; then
  mkdir -p "$root/tmp/old" && cp "$old"/*.deb "$root/tmp/old/"
  chroot "$root" sh -c 'dpkg -i /tmp/old/*.deb' > /dev/null || fail "dpkg -i of the old packages"
  echo "installed the old release: $(cd "$old" && ls *.deb | tr '\n' ' ')"
fi
if [[ -n $old ]]; then
  # apt, as the README says: it orders the unpacks so a file that moved between packages
  # (Breaks + Replaces) changes hands; dpkg -i in name order would refuse.
  chroot "$root" sh -c 'apt-get install -y -q /tmp/pk/*.deb' > /dev/null || fail "apt-get install (upgrade)"
else
  chroot "$root" sh -c 'dpkg -i /tmp/pk/*.deb' || fail "dpkg -i"
fi
chroot "$root" id hullpose | grep -q '(video)' || fail "hullpose not in group video"
chroot "$root" id hullpose | grep -q '(gpio)' || fail "hullpose not in group gpio"
[[ $(chroot "$root" getent passwd hullpose | cut -d: -f7) == /usr/sbin/nologin ]] || fail "hullpose has a login shell"
chroot "$root" dpkg -s hullpose-common | grep -q '/etc/hullpose/hullpose.conf' || fail "hullpose.conf is not a conffile"
chroot "$root" sh -c 'dpkg -i /tmp/pk/*.deb' > /dev/null || fail "reinstall (same version)"
# The rig key as README "Deploying a rig" step 6 installs it: the service user reads it, others not.
chroot "$root" sh -c 'cd /tmp && hullpose-rig-key --output rig.key && install -o hullpose -g hullpose -m 600 rig.key /etc/hullpose/rig.key' > /dev/null \
  || fail "making and installing the rig key"
chroot "$root" runuser -u hullpose -- hullpose-rig-key --check /etc/hullpose/rig.key > /dev/null || fail "user hullpose cannot read the rig key"
chroot "$root" runuser -u nobody -- hullpose-rig-key --check /etc/hullpose/rig.key > /dev/null 2>&1 && fail "user nobody can read the rig key"
{ chroot "$root" runuser -u hullpose -- hullpose-doctor --role consumer --json || true; } | grep -A3 '"check": "rig.key"' | grep -q '"status": "ok"' \
  || fail "hullpose-doctor (as hullpose) does not find the rig key fine"
[[ -f $root/usr/share/hullpose/web/index.html ]] && [[ -f $root/usr/share/javascript/three/three.min.js ]] || fail "web page or libjs-three missing"
rc=0; chroot "$root" hullpose-doctor --role fusion-host > /dev/null || rc=$?
((rc <= 1)) || fail "hullpose-doctor exit status $rc"
chroot "$root" dpkg -r hullpose-camera-node hullpose-tools hullpose-trigger-master hullpose-fusion-host hullpose-consumers || fail "dpkg -r"
chroot "$root" dpkg -P hullpose-common || fail "dpkg -P"
[[ ! -e $root/etc/hullpose/hullpose.conf ]] || fail "purge left hullpose.conf"
echo PASS
