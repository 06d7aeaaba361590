// Pose tree and labels (thesis paper 5). Where this departs from the paper, and why:
//  - The tree grows from the top-most voxel of the LARGEST 26-connected component, not of all
//    voxels: a stray voxel above the head would otherwise become the whole tree.
//  - Pruning removes the shortest spurious terminal branch one at a time (then re-evaluates),
//    so a limb end that CK3 left two voxels thick (a fork of two stubs) loses one stub, not its
//    tip. The threshold is a fraction of the longest path below the head branch, rather than an
//    arm length, because the tree here is treated as unrooted: the head is a terminal branch like
//    any other, which removes the paper's dependence on the head being the highest point.
//    Pruning never goes below five branches, and up to four spurs survive it for the ranking.
//  - Ranking: the head must continue the torso (eq. 1's head factor times a direction factor):
//    CK3's spurs off a thick chest are as long as a neck and only their direction differs.
//  - Candidate ranking (eq. 1-4) measures the "shortened limb" penalty in units of a fraction of
//    the longest path, and counts junctions closer than a few voxels as one (CK3 splits a
//    degree-4 junction into two degree-3 nodes where the skeleton is two voxels thick).
//  - Validity: instead of one empirical threshold on the raw rank product (which scales with the
//    number of limbs and is hard to read), every rank factor is in 0..1, the labelling must
//    reach a minimum geometric mean AND a minimum single factor, the torso must exist, and the
//    skeleton must not touch the sides or top of the capture volume (a cut-off person). A
//    single badly wrong limb (arm merged with the torso, leg missing) therefore fails the tree
//    even when the others are perfect.
//  - Temporal correspondence chooses the extremity classes only when the labelling it implies
//    ranks nearly as well as the best structural one, and left/right only when the geometric
//    decision of algorithm 6 has too little margin: the thesis found the geometric left/right
//    robust where correspondences fail (fast spins).
#include "hullpose/pose/pose_tree.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>

#include "hullpose/pose/anthropometry.hpp"
#include "hullpose/pose/geometry.hpp"

namespace hullpose::pose {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDeg = M_PI / 180.0;

double closeness(double ideal, double actual) {
  if (ideal <= 0 || actual <= 0) return 0;
  return std::min(ideal, actual) / std::max(ideal, actual);
}

// Index into the endpoint class arrays.
constexpr int kHeadSlot = 0, kHand1 = 1, kHand2 = 2, kFoot1 = 3, kFoot2 = 4;

// The torso's line, pointing from the pelvis to the origin.
Eigen::Vector3d torso_up(const LabelledTree& tree) {
  MomentAccumulator m;
  for (int32_t i : tree.torso_path) m.add(tree.position[i]);
  Eigen::Vector3d d =
      m.count() >= 2 ? fit_line(m).direction
                     : Eigen::Vector3d(tree.position[tree.origin] - tree.position[tree.pelvis]);
  if (d.dot(tree.position[tree.origin] - tree.position[tree.pelvis]) < 0) d = -d;
  return d.normalized();
}

}  // namespace

PoseTreeBuilder::PoseTreeBuilder(TreeParams params) : params_(params) {}

void PoseTreeBuilder::invalidate(const char* why) {
  tree_.valid = false;
  tree_.why = why;
}

// Algorithm 2 with depth layers: the largest component's top-most voxel is the root, one tree
// node per connected set of voxels at one breadth-first depth, then the tree's adjacency.
void PoseTreeBuilder::grow_tree(std::span<const Eigen::Vector3i> voxels,
                                const VoxelGridSpec& grid) {
  index_voxels(voxels, grid);
  index_neighbours(voxels, grid);
  tree_.position.clear();
  tree_.parent.clear();
  const int32_t root = largest_component_root(voxels, grid);
  if (root >= 0) {
    depths_from(voxels.size(), root);
    one_node_per_depth_layer(voxels, grid);
  }
  for (const Eigen::Vector3i& v : voxels)
    if (grid.contains(v)) {
      lookup_[grid.index(v.x(), v.y(), v.z())] = -1;
      occupied_.set(v.x(), v.y(), v.z(), false);
    }
  build_adjacency();
}

void PoseTreeBuilder::index_voxels(std::span<const Eigen::Vector3i> voxels,
                                   const VoxelGridSpec& grid) {
  if (!(grid == grid_) || lookup_.size() != grid.size()) {
    grid_ = grid;
    lookup_.assign(grid.size(), -1);
    occupied_.reset(grid.dims);
  }
  const int32_t n_in = static_cast<int32_t>(voxels.size());
  for (int32_t i = 0; i < n_in; ++i) {
    if (!grid.contains(voxels[i])) continue;
    int32_t& slot = lookup_[grid.index(voxels[i].x(), voxels[i].y(), voxels[i].z())];
    if (slot < 0) slot = i;
    occupied_.set(voxels[i].x(), voxels[i].y(), voxels[i].z());
  }
}

// The voxels' 26-neighbour lists, once per frame: the three graph passes below read them instead
// of 26 lookups each into the grid-sized table (scattered over three z-planes: on the crane's
// real skeletons the lookups were ~40 % of the bottom-up stage). Most neighbours are empty: the
// occupancy bits (32 times smaller than the table, so cached) answer those.
void PoseTreeBuilder::index_neighbours(std::span<const Eigen::Vector3i> voxels,
                                       const VoxelGridSpec& grid) {
  neighbour_begin_.assign(voxels.size() + 1, 0);
  neighbours_.clear();
  const Eigen::Vector3i& d = grid.dims;
  for (size_t i = 0; i < voxels.size(); ++i) {
    const Eigen::Vector3i& v = voxels[i];
    if (grid.contains(v)) {
      const int x0 = std::max(0, v.x() - 1), x1 = std::min(d.x() - 1, v.x() + 1);
      for (int z = std::max(0, v.z() - 1); z <= std::min(d.z() - 1, v.z() + 1); ++z)
        for (int y = std::max(0, v.y() - 1); y <= std::min(d.y() - 1, v.y() + 1); ++y) {
          const uint64_t* row = occupied_.row(y, z);
          for (int x = x0; x <= x1; ++x)
            if ((row[x >> 6] >> (x & 63) & 1) != 0 && (x != v.x() || y != v.y() || z != v.z()))
              neighbours_.push_back(lookup_[grid.index(x, y, z)]);
        }
    }
    neighbour_begin_[i + 1] = static_cast<int32_t>(neighbours_.size());
  }
}

template <typename Visit>
void PoseTreeBuilder::for_each_neighbour(int32_t i, Visit&& visit) const {
  for (int32_t k = neighbour_begin_[i]; k < neighbour_begin_[i + 1]; ++k) visit(neighbours_[k]);
}

// Components: the largest wins, rooted at its top-most voxel (ties: first listed); -1 if none.
int32_t PoseTreeBuilder::largest_component_root(std::span<const Eigen::Vector3i> voxels,
                                                const VoxelGridSpec& grid) {
  const int32_t n_in = static_cast<int32_t>(voxels.size());
  component_.assign(voxels.size(), -1);
  int32_t best_root = -1, best_size = 0, next_id = 0;
  for (int32_t s = 0; s < n_in; ++s) {
    if (!grid.contains(voxels[s]) || component_[s] >= 0) continue;
    if (lookup_[grid.index(voxels[s].x(), voxels[s].y(), voxels[s].z())] != s) continue;  // repeat
    const int32_t id = next_id++;
    queue_.clear();
    queue_.push_back(s);
    component_[s] = id;
    int32_t top = s;
    for (size_t q = 0; q < queue_.size(); ++q) {
      const int32_t i = queue_[q];
      if (voxels[i].z() > voxels[top].z() || (voxels[i].z() == voxels[top].z() && i < top)) top = i;
      for_each_neighbour(i, [&](int32_t j) {
        if (component_[j] < 0) {
          component_[j] = id;
          queue_.push_back(j);
        }
      });
    }
    if (static_cast<int32_t>(queue_.size()) > best_size) {
      best_size = static_cast<int32_t>(queue_.size());
      best_root = top;
    }
  }
  return best_root;
}

// Breadth-first depth of every voxel of the root's component; queue_ holds them in visit order.
void PoseTreeBuilder::depths_from(size_t voxel_count, int32_t root) {
  depth_.assign(voxel_count, -1);
  queue_.clear();
  queue_.push_back(root);
  depth_[root] = 0;
  for (size_t q = 0; q < queue_.size(); ++q) {
    const int32_t i = queue_[q];
    for_each_neighbour(i, [&](int32_t j) {
      if (depth_[j] < 0) {
        depth_[j] = depth_[i] + 1;
        queue_.push_back(j);
      }
    });
  }
}

// On a one-voxel-thin skeleton one node per depth layer set is exactly the paper's
// node-per-voxel tree; where CK3 left the skeleton two voxels thick, the voxels side by side
// share a depth and collapse into one node at their centroid, instead of growing two parallel
// branches that no length threshold can tell from a limb.
void PoseTreeBuilder::one_node_per_depth_layer(std::span<const Eigen::Vector3i> voxels,
                                               const VoxelGridSpec& grid) {
  cluster_.assign(voxels.size(), -1);
  for (size_t q = 0; q < queue_.size(); ++q) {
    const int32_t seed = queue_[q];
    if (cluster_[seed] >= 0) continue;
    const int32_t id = static_cast<int32_t>(tree_.position.size());
    const int32_t depth = depth_[seed];
    int32_t parent = -1;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int members = 0;
    stack_.clear();
    stack_.push_back(seed);
    cluster_[seed] = id;
    while (!stack_.empty()) {
      const int32_t i = stack_.back();
      stack_.pop_back();
      sum += grid.centre_mm(voxels[i]);
      ++members;
      for_each_neighbour(i, [&](int32_t j) {
        if (depth_[j] == depth && cluster_[j] < 0) {
          cluster_[j] = id;
          stack_.push_back(j);
        } else if (depth_[j] == depth - 1 && parent < 0) {
          parent = cluster_[j];
        }
      });
    }
    tree_.parent.push_back(parent);
    tree_.position.push_back(sum / members);
  }
}

// Undirected adjacency (CSR) of the tree.
void PoseTreeBuilder::build_adjacency() {
  const int32_t n = static_cast<int32_t>(tree_.parent.size());
  adj_begin_.assign(static_cast<size_t>(n) + 1, 0);
  for (int32_t i = 1; i < n; ++i) {
    ++adj_begin_[i + 1];
    ++adj_begin_[tree_.parent[i] + 1];
  }
  std::partial_sum(adj_begin_.begin(), adj_begin_.end(), adj_begin_.begin());
  adj_.resize(n > 0 ? 2 * static_cast<size_t>(n - 1) : 0);
  degree_.assign(static_cast<size_t>(n), 0);  // fill cursor
  for (int32_t i = 1; i < n; ++i) {
    const int32_t p = tree_.parent[i];
    adj_[adj_begin_[i] + degree_[i]++] = p;
    adj_[adj_begin_[p] + degree_[p]++] = i;
  }
}

void PoseTreeBuilder::distances_from(int32_t source, bool alive_only) {
  const size_t n = tree_.position.size();
  dist_.assign(n, kInf);
  via_.assign(n, -1);
  hops_.assign(n, 0);
  queue_.clear();
  queue_.push_back(source);
  dist_[source] = 0;
  for (size_t q = 0; q < queue_.size(); ++q) {
    const int32_t i = queue_[q];
    for (int32_t k = adj_begin_[i]; k < adj_begin_[i + 1]; ++k) {
      const int32_t j = adj_[k];
      if (dist_[j] != kInf || (alive_only && !alive_[j])) continue;
      dist_[j] = dist_[i] + (tree_.position[j] - tree_.position[i]).norm();
      via_[j] = i;
      hops_[j] = hops_[i] + 1;
      queue_.push_back(j);
    }
  }
}

double PoseTreeBuilder::longest_path() {
  // Tree diameter by two sweeps: the farthest node from anywhere is one end of it.
  distances_from(0, false);
  const auto far = [&] {
    return static_cast<int32_t>(std::max_element(dist_.begin(), dist_.end()) - dist_.begin());
  };
  distances_from(far(), false);
  return dist_[far()];
}

void PoseTreeBuilder::collect_branches() {
  const int32_t n = static_cast<int32_t>(tree_.position.size());
  for (int32_t i = 0; i < n; ++i) {
    int32_t d = 0;
    if (alive_[i])
      for (int32_t k = adj_begin_[i]; k < adj_begin_[i + 1]; ++k) d += alive_[adj_[k]];
    degree_[i] = d;
  }
  branches_.clear();
  junctions_.clear();
  for (int32_t e = 0; e < n; ++e) {
    if (!alive_[e]) continue;
    if (degree_[e] >= 3) junctions_.push_back(e);
    if (degree_[e] != 1) continue;
    int32_t prev = -1, cur = e;
    double length = 0;
    while (cur == e || degree_[cur] == 2) {
      int32_t next = -1;
      for (int32_t k = adj_begin_[cur]; k < adj_begin_[cur + 1]; ++k)
        if (alive_[adj_[k]] && adj_[k] != prev) {
          next = adj_[k];
          break;
        }
      if (next < 0) break;
      length += (tree_.position[next] - tree_.position[cur]).norm();
      prev = cur;
      cur = next;
    }
    branches_.push_back({e, cur, length});
  }
}

void PoseTreeBuilder::remove_branch(int32_t end, int32_t junction) {
  int32_t prev = -1, cur = end;
  while (cur != junction && cur >= 0) {
    int32_t next = -1;
    for (int32_t k = adj_begin_[cur]; k < adj_begin_[cur + 1]; ++k)
      if (alive_[adj_[k]] && adj_[k] != prev) {
        next = adj_[k];
        break;
      }
    alive_[cur] = 0;
    prev = cur;
    cur = next;
  }
}

bool PoseTreeBuilder::prune(double longest) {
  alive_.assign(tree_.position.size(), 1);
  const double threshold = params_.prune_ratio * longest;
  while (true) {
    collect_branches();
    if (junctions_.empty()) break;  // a bare path: nothing left to prune
    // Never below five: a person has five extremities however short one of them is (the head's
    // branch shrinks to ~0.05 of the longest path when a raised arm's junction moves up the
    // neck); whether a short one is a real limb is the ranking's call, not the pruning's.
    if (branches_.size() <= kNumExtremities) break;
    const auto shortest =
        std::min_element(branches_.begin(), branches_.end(),
                         [](const Branch& a, const Branch& b) { return a.length < b.length; });
    if (shortest->length >= threshold && branches_.size() <= kMaxEnds) break;
    remove_branch(shortest->end, shortest->junction);
  }
  if (branches_.size() < kNumExtremities || junctions_.empty()) return false;
  ends_.clear();
  for (size_t k = 0; k < branches_.size(); ++k) {
    ends_.push_back(branches_[k].end);
    end_branch_[k] = branches_[k].length;
    end_junction_[k] = branches_[k].junction;
  }
  return true;
}

// Where the paths from `a` and `b` towards the last distances_from() source meet (-1 if either
// is unreached): equalise the hop counts, then walk both up in step.
int32_t PoseTreeBuilder::meeting_node(int32_t a, int32_t b) const {
  if (dist_[a] == kInf || dist_[b] == kInf) return -1;
  int32_t ha = hops_[a], hb = hops_[b];
  for (; ha > hb; --ha) a = via_[a];
  for (; hb > ha; --hb) b = via_[b];
  while (a != b) {
    a = via_[a];
    b = via_[b];
  }
  return a;
}

// Eq. 1-4 for one origin candidate and one assignment of endpoints to classes; dist_ must hold
// the distances from `candidate` over the pruned tree.
PoseTreeBuilder::Ranked PoseTreeBuilder::rank_candidate(
    int32_t candidate, const std::array<int32_t, kNumExtremities>& ends, double longest) const {
  const double unit =
      longest / ratio::kLongestPath;  // one stature, by the paper-5 reference length
  const double ideal_neck = ratio::kNeckChain * unit, ideal_arm = ratio::kArmChain * unit;
  const double ideal_torso = ratio::kTorso * unit,
               ideal_leg = (ratio::kTorso + ratio::kLegChain) * unit;
  const double offset_scale = params_.branch_offset_ratio * longest;
  const double merge_mm = params_.junction_merge_voxels * grid_.voxel_mm;

  auto branch_of = [&](int32_t node) {
    for (size_t k = 0; k < ends_.size(); ++k)
      if (ends_[k] == node) return end_branch_[k];
    return 0.0;
  };
  // The neck continues the torso: the head leaves the origin within ~60 degrees of the torso's
  // direction (pelvis -> origin; even a bowed head's top stays inside 90), while the spurs CK3
  // grows off a thick chest or back leave it sideways, forwards or downwards. Length alone cannot
  // tell them apart: a spur is as long as the chest is deep, about the neck's length.
  const int32_t pelvis = meeting_node(ends[kFoot1], ends[kFoot2]);
  double head_direction = 1;
  if (pelvis >= 0 && pelvis != candidate) {
    const Eigen::Vector3d up = tree_.position[candidate] - tree_.position[pelvis];
    const Eigen::Vector3d neck = tree_.position[ends[kHeadSlot]] - tree_.position[candidate];
    const double norms = up.norm() * neck.norm();
    if (norms > 0)
      head_direction = std::clamp(2 * up.dot(neck) / norms, 0.0, 1.0);  // 1 up to 60 deg, 0 at 90
  }
  Ranked r;
  r.origin = candidate;
  r.ends = ends;
  r.upright = pelvis >= 0 && tree_.position[candidate].z() > tree_.position[pelvis].z();
  for (int s = 0; s < kNumExtremities; ++s) {
    const double dr = dist_[ends[s]];
    const double offset =
        std::max(0.0, dr - branch_of(ends[s]));  // root to the limb's branch point
    double f;
    if (s == kHeadSlot)
      f = closeness(ideal_neck, dr) / (1 + offset / offset_scale) * head_direction;
    else if (s == kHand1 || s == kHand2)
      f = closeness(ideal_arm, dr) / (1 + offset / offset_scale);
    else
      f = closeness(ideal_leg, dr) * closeness(ideal_torso, offset);
    r.factor[s] = f;
  }
  // Endpoints left out of this labelling are spurs: their branches do not count in the degree.
  auto dropped_at = [&](int32_t junction) {
    int n = 0;
    for (size_t k = 0; k < ends_.size(); ++k)
      if (end_junction_[k] == junction &&
          std::find(ends.begin(), ends.end(), ends_[k]) == ends.end())
        ++n;
    return n;
  };
  int degree = degree_[candidate] - dropped_at(candidate);
  for (int32_t j : junctions_)
    if (j != candidate && dist_[j] <= merge_mm) degree += degree_[j] - 2 - dropped_at(j);
  const double degree_factor = std::exp(-(degree - 4.0) * (degree - 4.0) / 3.0);
  r.rank = degree_factor;
  for (double f : r.factor) r.rank *= f;
  r.quality = std::pow(r.rank, 1.0 / (kNumExtremities + 1));
  return r;
}

PoseTreeBuilder::Ranked PoseTreeBuilder::best_structural(double longest) {
  // Every origin candidate, and every choice of five endpoints when pruning left more (a long
  // spur, e.g. the ghost volume between the legs, can outlast the head's short branch).
  Ranked best, best_upright;
  const uint32_t count = static_cast<uint32_t>(ends_.size());
  for (int32_t c : junctions_) {
    distances_from(c, true);
    for (uint32_t subset = 0; subset < (1u << count); ++subset) {
      if (std::popcount(subset) != kNumExtremities) continue;
      std::array<int32_t, kNumExtremities> order;
      int n = 0;
      for (uint32_t k = 0; k < count; ++k)
        if (subset & (1u << k)) order[n++] = ends_[k];
      // Nearest last: feet are the two farthest, then the hands, the head nearest (algorithm 3).
      std::sort(order.begin(), order.end(),
                [&](int32_t a, int32_t b) { return dist_[a] > dist_[b]; });
      const std::array<int32_t, kNumExtremities> ends = {order[4], order[2], order[3], order[0],
                                                         order[1]};
      const Ranked r = rank_candidate(c, ends, longest);
      if (r.rank > best.rank) best = r;
      if (r.upright && r.rank > best_upright.rank) best_upright = r;
    }
  }
  return !best.upright && best_upright.origin >= 0 &&
                 best_upright.quality >= best.quality - params_.upright_margin
             ? best_upright
             : best;
}

PoseTreeBuilder::Ranked PoseTreeBuilder::best_for_assignment(
    const std::array<int32_t, kNumExtremities>& ends, double longest) {
  Ranked best;
  for (int32_t c : junctions_) {
    distances_from(c, true);
    const Ranked r = rank_candidate(c, ends, longest);
    if (r.rank > best.rank) best = r;
  }
  return best;
}

std::array<int32_t, kNumExtremities> PoseTreeBuilder::temporal_assignment(
    const TemporalHint& hint) const {
  // The assignment of endpoints to the previous extremities with the least summed displacement:
  // dynamic programming over the subsets of endpoints used so far (5 x 2^kMaxEnds states).
  const int count = static_cast<int>(ends_.size());
  const uint32_t full = 1u << count;
  std::array<std::array<double, kNumExtremities>, kMaxEnds> cost{};
  for (int k = 0; k < count; ++k)
    for (int s = 0; s < kNumExtremities; ++s)
      cost[k][s] = (tree_.position[ends_[k]] - hint.extremity_mm[s]).norm();
  // best_[mask]: least cost of giving slots 0..popcount(mask)-1 the endpoints in mask.
  std::fill(assign_cost_.begin(), assign_cost_.begin() + full, kInf);
  assign_cost_[0] = 0;
  for (uint32_t mask = 0; mask < full; ++mask) {
    const int s = std::popcount(mask);
    if (s >= kNumExtremities || assign_cost_[mask] == kInf) continue;
    for (int k = 0; k < count; ++k) {
      if (mask & (1u << k)) continue;
      const uint32_t next = mask | (1u << k);
      const double c = assign_cost_[mask] + cost[k][s];
      if (c < assign_cost_[next]) {
        assign_cost_[next] = c;
        assign_from_[next] = static_cast<int8_t>(k);
      }
    }
  }
  uint32_t best = 0;
  for (uint32_t mask = 0; mask < full; ++mask)
    if (std::popcount(mask) == kNumExtremities &&
        (best == 0 || assign_cost_[mask] < assign_cost_[best]))
      best = mask;
  std::array<int32_t, kNumExtremities> out;
  for (int s = kNumExtremities; s-- > 0;) {
    const int k = assign_from_[best];
    out[s] = ends_[k];
    best &= ~(1u << k);
  }
  return out;
}

void PoseTreeBuilder::walk_path(int32_t from, int32_t to, std::vector<int32_t>& out) const {
  out.clear();
  for (int32_t i = from; i >= 0; i = via_[i]) {
    out.push_back(i);
    if (i == to) break;
  }
}

double PoseTreeBuilder::path_length(const std::vector<int32_t>& path) const {
  double length = 0;
  for (size_t k = 1; k < path.size(); ++k)
    length += (tree_.position[path[k]] - tree_.position[path[k - 1]]).norm();
  return length;
}

// ODR direction of the nodes of `path` whose arc length lies in [from_mm, to_mm], measured from
// the extremity (path front) or from the junction (path back). The result points towards the
// back of the path (up the tree) when measured from the extremity, towards the front (away from
// the torso) when measured from the junction. Zero when fewer than two nodes qualify.
Eigen::Vector3d PoseTreeBuilder::path_direction(const std::vector<int32_t>& path, double from_mm,
                                                double to_mm, bool from_junction) const {
  MomentAccumulator m;
  double arc = 0;
  const int32_t n = static_cast<int32_t>(path.size());
  int32_t first = -1, last = -1;
  for (int32_t k = 0; k < n; ++k) {
    const int32_t idx = from_junction ? n - 1 - k : k;
    if (k > 0) {
      const int32_t prev = from_junction ? idx + 1 : idx - 1;
      arc += (tree_.position[path[idx]] - tree_.position[path[prev]]).norm();
    }
    if (arc > to_mm) break;
    if (arc < from_mm) continue;
    m.add(tree_.position[path[idx]]);
    if (first < 0) first = path[idx];
    last = path[idx];
  }
  if (m.count() < 2) return Eigen::Vector3d::Zero();
  Eigen::Vector3d d = fit_line(m).direction;
  const Eigen::Vector3d along = tree_.position[last] - tree_.position[first];
  if (d.dot(along) < 0) d = -d;  // along the walk: up the tree, or away from the torso
  return d;
}

void PoseTreeBuilder::label_parts() {
  const size_t n = tree_.position.size();
  tree_.part.assign(n, Part::Unlabelled);
  auto paint = [&](const std::vector<int32_t>& path, Part part, bool skip_last) {
    const size_t count = skip_last && !path.empty() ? path.size() - 1 : path.size();
    for (size_t k = 0; k < count; ++k)
      if (tree_.part[path[k]] == Part::Unlabelled) tree_.part[path[k]] = part;
  };
  paint(tree_.torso_path, Part::Torso, false);
  paint(tree_.limb_path[static_cast<int>(Extremity::Head)], Part::Neck, true);
  paint(tree_.limb_path[static_cast<int>(Extremity::LHand)], Part::LArm, true);
  paint(tree_.limb_path[static_cast<int>(Extremity::RHand)], Part::RArm, true);
  paint(tree_.limb_path[static_cast<int>(Extremity::LFoot)], Part::LLeg, true);
  paint(tree_.limb_path[static_cast<int>(Extremity::RFoot)], Part::RLeg, true);
  // Pruned stubs take the part they hang from: down the tree, then up, then down again.
  for (size_t i = 1; i < n; ++i)
    if (tree_.part[i] == Part::Unlabelled) tree_.part[i] = tree_.part[tree_.parent[i]];
  for (size_t i = n; i-- > 1;)
    if (tree_.part[tree_.parent[i]] == Part::Unlabelled)
      tree_.part[tree_.parent[i]] = tree_.part[i];
  for (size_t i = 1; i < n; ++i)
    if (tree_.part[i] == Part::Unlabelled) tree_.part[i] = tree_.part[tree_.parent[i]];
}

// The body frame (up, forward, left) and which limb of each pair is left; false when no
// forward direction can be found.
bool PoseTreeBuilder::orient(const TemporalHint& hint, double stature) {
  const double thigh_mm = bone_ratio(Joint::LKne) * stature;
  tree_.up = torso_up(tree_);
  if (!settle_forward(hint, stature, thigh_mm)) return false;
  tree_.left = tree_.up.cross(tree_.forward);
  settle_arms(hint, stature);
  settle_legs(hint, stature, thigh_mm);
  auto& paths = tree_.limb_path;
  for (int s = 0; s < kNumExtremities; ++s) tree_.extremity[s] = paths[s].front();
  return true;
}

// Algorithm 5: joint normals of ankle and knee, forward = normal x torso; the previous frame's
// forward when the legs give none. `up` is a copy and `thigh` comes from orient() (settle_legs
// uses it too) on purpose: so the compiler forms the same FMAs (-march=native) as when this was
// part of orient(), and the estimates stay bit-identical.
bool PoseTreeBuilder::settle_forward(const TemporalHint& hint, double stature, double thigh) {
  const Eigen::Vector3d up = tree_.up;
  const auto& paths = tree_.limb_path;
  const double foot = (bone_ratio(Joint::LToe) + bone_ratio(Joint::LFoot)) * stature;
  const double lleg = bone_ratio(Joint::LAnk) * stature;
  const double leg1 = path_length(paths[kFoot1]), leg2 = path_length(paths[kFoot2]);
  const bool use_ankles = std::abs(leg1 - leg2) <= 2 * foot;  // a degenerate foot: skip ankles
  Eigen::Vector3d forward = Eigen::Vector3d::Zero();
  for (int s : {kFoot1, kFoot2}) {
    const Eigen::Vector3d v_foot = path_direction(paths[s], 0, foot, false);
    const Eigen::Vector3d v_lleg = path_direction(paths[s], foot, foot + lleg, false);
    const Eigen::Vector3d v_thigh =
        path_direction(paths[s], foot + lleg, foot + lleg + thigh, false);
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    if (use_ankles && !v_foot.isZero() && !v_lleg.isZero() &&
        angle_between(v_foot, v_lleg) > params_.bend_min_deg * kDeg)
      normal += v_foot.cross(v_lleg).normalized();
    if (!v_lleg.isZero() && !v_thigh.isZero() &&
        angle_between(v_lleg, v_thigh) > params_.bend_min_deg * kDeg)
      normal += v_lleg.cross(-v_thigh).normalized();
    if (normal.norm() > 1e-6) forward += normal.normalized().cross(up).normalized();
  }
  forward -= up * up.dot(forward);
  tree_.forward_from_previous = false;
  if (forward.norm() <
      params_.min_forward_norm) {  // straight legs without feet, or the two legs disagree
    if (!hint.valid) return false;
    forward = hint.forward - up * up.dot(hint.forward);
    if (forward.norm() < 1e-6) return false;
    tree_.forward_from_previous = true;
  }
  tree_.forward = forward.normalized();
  return true;
}

// Which of the limbs in slots a and b is left; a `weak` geometric decision defers to the
// previous frame's positions.
void PoseTreeBuilder::settle_sides(int a, int b, bool first_left, bool weak,
                                   const TemporalHint& hint, Extremity hint_left,
                                   Extremity hint_right) {
  auto& paths = tree_.limb_path;
  if (weak && hint.valid) {
    const Eigen::Vector3d& p1 = tree_.position[paths[a].front()];
    const Eigen::Vector3d& p2 = tree_.position[paths[b].front()];
    const Eigen::Vector3d& l = hint.extremity_mm[static_cast<int>(hint_left)];
    const Eigen::Vector3d& r = hint.extremity_mm[static_cast<int>(hint_right)];
    first_left = (p1 - l).norm() + (p2 - r).norm() <= (p2 - l).norm() + (p1 - r).norm();
  }
  if (!first_left) {
    std::swap(paths[a], paths[b]);
    std::swap(tree_.limb_score[a], tree_.limb_score[b]);
  }
}

// Arms, algorithm 6: lines through the nodes nearest the torso, pointing away from it.
void PoseTreeBuilder::settle_arms(const TemporalHint& hint, double stature) {
  const auto& paths = tree_.limb_path;
  const double set_mm = params_.arm_side_shoulder_widths * bone_ratio(Joint::LSho) * stature;
  const Eigen::Vector3d v1 = path_direction(paths[kHand1], 0, set_mm, true);
  const Eigen::Vector3d v2 = path_direction(paths[kHand2], 0, set_mm, true);
  const Eigen::Vector3d& f = tree_.forward;
  const Eigen::Vector3d& l = tree_.left;
  bool first_left;
  double margin;
  const double d1 = l.dot(v1), d2 = l.dot(v2);
  if ((d1 > 0) == (d2 > 0)) {  // both to one side: the one further back (front) is left
    const double a1 = angle_between(f, v1), a2 = angle_between(f, v2);
    first_left = d1 > 0 ? a1 > a2 : a1 < a2;
    margin = std::abs(a1 - a2);
  } else {
    const double a1 = angle_between(l, v1), a2 = angle_between(l, v2);
    first_left = a1 < a2;
    margin = std::abs(a1 - a2);
  }
  tree_.lr_margin_deg = margin / kDeg;
  settle_sides(kHand1, kHand2, first_left, margin < params_.lr_min_margin_deg * kDeg, hint,
               Extremity::LHand, Extremity::RHand);
}

// Legs: where the two thighs sit along the left axis, relative to the pelvis. Algorithm 6's
// hip-line angles are unreliable here: the leg branches leave the crotch nearly parallel
// whenever the legs are close, and the angle comparison then follows noise.
void PoseTreeBuilder::settle_legs(const TemporalHint& hint, double stature, double thigh) {
  const auto& paths = tree_.limb_path;
  const double set_mm = bone_ratio(Joint::LHip) * stature + params_.leg_side_thighs * thigh;
  auto lateral = [&](const std::vector<int32_t>& path) {
    MomentAccumulator m;
    double arc = 0;
    for (size_t k = path.size(); k-- > 0;) {
      if (k + 1 < path.size())
        arc += (tree_.position[path[k]] - tree_.position[path[k + 1]]).norm();
      if (arc > set_mm) break;
      m.add(tree_.position[path[k]]);
    }
    return tree_.left.dot(m.centroid() - tree_.position[tree_.pelvis]);
  };
  const double d1 = lateral(paths[kFoot1]), d2 = lateral(paths[kFoot2]);
  tree_.leg_margin_mm = std::abs(d1 - d2);
  settle_sides(kFoot1, kFoot2, d1 > d2, tree_.leg_margin_mm < params_.lr_min_margin_mm, hint,
               Extremity::LFoot, Extremity::RFoot);
}

const LabelledTree& PoseTreeBuilder::build(std::span<const Eigen::Vector3i> voxels,
                                           const VoxelGridSpec& grid, const TemporalHint& hint) {
  reset(grid.voxel_mm);
  grow_tree(voxels, grid);
  const size_t n = tree_.position.size();
  if (n < 8) {
    invalidate(n == 0 ? "no skeleton voxels" : "skeleton too small");
    return tree_;
  }
  if (reaches_volume_side(grid)) {
    invalidate("the skeleton reaches the side of the capture volume: the person is partly outside");
    return tree_;
  }
  const double longest = longest_path();
  tree_.longest_path_mm = longest;
  if (!prune(longest)) {
    invalidate(branches_.size() < kNumExtremities ? "fewer than five extremities" : "no junction");
    return tree_;
  }
  const Ranked best = choose_labelling(hint, longest);
  tree_.quality = best.quality;
  tree_.limb_score = best.factor;
  if (best.origin < 0) {
    invalidate("no origin candidate");
    return tree_;
  }
  tree_.origin = best.origin;
  for (size_t k = 0; k < ends_.size(); ++k)
    if (std::find(best.ends.begin(), best.ends.end(), ends_[k]) == best.ends.end())
      remove_branch(ends_[k], end_junction_[k]);
  trace_paths(best);

  const char* why = rejection(best);
  // A labelling rejected on its rank alone is complete: it is oriented too, so that it can be
  // fitted as a guess (LabelledTree::low_rank).
  const bool rank_only = why != nullptr && tree_.pelvis != best.origin;
  if (why == nullptr || rank_only) {
    const bool oriented = orient(hint, longest / ratio::kLongestPath);
    if (why == nullptr && !oriented) why = "no forward direction";
    tree_.low_rank = rank_only && oriented;
  }
  if (why != nullptr) {
    invalidate(why);
    const auto& paths = tree_.limb_path;
    for (int s = 0; s < kNumExtremities; ++s)
      tree_.extremity[s] = paths[s].empty() ? -1 : paths[s].front();
  }
  label_parts();
  tree_.valid = why == nullptr;
  return tree_;
}

void PoseTreeBuilder::reset(double voxel_mm) {
  tree_.valid = false;
  tree_.why = "";
  tree_.origin = tree_.pelvis = -1;
  tree_.quality = 0;
  tree_.used_temporal_labels = tree_.forward_from_previous = tree_.low_rank = false;
  tree_.voxel_mm = voxel_mm;
  tree_.torso_path.clear();
  for (auto& p : tree_.limb_path) p.clear();
  tree_.part.clear();
}

// A node near the sides or the top of the capture volume: the person is cut off there.
bool PoseTreeBuilder::reaches_volume_side(const VoxelGridSpec& grid) const {
  const Eigen::Vector3d low = grid.origin_mm.array() + (params_.edge_voxels + 1) * grid.voxel_mm;
  const Eigen::Vector3d high =
      grid.origin_mm.array() +
      (grid.dims.cast<double>().array() - params_.edge_voxels - 1) * grid.voxel_mm;
  for (const Eigen::Vector3d& p : tree_.position)
    if (p.x() < low.x() || p.y() < low.y() || p.x() > high.x() || p.y() > high.y() ||
        p.z() > high.z())
      return true;
  return false;
}

// The best structural labelling, or the previous frame's correspondence when it implies other
// extremity classes and ranks nearly as well.
PoseTreeBuilder::Ranked PoseTreeBuilder::choose_labelling(const TemporalHint& hint,
                                                          double longest) {
  Ranked best = best_structural(longest);
  if (!hint.valid) return best;
  const auto temporal = temporal_assignment(hint);
  auto same_set = [&](int a, int b, const std::array<int32_t, kNumExtremities>& e) {
    return (e[a] == best.ends[a] && e[b] == best.ends[b]) ||
           (e[a] == best.ends[b] && e[b] == best.ends[a]);
  };
  if (temporal[kHeadSlot] != best.ends[kHeadSlot] || !same_set(kHand1, kHand2, temporal) ||
      !same_set(kFoot1, kFoot2, temporal)) {
    const Ranked t = best_for_assignment(temporal, longest);
    if (t.quality >= best.quality - params_.temporal_quality_margin) {
      best = t;
      tree_.used_temporal_labels = true;
    }
  }
  return best;
}

// Paths from every extremity to the origin; the pelvis is where the two foot paths meet, and
// the torso runs from it to the origin.
void PoseTreeBuilder::trace_paths(const Ranked& best) {
  distances_from(best.origin, true);
  auto& paths = tree_.limb_path;
  for (int s = 0; s < kNumExtremities; ++s) walk_path(best.ends[s], best.origin, paths[s]);
  mark_.assign(tree_.position.size(), 0);
  for (int32_t i : paths[kFoot1]) mark_[i] = 1;
  int32_t pelvis = best.origin;
  for (int32_t i : paths[kFoot2])
    if (mark_[i]) {
      pelvis = i;
      break;
    }
  tree_.pelvis = pelvis;
  for (int s : {kFoot1, kFoot2}) {
    const auto at = std::find(paths[s].begin(), paths[s].end(), pelvis);
    paths[s].erase(at + 1, paths[s].end());
  }
  walk_path(pelvis, best.origin, tree_.torso_path);
  std::reverse(tree_.torso_path.begin(), tree_.torso_path.end());
}

// Why the labelling is not a body, or nullptr. The rank checks come after the torso's: a
// labelling that fails only them is a complete one (build() keeps it as low_rank).
const char* PoseTreeBuilder::rejection(const Ranked& best) const {
  if (tree_.pelvis == best.origin) return "no torso between the arms and the legs";
  if (best.quality < params_.min_quality) return "labelling ranks below the minimum quality";
  if (*std::min_element(best.factor.begin(), best.factor.end()) < params_.min_factor)
    return "a limb is far from its expected length";
  return nullptr;
}

}  // namespace hullpose::pose
