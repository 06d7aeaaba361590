#!/usr/bin/env bash
# Builds the arm64 sysroot the cross build compiles and links against and the qemu test run loads
# its libraries from: the target -dev packages of deploy/packages.txt (every lib*-dev, catch2,
# nlohmann-json3-dev; host tools excluded), unpacked by mmdebstrap (--variant=extract: no
# maintainer scripts, so no emulation) into SYSROOT.
#
# Why a sysroot and not `dpkg --add-architecture arm64` + the `:arm64` dev packages on the host:
# liblcm1 and liblcm-dev carry no `Multi-Arch: same`, so liblcm-dev:arm64 cannot be installed
# beside the host's liblcm-dev:amd64 (nor can libopencv-dev, the package with OpenCV's CMake
# config); a private tree also leaves the build machine's package set alone.
#
# usage: make-sysroot.sh SYSROOT [SUITE=bookworm] [MIRROR=http://deb.debian.org/debian]
# Idempotent: a SYSROOT whose .packages stamp matches the wanted list is kept.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
sysroot=$1 suite=${2:-bookworm} mirror=${3:-http://deb.debian.org/debian}
mapfile -t wanted < <(grep -E '^(lib[a-z0-9.+-]*-dev|catch2|nlohmann-json3-dev)\s*$' "$here/../packages.txt" \
  | grep -v -E '^libclang' | sed 's/\s*$//')
wanted=(libc6-dev libstdc++-12-dev "${wanted[@]}")
stamp="$suite ${wanted[*]}"
if [[ -f $sysroot/.packages && $(cat "$sysroot/.packages") == "$stamp" ]]; then
  echo "make-sysroot: $sysroot is up to date (${#wanted[@]} packages)"
  exit 0
fi
command -v mmdebstrap >/dev/null || { echo "make-sysroot: mmdebstrap missing (make cross installs deploy/cross/packages.txt)" >&2; exit 1; }
rm -rf "$sysroot"
mkdir -p "$(dirname "$sysroot")"
echo "make-sysroot: unpacking ${#wanted[@]} arm64 packages and their dependencies into $sysroot"
sources="deb $mirror $suite main
deb $mirror $suite-updates main
deb http://deb.debian.org/debian-security $suite-security main"
mmdebstrap --quiet --variant=extract --architectures=arm64 --include="$(IFS=,; echo "${wanted[*]}")" \
  "$suite" "$sysroot" - <<<"$sources"

# What the skipped maintainer scripts would have done and the linker needs: the BLAS/LAPACK
# alternatives (OpenCV links libblas.so.3 and liblapack.so.3) ...
lib=$sysroot/usr/lib/aarch64-linux-gnu
for alt in blas/libblas.so.3 lapack/liblapack.so.3; do
  [[ -e $lib/$alt ]] && ln -sfn "$alt" "$lib/$(basename "$alt")"
done
# ... and no absolute symlinks under usr/: the cross linker would follow them into the host's /.
while IFS= read -r link; do
  target=$(readlink "$link")
  [[ -e $sysroot$target ]] || continue
  ln -sfn "$(realpath --relative-to="$(dirname "$link")" "$sysroot$target")" "$link"
done < <(find "$sysroot/usr" -type l -lname '/*')
echo "$stamp" > "$sysroot/.packages"
echo "make-sysroot: $(du -sh "$sysroot" | cut -f1) in $sysroot"
