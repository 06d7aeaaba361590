#pragma once
// Pose tree and body-part labels from curve-skeleton voxels (thesis paper 5).
//
// Lifecycle: construct once; call build() per frame. All buffers are owned and reused, so after
// the first frames of a given size build() does not allocate.
//
// Steps (paper 5, algorithms 1-6, with the changes documented in pose_tree.cpp):
//   1. breadth-first tree over 26-adjacency from the top-most voxel of the largest component,
//      voxels side by side at the same depth collapsed into one node (thick CK3 parts);
//   2. prune spurious leaf branches (anthropometric threshold relative to the longest path),
//      then keep the nine longest terminal branches (head, two hands, two feet, and up to four
//      spurs that the ranking leaves out), never fewer than five;
//   3. rank origin-node candidates (eq. 1-4) and label extremities by distance, or by temporal
//      correspondence with the previous valid frame;
//   4. segment into neck, torso, arms and legs;
//   5. forward vector from the legs (alg. 5) and left/right from shoulder and hip lines (alg. 6);
//   6. validity: see TreeParams and docs in pose_tree.cpp (including: the skeleton must not
//      touch the sides or the top of the capture volume).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/fusion/bit_grid.hpp"

namespace hullpose::pose {

// The five extremities in the order the labelled tree reports them.
enum class Extremity : uint8_t { Head, LHand, RHand, LFoot, RFoot };
inline constexpr int kNumExtremities = 5;

enum class Part : uint8_t { Unlabelled, Neck, Torso, LArm, RArm, LLeg, RLeg };

struct TreeParams {
  // Leaf branches shorter than this fraction of the longest path are spurious. The head's branch
  // is ~0.125 of it on an ideal tree but shrinks to ~0.05 when a raised arm's branch point moves
  // up the neck, so this stays low and the ranking (with the head's direction) drops the longer
  // spurs. (Synthetic CMU 55_01 at 128^3: 0.055 gave 98.7 % valid, 0.04 99.1 %, 0.03 97.6 %.)
  double prune_ratio = 0.04;
  // Scale of the "shortened limb" penalty of eq. 3-4, as a fraction of the longest path. The
  // paper's 1/(1 + (dr - db)) has no unit; in mm it would punish a one-voxel offset as hard as a
  // missing arm.
  double branch_offset_ratio = 0.04;
  // Junctions closer than this many voxels are one junction split by a 2-voxel-thick part.
  double junction_merge_voxels = 3.5;
  // Validity (replaces the paper's fixed rank threshold): the best labelling's geometric-mean
  // rank factor and every single factor must reach these, the torso must exist, and the
  // skeleton must not be too small for a person of the running stature.
  // (0.5 / 0.2 on synthetic CMU 55_01 at 128^3: 99.1 % valid at 33.3 mm MPJPE; min_factor
  // 0.25 gave 96.2 % at 32.6 mm, 0.3 92.0 % at 32.3 mm.)
  double min_quality = 0.5;
  double min_factor = 0.2;
  // Left/right decisions with less angular margin than this defer to temporal correspondence
  // when a previous valid frame exists.
  double lr_min_margin_deg = 8;  // arms: angular margin of algorithm 6
  double lr_min_margin_mm = 30;  // legs: lateral separation of the thighs
  // How much of each path the left/right decision reads, from its junction: arms 1.5 shoulder
  // widths (the upper arm, past the shoulder node, before the elbow bends it), legs the hip
  // offset plus half a thigh (above the knee). Body proportions, not tuned to a clip.
  double arm_side_shoulder_widths = 1.5;
  double leg_side_thighs = 0.5;
  // An upside-down labelling (origin below the pelvis) wins only if it ranks this much better
  // than the best upright one: people stand far more often than they stand on their hands, and
  // on a skeleton whose arms hang beside the legs the two readings rank alike.
  double upright_margin = 0.1;
  // A skeleton that comes this close (voxels) to a side or the top of the grid belongs to a hull
  // cut off by the capture volume: part of the person is outside, and a limb may be missing or
  // cut short, so the frame is invalid. (Walks that leave the volume: 02_01, 08_02, 49_08.)
  int edge_voxels = 1;
  // Algorithm 5: a joint normal counts only if the joint is bent by more than this.
  double bend_min_deg = 12;
  // Algorithm 5's summed forward vector (up to 2 unit normals and 2 feet, projected off the
  // torso axis) shorter than this has no direction (straight legs without feet, or legs that
  // disagree): the previous frame's forward is used. 0.3 is about one unit vector 70 degrees off
  // the horizontal plane.
  double min_forward_norm = 0.3;
  // The temporal correspondence of the extremities chooses the labels only when the labelling it
  // implies ranks within this of the best structural one (a quality is in 0..1; README).
  double temporal_quality_margin = 0.05;
};

// What the previous valid frame tells the next one.
struct TemporalHint {
  bool valid = false;
  std::array<Eigen::Vector3d, kNumExtremities> extremity_mm{};
  Eigen::Vector3d forward = Eigen::Vector3d::UnitY();
};

struct LabelledTree {
  bool valid = false;
  const char* why = "";  // static text: why the tree is not valid

  // Every node of the tree, in breadth-first order from the root (top-most voxel).
  std::vector<Eigen::Vector3d> position;  // mm, voxel centres
  std::vector<int32_t> parent;            // -1 at the root
  std::vector<Part> part;

  int32_t origin = -1;                               // arms, neck and torso meet here
  int32_t pelvis = -1;                               // legs meet the torso here
  std::array<int32_t, kNumExtremities> extremity{};  // node ids in Extremity order
  // Node paths from each extremity to its junction (origin for head and hands, pelvis for feet),
  // extremity first, junction last; torso path from origin to pelvis.
  std::array<std::vector<int32_t>, kNumExtremities> limb_path;
  std::vector<int32_t> torso_path;

  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();       // torso direction, pelvis -> origin
  Eigen::Vector3d forward = Eigen::Vector3d::UnitY();  // facing, orthogonal to up
  Eigen::Vector3d left = -Eigen::Vector3d::UnitX();    // up x forward
  double voxel_mm = 0;
  double longest_path_mm = 0;
  double quality = 0;                                // geometric mean of rank factors, 0..1
  std::array<double, kNumExtremities> limb_score{};  // rank factor per extremity, 0..1
  double lr_margin_deg = 0;                          // arms: algorithm 6's angular margin
  double leg_margin_mm = 0;                          // legs: lateral separation of the thighs
  bool used_temporal_labels = false;
  bool forward_from_previous = false;
  // Not valid, but complete (a torso, five extremities, left and right settled): the labelling
  // ranks below min_quality or one limb below min_factor. A guess, not a reading
  // (PoseParams::fit_low_rank).
  bool low_rank = false;
};

class PoseTreeBuilder {
 public:
  explicit PoseTreeBuilder(TreeParams params = {});
  // Builds and labels the tree of one frame's skeleton voxels. `hint` carries the previous
  // valid frame (temporal correspondence); pass an invalid hint on the first frame. Voxels
  // outside the grid or repeated are ignored. Never throws on bad data: an unusable skeleton
  // gives an invalid tree with a reason.
  const LabelledTree& build(std::span<const Eigen::Vector3i> voxels, const VoxelGridSpec& grid,
                            const TemporalHint& hint);
  const LabelledTree& tree() const { return tree_; }

 private:
  struct Branch {
    int32_t end;       // endpoint node
    int32_t junction;  // first node of degree >= 3 (or the other end of a bare path)
    double length;     // mm, endpoint to junction
  };
  struct Ranked {
    double rank = 0, quality = 0;
    bool upright = false;  // the origin above the pelvis (z up)
    int32_t origin = -1;
    std::array<int32_t, kNumExtremities> ends{};  // Head, hand, hand, foot, foot (endpoint idx)
    std::array<double, kNumExtremities> factor{};
  };

  // build()'s steps, in order.
  void reset(double voxel_mm);
  void grow_tree(std::span<const Eigen::Vector3i> voxels, const VoxelGridSpec& grid);
  bool reaches_volume_side(const VoxelGridSpec& grid) const;
  Ranked choose_labelling(const TemporalHint& hint, double longest);
  void trace_paths(const Ranked& best);
  const char* rejection(const Ranked& best) const;
  bool orient(const TemporalHint& hint, double stature);
  // grow_tree()'s steps.
  void index_voxels(std::span<const Eigen::Vector3i> voxels, const VoxelGridSpec& grid);
  void index_neighbours(std::span<const Eigen::Vector3i> voxels, const VoxelGridSpec& grid);
  template <typename Visit>
  void for_each_neighbour(int32_t i, Visit&& visit) const;
  int32_t largest_component_root(std::span<const Eigen::Vector3i> voxels,
                                 const VoxelGridSpec& grid);
  void depths_from(size_t voxel_count, int32_t root);
  void one_node_per_depth_layer(std::span<const Eigen::Vector3i> voxels, const VoxelGridSpec& grid);
  void build_adjacency();
  // orient()'s steps.
  bool settle_forward(const TemporalHint& hint, double stature, double thigh);
  void settle_arms(const TemporalHint& hint, double stature);
  void settle_legs(const TemporalHint& hint, double stature, double thigh);
  void settle_sides(int a, int b, bool first_left, bool weak, const TemporalHint& hint,
                    Extremity hint_left, Extremity hint_right);
  void distances_from(int32_t source, bool alive_only);
  double longest_path();
  void collect_branches();
  bool prune(double longest);
  void remove_branch(int32_t end, int32_t junction);
  Ranked rank_candidate(int32_t candidate, const std::array<int32_t, kNumExtremities>& ends,
                        double longest) const;
  Ranked best_structural(double longest);
  Ranked best_for_assignment(const std::array<int32_t, kNumExtremities>& ends, double longest);
  std::array<int32_t, kNumExtremities> temporal_assignment(const TemporalHint& hint) const;
  int32_t meeting_node(int32_t a, int32_t b) const;
  void walk_path(int32_t from, int32_t to, std::vector<int32_t>& out) const;
  void label_parts();
  Eigen::Vector3d path_direction(const std::vector<int32_t>& path, double from_mm, double to_mm,
                                 bool from_junction) const;
  double path_length(const std::vector<int32_t>& path) const;
  void invalidate(const char* why);

  TreeParams params_;
  LabelledTree tree_;
  VoxelGridSpec grid_;
  std::vector<int32_t> lookup_;  // grid index -> input voxel index, -1 elsewhere
  fusion::BitGrid occupied_;     // the voxels of lookup_ that are set
  std::vector<int32_t> neighbour_begin_, neighbours_;  // per input voxel: its 26-neighbours (CSR)
  std::vector<int32_t> component_;                     // per input voxel: connected component
  std::vector<int32_t> depth_;    // per input voxel: breadth-first depth from the root
  std::vector<int32_t> cluster_;  // per input voxel: tree node
  std::vector<int32_t> stack_;
  std::vector<int32_t> adj_begin_, adj_;  // tree adjacency (CSR)
  std::vector<uint8_t> alive_;
  std::vector<int32_t> degree_;
  std::vector<double> dist_;
  std::vector<int32_t> via_;   // parent in the last distances_from() traversal
  std::vector<int32_t> hops_;  // and the number of steps from its source
  std::vector<int32_t> queue_;
  std::vector<uint8_t> mark_;
  std::vector<Branch> branches_;
  std::vector<int32_t> junctions_;
  // Endpoints after pruning: five limbs, or up to four more spurs the ranking must leave out.
  static constexpr int kMaxEnds = kNumExtremities + 4;
  std::vector<int32_t> ends_;
  std::array<double, kMaxEnds> end_branch_{};     // db per endpoint
  std::array<int32_t, kMaxEnds> end_junction_{};  // where its terminal branch meets the tree
  mutable std::array<double, 1u << kMaxEnds> assign_cost_{};  // temporal_assignment() DP
  mutable std::array<int8_t, 1u << kMaxEnds> assign_from_{};
};

}  // namespace hullpose::pose
