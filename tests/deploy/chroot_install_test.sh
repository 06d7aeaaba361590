#!/usr/bin/env bash
# The packages' maintainer scripts on a real Debian 12 system: mmdebstrap makes a minimal amd64
# root with the packages' dependencies (downloads ~150 MB, a few minutes: not part of make test),
# then dpkg installs the packages there (hullpose user and groups created), reinstalls them (the
# upgrade path), removes and purges them. Needs root and mmdebstrap.
# usage: chroot_install_test.sh PACKAGES_DIR   (e.g. build-package/packages)
set -euo pipefail
pkgs=$(cd "$1" && pwd)
root=$(mktemp -d /tmp/hullpose-chroot.XXXXXX)
trap 'rm -rf "$root"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
deps=$(for d in "$pkgs"/*.deb; do dpkg-deb -f "$d" Depends; done | tr ',' '\n' | sed 's/(.*)//; s/ //g' \
  | grep -v '^hullpose' | sort -u | paste -sd,)
mmdebstrap --quiet --variant=apt --include="$deps,systemd" bookworm "$root" \
  "deb http://deb.debian.org/debian bookworm main" "deb http://deb.debian.org/debian-security bookworm-security main"
mkdir -p "$root/tmp/pk" && cp "$pkgs"/*.deb "$root/tmp/pk/"
chroot "$root" sh -c 'dpkg -i /tmp/pk/*.deb' || fail "dpkg -i"
chroot "$root" id hullpose | grep -q '(video)' || fail "hullpose not in group video"
chroot "$root" id hullpose | grep -q '(gpio)' || fail "hullpose not in group gpio"
[[ $(chroot "$root" getent passwd hullpose | cut -d: -f7) == /usr/sbin/nologin ]] || fail "hullpose has a login shell"
chroot "$root" dpkg -s hullpose-common | grep -q '/etc/hullpose/hullpose.conf' || fail "hullpose.conf is not a conffile"
chroot "$root" sh -c 'dpkg -i /tmp/pk/*.deb' > /dev/null || fail "reinstall (upgrade path)"
rc=0; chroot "$root" hullpose-doctor --role fusion-host > /dev/null || rc=$?
((rc <= 1)) || fail "hullpose-doctor exit status $rc"
chroot "$root" dpkg -r hullpose-camera-node hullpose-tools hullpose-trigger-master hullpose-fusion-host || fail "dpkg -r"
chroot "$root" dpkg -P hullpose-common || fail "dpkg -P"
[[ ! -e $root/etc/hullpose/hullpose.conf ]] || fail "purge left hullpose.conf"
echo PASS
