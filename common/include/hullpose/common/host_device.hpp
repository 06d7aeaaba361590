#pragma once
// HULLPOSE_HD marks functions the CPU path and the CUDA backend (fusion_host/gpu) share verbatim,
// so the CPU tests exercise the code the GPU runs.
#ifdef __CUDACC__
#define HULLPOSE_HD __host__ __device__
#else
#define HULLPOSE_HD
#endif
