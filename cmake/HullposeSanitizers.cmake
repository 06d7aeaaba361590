# HULLPOSE_SANITIZE=address,undefined or thread: instrument every target.
if(HULLPOSE_SANITIZE)
  if(HULLPOSE_SANITIZE MATCHES "thread" AND HULLPOSE_SANITIZE MATCHES "address")
    message(FATAL_ERROR "HULLPOSE_SANITIZE: thread cannot be combined with address")
  endif()
  set(_san "-fsanitize=${HULLPOSE_SANITIZE}" -fno-omit-frame-pointer -fno-sanitize-recover=all)
  if(HULLPOSE_SANITIZE MATCHES "undefined")
    # UBSan's vptr check misfires inside LCM's header-only C++ dispatch (lcm-cpp-impl.hpp,
    # LCM 1.3.1): every typed callback is reported as an invalid vptr although the C API hands
    # back the right pointer (checked with ASan alone). The other UB checks stay on.
    list(APPEND _san -fno-sanitize=vptr)
  endif()
  add_compile_options(${_san})
  add_link_options(${_san})
  # A Debug build under a sanitizer is optimised a little (-O1, the sanitizers' documented
  # setting for reasonable speed): at -O0 the unit tests spent most of their time in unoptimised
  # Eigen (test_pose_recovery 65 s, test_import 58 s). GCC 12 at -O1 with the instrumentation
  # reports false "maybe-uninitialized" inside Eigen's AVX-512 kernels (extrinsics.cpp), as it
  # does at -O2 for the files that say so; the unsanitised trees keep that warning.
  add_compile_options($<$<CONFIG:Debug>:-O1>)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options($<$<CONFIG:Debug>:-Wno-maybe-uninitialized>)
  endif()
  message(STATUS "hullpose: sanitizers ${HULLPOSE_SANITIZE}")
endif()
