#!/usr/bin/env bash
# make cross: the boards' build. Cross-compiles hullpose for arm64 (aarch64) with Debian's cross
# toolchain against an arm64 sysroot (make-sysroot.sh), packs the arm64 .debs and runs the unit
# tests under qemu-user-static (ctest's CMAKE_CROSSCOMPILING_EMULATOR, no binfmt needed).
#
# usage: build.sh [DIR=build-arm64] [JOBS=nproc]
#   DIR/sysroot   the arm64 sysroot          DIR/build   the CMake build
#   DIR/packages  the arm64 .debs            DIR/figures.txt  times and test counts
# CUDA is off (a Jetson builds natively with JetPack's nvcc: deploy/boards/jetson-orin-fusion.md), and
# so is the synthetic frame source: a board's production camera node carries no renderer.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
dir=$(mkdir -p "${1:-build-arm64}" && cd "${1:-build-arm64}" && pwd)
jobs=${2:-$(nproc)}
say() { echo "make cross: $*" >&2; }
t0=$SECONDS
"$root/deploy/install-deps.sh" "$root/deploy/cross/packages.txt"
"$root/deploy/cross/make-sysroot.sh" "$dir/sysroot"
t_sysroot=$(( SECONDS - t0 ))

# The toolchain file sets these too; exported here as well so every pkg-config call of the
# configure step (first run included) sees only the sysroot's .pc files.
export PKG_CONFIG_SYSROOT_DIR=$dir/sysroot
export PKG_CONFIG_LIBDIR=$dir/sysroot/usr/lib/aarch64-linux-gnu/pkgconfig:$dir/sysroot/usr/share/pkgconfig
export PKG_CONFIG_PATH=
cmake -S "$root" -B "$dir/build" -DCMAKE_TOOLCHAIN_FILE="$root/deploy/cross/toolchain-aarch64.cmake" \
  -DHULLPOSE_SYSROOT="$dir/sysroot" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHULLPOSE_NATIVE=OFF -DHULLPOSE_CUDA=OFF \
  -DHULLPOSE_SYNTHETIC_SOURCE=OFF \
  -DHULLPOSE_SHARED_DIR="$root/../shared" > "$dir/configure.log"

# What the packages install, plus the unit tests ctest will run (benchmarks, fuzz targets and
# the system tests, which start programs from shell scripts, are not built).
mapfile -t installed < <(sed -n 's/^HULLPOSE_PACKAGED_TARGETS=//p' "$dir/build/hullpose-packaging.txt" | tr ';' '\n')
mapfile -t unit < <(ctest --test-dir "$dir/build" -N -L unit | sed -n 's/^ *Test *#[0-9]*: //p')
known=$(cmake --build "$dir/build" --target help | sed -n 's/^\.\.\. \([^ ]*\).*/\1/p')
targets=()
for t in "${installed[@]}" "${unit[@]}"; do grep -qx "$t" <<<"$known" && targets+=("$t"); done
say "building ${#targets[@]} targets for arm64 (-j$jobs)"
t1=$SECONDS
cmake --build "$dir/build" -j "$jobs" --target "${targets[@]}"
t_build=$(( SECONDS - t1 ))

t2=$SECONDS
rm -rf "$dir/packages"
(cd "$dir/build" && cpack -G DEB -B "$dir/packages" > "$dir/cpack.log")
rm -rf "$dir/packages/_CPack_Packages"
t_pack=$(( SECONDS - t2 ))
check=$(mktemp -d)
for deb in "$dir"/packages/*.deb; do
  [[ $(dpkg-deb -f "$deb" Architecture) == arm64 ]] || { say "$deb is not Architecture: arm64"; exit 1; }
  dpkg-deb -x "$deb" "$check"
done
for program in "$check"/usr/bin/*; do
  readelf -h "$program" | grep -q 'Machine:.*AArch64' || { say "$program is not an aarch64 program"; exit 1; }
done
rm -rf "$check"
say "arm64 packages: $(cd "$dir/packages" && ls ./*.deb | xargs -n1 basename | tr '\n' ' ')"

t3=$SECONDS
set +e
# A private TMPDIR: the emulated run often shares the machine with a native `make test`, and
# tests that keep scratch files under a fixed name would otherwise meet the other run's files.
mkdir -p "$dir/tmp"
(cd "$dir/build" && TMPDIR=$dir/tmp ctest -L unit --output-on-failure --timeout 1800 -j "$jobs" > "$dir/ctest.log" 2>&1)
rc=$?
set -e
t_test=$(( SECONDS - t3 ))
summary=$(grep -E 'tests passed|tests failed' "$dir/ctest.log" | tail -1)
{
  echo "sysroot ${t_sysroot}s, build ${t_build}s (${#targets[@]} targets, -j$jobs), cpack ${t_pack}s, qemu unit tests ${t_test}s"
  echo "qemu-aarch64-static unit tests: $summary"
  grep -E '^\s*[0-9]+/[0-9]+ Test' "$dir/ctest.log"
} | tee "$dir/figures.txt" >&2
exit $rc
