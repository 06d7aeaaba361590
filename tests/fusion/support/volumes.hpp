#pragma once
// Test volumes and an independent, deliberately naive topology reference (dense arrays, BFS,
// Khalimsky-grid Euler characteristic, clique enumeration straight from the definitions of
// critical-kernels-thinning.md) to check the optimised code against.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <random>
#include <vector>

#include "hullpose/fusion/bit_grid.hpp"

namespace hullpose::fusion::testing {

using Pred = std::function<bool(double x, double y, double z)>;
// Voxels (x, y, z) of a grid of `dims` whose coordinates satisfy `inside`.
BitGrid make_volume(const Eigen::Vector3i& dims, const Pred& inside);

BitGrid box(int a, int b, int c, int margin = 3);
BitGrid ball(double radius, bool even_centre, int margin = 3);
BitGrid cylinder_x(double radius, int length, int margin = 3);        // axis along x, odd-centred
BitGrid torus(double R, double r, bool even_centre, int margin = 3);  // in the xy plane
BitGrid hollow_ball(double R, double thickness, int margin = 3);
BitGrid cross_bars(int width, int length,
                   int margin = 3);  // two width² bars crossing in the xy plane
BitGrid trefoil_tube(double scale, double radius, int margin = 3);
BitGrid random_blobs(std::mt19937& rng, int size, int blobs);
BitGrid random_noise(std::mt19937& rng, const Eigen::Vector3i& dims, double density, int margin);

// One of the 48 cube isometries: axis permutation perm, then flips.
struct Isometry {
  std::array<int, 3> perm;
  std::array<bool, 3> flip;
};
std::vector<Isometry> all_isometries();
BitGrid apply(const Isometry& g, const BitGrid& v);

// Reference invariants (dense BFS; Euler characteristic on the Khalimsky grid).
struct RefInvariants {
  int components = 0, cavities = 0;
  int64_t euler = 0;
  bool operator==(const RefInvariants&) const = default;
};
RefInvariants reference_invariants(const BitGrid& v);

// Reference simple test straight from §1.1 (BFS on an explicit 3x3x3 array).
bool reference_simple(const BitGrid& v, int x, int y, int z);

// Every crucial clique of X (non-simple voxels, crucial 2-, 1- and essential 0-cliques) must
// contain a voxel of Y (notes §5.2). Returns the number of cliques violating this.
int crucial_cliques_missed(const BitGrid& X, const BitGrid& Y);

}  // namespace hullpose::fusion::testing
