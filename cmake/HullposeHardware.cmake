# Optional camera-board libraries (HULLPOSE_LIBCAMERA, HULLPOSE_GPIOD: AUTO | ON | OFF). Sets
# HULLPOSE_HAVE_LIBCAMERA / HULLPOSE_HAVE_LIBGPIOD; the targets PkgConfig::LIBCAMERA and
# PkgConfig::LIBGPIOD exist only when they are on.
function(hullpose_optional_pkg var mode module)
  if(mode STREQUAL "OFF")
    set(HULLPOSE_HAVE_${var} OFF PARENT_SCOPE)
    return()
  endif()
  if(mode STREQUAL "ON")
    pkg_check_modules(${var} REQUIRED IMPORTED_TARGET GLOBAL ${module})
  else()
    pkg_check_modules(${var} IMPORTED_TARGET GLOBAL ${module})
  endif()
  set(HULLPOSE_HAVE_${var} ${${var}_FOUND} PARENT_SCOPE)
  if(NOT ${var}_FOUND)
    message(STATUS "hullpose: ${module} not found: its backend is left out of this build")
  endif()
endfunction()

hullpose_optional_pkg(LIBCAMERA "${HULLPOSE_LIBCAMERA}" libcamera)
hullpose_optional_pkg(LIBGPIOD "${HULLPOSE_GPIOD}" libgpiodcxx)
# hullpose_use_gpiod(<target>): links libgpiod and defines HULLPOSE_HAVE_LIBGPIOD where the build
# has it (the target's gpiod: backend is compiled out otherwise).
function(hullpose_use_gpiod target)
  if(HULLPOSE_HAVE_LIBGPIOD)
    target_link_libraries(${target} PRIVATE PkgConfig::LIBGPIOD)
    target_compile_definitions(${target} PRIVATE HULLPOSE_HAVE_LIBGPIOD=1)
  endif()
endfunction()

message(STATUS "hullpose: libcamera source ${HULLPOSE_HAVE_LIBCAMERA}, libgpiod trigger ${HULLPOSE_HAVE_LIBGPIOD}, "
               "synthetic source ${HULLPOSE_SYNTHETIC_SOURCE}")
