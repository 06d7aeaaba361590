#include "hullpose/skeleton_io/gaps.hpp"

namespace hullpose::skeleton_io {

GapReport fill_gaps(std::vector<SkeletonFrame>& frames, int max_fill_frames) {
  GapReport report;
  const int n = static_cast<int>(frames.size());
  report.state.assign(frames.size(), FrameState::Measured);
  int i = 0;
  while (i < n) {
    if (frames[static_cast<size_t>(i)].valid) {
      ++i;
      continue;
    }
    int end = i;  // one past the invalid run
    while (end < n && !frames[static_cast<size_t>(end)].valid) ++end;
    const bool bounded = i > 0 && end < n;
    const int length = end - i;
    if (bounded && length <= max_fill_frames) {
      const JointPositions& a = frames[static_cast<size_t>(i - 1)].joints;
      const JointPositions& b = frames[static_cast<size_t>(end)].joints;
      for (int k = i; k < end; ++k) {
        const double t = static_cast<double>(k - i + 1) / (length + 1);
        for (size_t j = 0; j < kNumJoints; ++j)
          frames[static_cast<size_t>(k)].joints[j] = (1 - t) * a[j] + t * b[j];
        report.state[static_cast<size_t>(k)] = FrameState::Filled;
      }
      report.filled += length;
    } else {
      for (int k = i; k < end; ++k) report.state[static_cast<size_t>(k)] = FrameState::Missing;
      report.missing += length;
      report.missing_ranges.emplace_back(i, end - 1);
    }
    i = end;
  }
  return report;
}

}  // namespace hullpose::skeleton_io
