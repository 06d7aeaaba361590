#pragma once
// The 25 joints as markers for biomechanics tools: TRC (OpenSim's marker file) and C3D (the
// motion-capture industry's binary point file, c3d.org specification). Both in millimetres in
// OpenSim's frame, Y up: rig (x, y, z) -> (x, z, -y). Gaps (gaps.hpp): TRC leaves the marker
// fields of a missing frame empty; C3D marks a missing point with residual -1, an interpolated
// one with residual 0 (the specification's "processed, not measured") and a fresh estimate with a
// positive residual.
#include <filesystem>

#include "hullpose/skeleton_io/gaps.hpp"

namespace hullpose::skeleton_io {

void write_trc(const std::filesystem::path& path, const Take& take, const GapReport& gaps);
void write_c3d(const std::filesystem::path& path, const Take& take, const GapReport& gaps);

}  // namespace hullpose::skeleton_io
