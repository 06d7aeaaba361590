# CUDA is optional. HULLPOSE_CUDA=AUTO builds the CUDA backend when nvcc is found
# (PATH, CUDACXX, or /usr/local/cuda); ON requires it; OFF skips it.
# Sets HULLPOSE_HAVE_CUDA for the rest of the build.
set(HULLPOSE_HAVE_CUDA OFF)
if(NOT HULLPOSE_CUDA STREQUAL "OFF")
  if(NOT CMAKE_CUDA_COMPILER AND NOT DEFINED ENV{CUDACXX} AND EXISTS /usr/local/cuda/bin/nvcc)
    set(CMAKE_CUDA_COMPILER /usr/local/cuda/bin/nvcc)
  endif()
  include(CheckLanguage)
  check_language(CUDA)
  if(CMAKE_CUDA_COMPILER)
    enable_language(CUDA)
    find_package(CUDAToolkit REQUIRED)
    set(HULLPOSE_HAVE_CUDA ON)
    # Turing, Ampere and Hopper (H100/H200); CUDA 13 has dropped everything older.
    set(HULLPOSE_CUDA_ARCHS "75;86;90" CACHE STRING "CUDA architectures to build for")
    set(CMAKE_CUDA_ARCHITECTURES ${HULLPOSE_CUDA_ARCHS})
    message(STATUS "hullpose: CUDA backend ON (${CMAKE_CUDA_COMPILER}, archs ${CMAKE_CUDA_ARCHITECTURES})")
  elseif(HULLPOSE_CUDA STREQUAL "ON")
    message(FATAL_ERROR "HULLPOSE_CUDA=ON but no CUDA compiler was found (looked on PATH, CUDACXX, /usr/local/cuda)")
  else()
    message(STATUS "hullpose: CUDA backend OFF (no nvcc found)")
  endif()
endif()
