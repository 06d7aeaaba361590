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
  message(STATUS "hullpose: sanitizers ${HULLPOSE_SANITIZE}")
endif()
