#pragma once
// Curve thinning of a binary voxel volume (26-adjacent object, 6-adjacent background).
//
//  - Ck3Thinner: the fully parallel, symmetric critical-kernel scheme of thesis paper 4
//    (Algorithm 1), as specified in ../shared/reference/critical-kernels-thinning.md ("the notes"):
//    simple points from an 8 MiB LUT, crucial 2-, 1- and 0-cliques with level-parallel
//    (double-buffered) marking and the corrected 0-clique test (§2.4), repeated until stable.
//    The curve constraint is selectable (CurveRule). Only border voxels are ever visited.
//    Multi-threaded (OpenMP); every pass is a pure function of the previous passes' state, so
//    the result does not depend on thread count or visiting order, and it commutes with the 48
//    symmetries of the cube.
//  - D6i1dThinner: the directional scheme the thesis compared against (notes §4), with our own
//    provably topology-preserving directional deletability (§4.4).
//
// Lifecycle: construct once with the options, call thin() per frame; all working buffers are
// kept and reused (no allocation at steady state for a fixed volume size).
// Volumes are fusion::BitGrid; voxels outside the grid are background.
#include <cstdint>
#include <memory>
#include <vector>

#include "hullpose/fusion/bit_grid.hpp"
#include "hullpose/thin/rules.hpp"

namespace hullpose::thin {

const char* to_string(CurveRule rule);

struct ThinOptions {
  CurveRule rule = CurveRule::kCk3;
  ZeroCliqueTest zero_clique = ZeroCliqueTest::kSpan3;
  int threads = 1;         // OpenMP threads for the passes of one iteration
  int max_iterations = 0;  // 0 = until stable; 1 = one step (tests)
  // Iterations with fewer border voxels run on one thread: below this a barrier costs more than
  // the work, and on a loaded machine a descheduled partner thread stalls every barrier.
  int min_parallel_border = 4096;
};

struct ThinStats {
  int iterations = 0;  // iterations run, including the last one that deleted nothing
  size_t initial_voxels = 0;
  size_t final_voxels = 0;
  size_t constrained = 0;  // |K| at the end (isthmus and end-voxel rules)
  size_t visited = 0;      // border-list entries classified, summed over iterations
};

class Ck3Thinner {
 public:
  explicit Ck3Thinner(const ThinOptions& options = {});
  ~Ck3Thinner();
  Ck3Thinner(const Ck3Thinner&) = delete;
  Ck3Thinner& operator=(const Ck3Thinner&) = delete;

  // Thins `volume` in place. `constraint`, if given, is the initial K (voxels never deleted;
  // must have the volume's dims or be empty, voxels outside the object are ignored) and receives
  // the final K, so a second call with it carried over is a fixed point (notes §5.3).
  ThinStats thin(fusion::BitGrid& volume, fusion::BitGrid* constraint = nullptr);

  const ThinOptions& options() const { return options_; }

 private:
  struct State;
  ThinOptions options_;
  std::unique_ptr<State> state_;
};

struct D6i1dOptions {
  int max_iterations = 0;  // full 6-direction iterations; 0 = until stable
};

class D6i1dThinner {
 public:
  explicit D6i1dThinner(const D6i1dOptions& options = {});
  ~D6i1dThinner();
  D6i1dThinner(const D6i1dThinner&) = delete;
  D6i1dThinner& operator=(const D6i1dThinner&) = delete;

  ThinStats thin(fusion::BitGrid& volume, fusion::BitGrid* constraint = nullptr);

 private:
  struct State;
  D6i1dOptions options_;
  std::unique_ptr<State> state_;
};

}  // namespace hullpose::thin
