# CMake toolchain for the boards' CPU: Debian's aarch64 cross compiler against the arm64 sysroot
# of deploy/cross/make-sysroot.sh; tests run under qemu-user-static with the sysroot's libraries.
#   cmake -S . -B build-arm64 -DCMAKE_TOOLCHAIN_FILE=deploy/cross/toolchain-aarch64.cmake \
#         -DHULLPOSE_SYSROOT=$PWD/build-arm64/sysroot
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

# CMake reads this file more than once, and not every reading sees -DHULLPOSE_SYSROOT (the
# cache is not loaded yet): the first reading hands it on through the environment. An empty
# value must fail, not fall through to "/usr/lib/aarch64-linux-gnu", which the cross binutils
# create on the host: the pkg-config paths below would then point at the host.
if(NOT HULLPOSE_SYSROOT)
  set(HULLPOSE_SYSROOT "$ENV{HULLPOSE_SYSROOT}")
endif()
if(HULLPOSE_SYSROOT STREQUAL "" OR NOT IS_DIRECTORY "${HULLPOSE_SYSROOT}/usr/lib/aarch64-linux-gnu")
  message(FATAL_ERROR "HULLPOSE_SYSROOT='${HULLPOSE_SYSROOT}' is not an arm64 sysroot (deploy/cross/make-sysroot.sh makes one)")
endif()
set(ENV{HULLPOSE_SYSROOT} "${HULLPOSE_SYSROOT}")
set(HULLPOSE_SYSROOT "${HULLPOSE_SYSROOT}" CACHE PATH "The arm64 sysroot" FORCE)
set(CMAKE_SYSROOT "${HULLPOSE_SYSROOT}")
set(CMAKE_FIND_ROOT_PATH "${HULLPOSE_SYSROOT}")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)  # lcm-gen, ccache: the host's
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# Libraries' own dependencies (OpenCV -> BLAS, ...) resolve inside the sysroot at link time.
set(CMAKE_EXE_LINKER_FLAGS_INIT "-Wl,-rpath-link,${HULLPOSE_SYSROOT}/usr/lib/aarch64-linux-gnu")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "-Wl,-rpath-link,${HULLPOSE_SYSROOT}/usr/lib/aarch64-linux-gnu")

set(ENV{PKG_CONFIG_SYSROOT_DIR} "${HULLPOSE_SYSROOT}")
set(ENV{PKG_CONFIG_LIBDIR} "${HULLPOSE_SYSROOT}/usr/lib/aarch64-linux-gnu/pkgconfig:${HULLPOSE_SYSROOT}/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_PATH} "")

set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64-static -L ${HULLPOSE_SYSROOT})
