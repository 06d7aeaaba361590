#pragma once
// Topological invariants and connected components of binary volumes (26-adjacent object,
// 6-adjacent background, voxels outside the grid are background), computed on runs of voxels
// along x so that they are cheap enough for per-frame clean-up and for the property tests.
#include <cstdint>
#include <vector>

#include "hullpose/fusion/bit_grid.hpp"

namespace hullpose::thin {

struct TopologyInvariants {
  int components = 0;  // b0: 26-connected object components
  int cavities = 0;    // 6-connected background components not connected to the outside
  int64_t euler = 0;   // Euler characteristic of the union of closed unit cubes
  int tunnels() const { return static_cast<int>(components + cavities - euler); }  // b1
  bool operator==(const TopologyInvariants&) const = default;
};

TopologyInvariants topology_invariants(const fusion::BitGrid& volume);

// Euler characteristic V - E + F - C of the union of the closed voxels.
int64_t euler_characteristic(const fusion::BitGrid& volume);

// 26-connected components. Reuse one instance across frames: buffers are kept.
class ComponentLabeller {
 public:
  // Labels the object's components; returns their number. Component ids are 0..n-1, ordered by
  // their first voxel in x-fastest order (deterministic).
  int label(const fusion::BitGrid& volume);
  // Voxel count of each component.
  const std::vector<int64_t>& sizes() const { return sizes_; }
  // Writes into `out` (dims of the labelled volume) the components whose `keep[id]` is true.
  void extract(const std::vector<bool>& keep, fusion::BitGrid& out) const;
  // 6-connected background components that do not touch the grid boundary (cavities), filled
  // into `volume` when their size is at most max_voxels; returns how many were filled.
  // Number of cavities (6-connected background components not reaching the outside).
  int count_cavities(const fusion::BitGrid& volume);
  // Fills the cavities of at most max_voxels voxels; returns how many were filled.
  int fill_cavities(fusion::BitGrid& volume, int64_t max_voxels);
  // All three invariants, reusing this labeller's buffers.
  TopologyInvariants invariants(const fusion::BitGrid& volume);

 private:
  struct Run {
    int x0, x1;  // inclusive
  };
  // Runs of one row set: rows indexed r = (z - lo) * rows_y + (y - lo); runs of row r are
  // [row_start[r], row_start[r + 1]).
  struct Runs {
    std::vector<Run> runs;
    std::vector<int> row_start;
    std::vector<int> parent;
    int lo = 0, rows_y = 0, rows_z = 0;
    int find(int a);
    void connect(bool adjacency26);
  };
  // Labels background runs; returns the root of the outside. Sizes per root in bg_size_.
  int label_background(const fusion::BitGrid& volume);
  std::vector<int64_t> bg_size_;
  Runs object_, background_;
  std::vector<int> comp_of_run_;
  std::vector<int64_t> sizes_;
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
};

}  // namespace hullpose::thin
