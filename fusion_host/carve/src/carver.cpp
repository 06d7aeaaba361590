#include "hullpose/carve/carver.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <opencv2/imgproc.hpp>

#include "hullpose/carve/column_counts.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"

namespace hullpose::carve {

VoxelProjector::VoxelProjector(const CameraModel& c) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) params_.r[3 * i + j] = c.R(i, j);
    params_.t[i] = c.t[i];
  }
  params_.fx = c.fx;
  params_.fy = c.fy;
  params_.cx = c.cx;
  params_.cy = c.cy;
  params_.k1 = c.dist[0];
  params_.k2 = c.dist[1];
  params_.p1 = c.dist[2];
  params_.p2 = c.dist[3];
  params_.k3 = c.dist[4];
  params_.width = c.width;
  params_.height = c.height;
}

namespace {

constexpr int kLevels = 4;  // node sizes F, 2F, 4F, 8F voxels; the top level are the cells
constexpr int kMaxCameras = 64;
constexpr int kMaxFinestVoxels = 512;  // finest nodes of up to 8³ voxels (resolution < 576)
// Per-voxel pixel tables (2 bytes per voxel and camera) up to this size; beyond, voxels of
// undecided finest nodes are projected on the fly (same projector, same result).
constexpr size_t kMaxPixelTableBytes = size_t{64} << 20;
constexpr uint16_t kUnseen = 0xffff;

// Bounding rectangle (inclusive) of the pixels of a node's voxel centres in one camera.
struct Rect {
  int16_t x0 = INT16_MAX, y0 = INT16_MAX, x1 = INT16_MIN, y1 = INT16_MIN;
  uint8_t unseen = 0;  // some voxel of the node is behind the camera or outside the image
  void add(int x, int y) {
    x0 = static_cast<int16_t>(std::min<int>(x0, x));
    y0 = static_cast<int16_t>(std::min<int>(y0, y));
    x1 = static_cast<int16_t>(std::max<int>(x1, x));
    y1 = static_cast<int16_t>(std::max<int>(y1, y));
  }
  void add(const Rect& r) {
    if (r.x0 <= r.x1) {
      add(r.x0, r.y0);
      add(r.x1, r.y1);
    }
    unseen |= r.unseen;
  }
};

// Every voxel of the grid with its centre and its finest node, visited in parallel by z-slabs
// of finest nodes: all voxels of one node go to one thread, so per-node writes need no lock.
template <typename Plan, typename Visit>
void for_each_voxel_by_finest_node(const VoxelGridSpec& grid, const Plan& p, Visit&& visit) {
  const Eigen::Vector3i d = grid.dims;
#pragma omp parallel for schedule(dynamic) num_threads(std::max(1, omp_get_num_procs()))
  for (int nz = 0; nz < p.nodes[0].z(); ++nz)
    for (int z = nz * p.finest; z < std::min(d.z(), (nz + 1) * p.finest); ++z)
      for (int y = 0; y < d.y(); ++y)
        for (int x = 0; x < d.x(); ++x)
          visit(x, y, z, grid.centre_mm({x, y, z}),
                p.node_index(0, x / p.finest, y / p.finest, nz));
}

}  // namespace

struct Carver::Precomputed {
  int finest = 2;                                // F
  std::array<Eigen::Vector3i, kLevels> nodes;    // node counts per level
  std::array<std::vector<Rect>, kLevels> rects;  // [node * cameras + camera]
  // Optional: the pixel of every voxel centre relative to its finest node's rectangle,
  // (dy << 8 | dx), or kUnseen; [(node * cameras + camera) * F³ + voxel in node].
  std::vector<uint16_t> pixels;
  std::vector<uint8_t> wide;  // [node * cameras + camera]: rectangle wider than 255 px, no table
  int size(int level) const { return finest << level; }
  // Nodes are stored top cell by top cell, each cell's subtree in Morton order, so that the
  // depth-first visit of a cell reads contiguous memory at every level.
  size_t node_count(int level) const {
    return static_cast<size_t>(nodes[kLevels - 1].prod()) << (3 * (kLevels - 1 - level));
  }
  size_t node_index(int level, int x, int y, int z) const {
    const int up = kLevels - 1 - level;
    const Eigen::Vector3i& top = nodes[kLevels - 1];
    const size_t cell = (static_cast<size_t>(z >> up) * top.y() + (y >> up)) * top.x() + (x >> up);
    size_t morton = 0;
    for (int b = 0; b < up; ++b)
      morton |= static_cast<size_t>((x >> b & 1) | (y >> b & 1) << 1 | (z >> b & 1) << 2)
                << (3 * b);
    return cell << (3 * up) | morton;
  }
};

struct Carver::Frame {
  std::vector<int> present;
  std::vector<ColumnCounts> counts;   // per camera
  std::vector<const uint8_t*> bases;  // per camera: the mask's first pixel and row step
  std::vector<size_t> steps;
};

cv::Rect foreground_box(const cv::Mat& view, std::span<const PixelRoi> fg_boxes, size_t camera) {
  if (fg_boxes.empty()) return cv::boundingRect(view);
  const PixelRoi& r = fg_boxes[camera];
  return cv::Rect(r.x, r.y, r.width, r.height) & cv::Rect(0, 0, view.cols, view.rows);
}

Carver::Carver(const Rig& rig, const CarveOptions& options)
    : rig_(rig),
      options_(options),
      pre_(std::make_unique<Precomputed>()),
      frame_(std::make_unique<Frame>()) {
  rig_.validate();
  const int ncam = static_cast<int>(rig_.cameras.size());
  HULLPOSE_THROW_UNLESS(ncam >= 1 && ncam <= kMaxCameras,
                        "carve: rig '" << rig_.rig_id << "' has " << ncam
                                       << " cameras, supported 1.." << kMaxCameras);
  HULLPOSE_THROW_UNLESS(options.tolerance >= 0 && options.tolerance < ncam,
                        "carve: tolerance " << options.tolerance << " must be in 0.." << ncam - 1
                                            << " for rig '" << rig_.rig_id << "'");
  HULLPOSE_THROW_UNLESS(options.threads >= 1,
                        "carve: threads must be >= 1, got " << options.threads);
  grid_ = VoxelGridSpec::fit(rig_.volume, options.resolution);
  for (const CameraModel& c : rig_.cameras) {
    HULLPOSE_THROW_UNLESS(
        c.width < INT16_MAX && c.height < INT16_MAX,
        "carve: camera " << c.id << " image " << c.width << "x" << c.height << " too large");
    projectors_.emplace_back(c);
  }

  // Finest node size: 4 voxels, larger for big grids so the tables stay near 64³ nodes. Measured
  // on CMU 55_01 (bench_fusion carve/N): nodes of 4 beat 2, 3 and 8 at 64³ and 128³; with 2 the
  // rectangle tests near the surface cost more than the per-voxel tests they save.
  Precomputed& p = *pre_;
  p.finest = std::max(4, grid_.dims.maxCoeff() / 64);
  HULLPOSE_THROW_UNLESS(p.finest * p.finest * p.finest <= kMaxFinestVoxels,
                        "carve: resolution " << options.resolution << " too large (at most 575)");
  for (int l = 0; l < kLevels; ++l) {
    const int s = p.size(l);
    p.nodes[static_cast<size_t>(l)] = (grid_.dims.array() + s - 1) / s;
  }
  for (int l = 0; l < kLevels; ++l)
    p.rects[static_cast<size_t>(l)].assign(p.node_count(l) * static_cast<size_t>(ncam), Rect{});
  // Finest level from every voxel centre, with the projector the reference uses.
  std::vector<Rect>& fine = p.rects[0];
  for_each_voxel_by_finest_node(
      grid_, p, [&](int, int, int, const Eigen::Vector3d& centre, size_t node) {
        for (int c = 0; c < ncam; ++c) {
          Rect& r = fine[node * static_cast<size_t>(ncam) + static_cast<size_t>(c)];
          int px, py;
          if (projectors_[static_cast<size_t>(c)].pixel(centre, px, py))
            r.add(px, py);
          else
            r.unseen = 1;
        }
      });
  // Per-voxel pixel table, relative to the finest rectangles just computed.
  const size_t f3 = static_cast<size_t>(p.finest) * p.finest * p.finest;
  if (fine.size() * f3 * sizeof(uint16_t) <= kMaxPixelTableBytes) {
    p.pixels.assign(fine.size() * f3, kUnseen);
    p.wide.assign(fine.size(), 0);
    for (size_t i = 0; i < fine.size(); ++i)
      p.wide[i] = fine[i].x0 <= fine[i].x1 &&
                  (fine[i].x1 - fine[i].x0 > 254 || fine[i].y1 - fine[i].y0 > 254);
    for_each_voxel_by_finest_node(
        grid_, p, [&](int x, int y, int z, const Eigen::Vector3d& centre, size_t node) {
          const size_t local = static_cast<size_t>(
              ((z % p.finest) * p.finest + y % p.finest) * p.finest + x % p.finest);
          for (int c = 0; c < ncam; ++c) {
            const size_t nc = node * static_cast<size_t>(ncam) + static_cast<size_t>(c);
            int px, py;
            if (!p.wide[nc] && projectors_[static_cast<size_t>(c)].pixel(centre, px, py))
              p.pixels[nc * f3 + local] =
                  static_cast<uint16_t>((py - fine[nc].y0) << 8 | (px - fine[nc].x0));
          }
        });
  }
  for (int l = 1; l < kLevels; ++l) {
    const Eigen::Vector3i& m = p.nodes[static_cast<size_t>(l - 1)];
    for (int z = 0; z < m.z(); ++z)
      for (int y = 0; y < m.y(); ++y)
        for (int x = 0; x < m.x(); ++x)
          for (int c = 0; c < ncam; ++c)
            p.rects[static_cast<size_t>(l)]
                   [p.node_index(l, x / 2, y / 2, z / 2) * static_cast<size_t>(ncam) +
                    static_cast<size_t>(c)]
                       .add(p.rects[static_cast<size_t>(l - 1)]
                                   [p.node_index(l - 1, x, y, z) * static_cast<size_t>(ncam) +
                                    static_cast<size_t>(c)]);
  }

  Frame& f = *frame_;
  f.counts.resize(static_cast<size_t>(ncam));
  f.bases.assign(static_cast<size_t>(ncam), nullptr);
  f.steps.assign(static_cast<size_t>(ncam), 0);
  for (int c = 0; c < ncam; ++c)
    f.counts[static_cast<size_t>(c)].reserve(rig_.cameras[static_cast<size_t>(c)].width,
                                             rig_.cameras[static_cast<size_t>(c)].height);
  f.present.reserve(static_cast<size_t>(ncam));
}

Carver::~Carver() = default;

HULLPOSE_LOG_CATEGORY(Carve, "carve")

bool Carver::begin_carve(std::span<const cv::Mat> views, std::span<const PixelRoi> fg_boxes,
                         fusion::BitGrid& hull, CarveReport& report,
                         std::vector<int>& present) const {
  HULLPOSE_THROW_UNLESS(views.size() == rig_.cameras.size(),
                        "carve: " << views.size() << " views for the " << rig_.cameras.size()
                                  << " cameras of rig '" << rig_.rig_id << "'");
  report.missing_cameras.clear();
  report.rejected_cameras.clear();
  present.clear();
  for (size_t c = 0; c < views.size(); ++c) {
    const cv::Mat& m = views[c];
    const CameraModel& cam = rig_.cameras[c];
    if (m.empty()) {
      report.missing_cameras.push_back(cam.id);
    } else if (m.type() != CV_8UC1 || m.cols != cam.width || m.rows != cam.height) {
      report.rejected_cameras.push_back(cam.id);
      HULLPOSE_LOG(Carve, Debug) << "camera " << cam.id << ": mask " << m.cols << "x" << m.rows
                                 << " of type " << m.type() << " skipped (the rig says "
                                 << cam.width << "x" << cam.height << " CV_8UC1)";
    } else {
      present.push_back(static_cast<int>(c));
    }
  }
  report.cameras_used = static_cast<int>(present.size());
  report.valid = report.cameras_used > options_.tolerance;
  HULLPOSE_LOG(Carve, Debug) << report.cameras_used << " of " << views.size() << " cameras carve, "
                             << report.missing_cameras.size() << " sent nothing, "
                             << report.rejected_cameras.size() << " rejected";
  hull.reset(grid_.dims);
  report.voxels = 0;
  if (!report.valid) return false;
  HULLPOSE_THROW_UNLESS(
      fg_boxes.empty() || fg_boxes.size() == views.size(),
      "carve: " << fg_boxes.size() << " foreground boxes for " << views.size() << " views");
  return true;
}

void Carver::carve_brute_force(std::span<const cv::Mat> views, fusion::BitGrid& hull,
                               CarveReport& report) const {
  std::vector<int> present;
  if (!begin_carve(views, {}, hull, report, present)) return;
  std::vector<CameraParams> cams;
  std::vector<MaskView> masks;
  for (int c : present) {
    const cv::Mat& m = views[static_cast<size_t>(c)];
    cams.push_back(projectors_[static_cast<size_t>(c)].params());
    masks.push_back({m.ptr<uint8_t>(0), m.step[0], 0, 0, m.cols, m.rows});
  }
  const int n = static_cast<int>(present.size());
  for (int z = 0; z < grid_.dims.z(); ++z)
    for (int y = 0; y < grid_.dims.y(); ++y)
      for (int x = 0; x < grid_.dims.x(); ++x) {
        const Eigen::Vector3d centre = grid_.centre_mm({x, y, z});
        if (voxel_kept(cams.data(), masks.data(), n, options_.tolerance, centre.x(), centre.y(),
                       centre.z())) {
          hull.set(x, y, z);
          ++report.voxels;
        }
      }
}

// One frame's depth-first visit of the octree (Carver::carve): a node's cameras are classified
// (classify_node), a decided node is filled or dropped, an undecided one split, and at the finest
// level its voxels are tested camera by camera (carve_finest_node).
class Carver::NodeVisit {
 public:
  NodeVisit(const Carver& carver, const Frame& frame, fusion::BitGrid& hull)
      : carver_(carver),
        pre_(*carver.pre_),
        frame_(frame),
        hull_(hull),
        ncam_(carver.rig_.cameras.size()),
        f3_(static_cast<size_t>(pre_.finest) * pre_.finest * pre_.finest),
        k_(carver.options_.tolerance),
        dims_(carver.grid_.dims) {}

  // `mixed` holds the cameras still undecided for this node; `base_miss` the misses so far.
  void visit(int level, const Eigen::Vector3i& node, int base_miss, const int* mixed,
             int nmixed) const {
    const int s = pre_.size(level);
    const Eigen::Vector3i lo = node * s;
    if ((lo.array() >= dims_.array()).any()) return;
    const Eigen::Vector3i hi = (lo.array() + s).min(dims_.array());
    const Rect* rects = &pre_.rects[static_cast<size_t>(level)]
                                   [pre_.node_index(level, node.x(), node.y(), node.z()) * ncam_];
    std::array<int, kMaxCameras> still;
    int nstill = 0;
    if (!classify_node(rects, mixed, nmixed, base_miss, still, nstill)) return;  // missed too often
    if (base_miss + nstill <= k_) {
      fill(lo, hi);  // inside in all but k cameras, whatever the undecided ones say
      return;
    }
    if (level > 0) {
      for (int cz = 0; cz < 2; ++cz)
        for (int cy = 0; cy < 2; ++cy)
          for (int cx = 0; cx < 2; ++cx)
            visit(level - 1, node * 2 + Eigen::Vector3i(cx, cy, cz), base_miss, still.data(),
                  nstill);
      return;
    }
    carve_finest_node(node, lo, hi, rects, base_miss, still.data(), nstill);
  }

 private:
  // kAll also needs every voxel centre of the node seen by the camera.
  Coverage classify(const Rect& r, int c) const {
    if (r.x0 > r.x1) return Coverage::kNone;  // no voxel centre is seen at all
    const Coverage v = frame_.counts[static_cast<size_t>(c)].cover(r.x0, r.y0, r.x1, r.y1);
    return r.unseen && v == Coverage::kAll ? Coverage::kSome : v;
  }

  // Sorts the node's undecided cameras into misses (counted) and still undecided ones; false once
  // more than k cameras miss the whole node.
  bool classify_node(const Rect* rects, const int* mixed, int nmixed, int& base_miss,
                     std::array<int, kMaxCameras>& still, int& nstill) const {
    for (int i = 0; i < nmixed; ++i) {
      const int c = mixed[i];
      switch (classify(rects[c], c)) {
        case Coverage::kAll:
          break;
        case Coverage::kNone:
          if (++base_miss > k_) return false;
          break;
        case Coverage::kSome:
          still[static_cast<size_t>(nstill++)] = c;
          break;
      }
    }
    return true;
  }

  void fill(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi) const {  // [lo, hi)
    for (int z = lo.z(); z < hi.z(); ++z)
      for (int y = lo.y(); y < hi.y(); ++y) {
        uint64_t* row = hull_.row(y, z);
        for (int x = lo.x(); x < hi.x(); ++x) row[x >> 6] |= uint64_t{1} << (x & 63);
      }
  }

  // Finest node: camera by camera over its voxels (the setup of a camera is paid once per node,
  // and a camera that misses every voxel still alive ends the node at once).
  void carve_finest_node(const Eigen::Vector3i& node, const Eigen::Vector3i& lo,
                         const Eigen::Vector3i& hi, const Rect* rects, int base_miss,
                         const int* still, int nstill) const {
    const int s = pre_.finest;
    const size_t node_cams = pre_.node_index(0, node.x(), node.y(), node.z()) * ncam_;
    std::array<uint8_t, kMaxFinestVoxels> misses;
    std::array<uint16_t, kMaxFinestVoxels> alive;
    std::fill_n(misses.begin(), f3_, static_cast<uint8_t>(base_miss));
    size_t nalive = 0;
    for (int z = 0; z < hi.z() - lo.z(); ++z)
      for (int y = 0; y < hi.y() - lo.y(); ++y)
        for (int x = 0; x < hi.x() - lo.x(); ++x)
          alive[nalive++] = static_cast<uint16_t>((z * s + y) * s + x);
    for (int i = 0; i < nstill && nalive > 0; ++i) {
      const int c = still[i];
      const size_t nc = node_cams + static_cast<size_t>(c);
      nalive = !pre_.pixels.empty() && !pre_.wide[nc]
                   ? test_from_table(c, nc, rects[c], misses, alive, nalive)
                   : test_projected(c, lo, misses, alive, nalive);
    }
    for (size_t a = 0; a < nalive; ++a) {
      const uint16_t local = alive[a];
      const int x = lo.x() + local % s, y = lo.y() + local / s % s, z = lo.z() + local / (s * s);
      hull_.row(y, z)[x >> 6] |= uint64_t{1} << (x & 63);
    }
  }

  // The alive voxels' pixels from the per-voxel table; keeps those that hit or may still miss.
  size_t test_from_table(int c, size_t nc, const Rect& rect,
                         std::array<uint8_t, kMaxFinestVoxels>& misses,
                         std::array<uint16_t, kMaxFinestVoxels>& alive, size_t nalive) const {
    const size_t step = frame_.steps[static_cast<size_t>(c)];
    const uint8_t* origin =
        frame_.bases[static_cast<size_t>(c)] + static_cast<size_t>(rect.y0) * step + rect.x0;
    const uint16_t* pix = &pre_.pixels[nc * f3_];
    size_t kept = 0;
    for (size_t a = 0; a < nalive; ++a) {
      const uint16_t local = alive[a];
      const uint16_t v = pix[local];
      const bool hit = v != kUnseen && origin[(v >> 8) * step + (v & 0xff)] != 0;
      if (hit || ++misses[local] <= k_) alive[kept++] = local;
    }
    return kept;
  }

  // The same with each voxel projected now (grids whose table would be too large).
  size_t test_projected(int c, const Eigen::Vector3i& lo,
                        std::array<uint8_t, kMaxFinestVoxels>& misses,
                        std::array<uint16_t, kMaxFinestVoxels>& alive, size_t nalive) const {
    const int s = pre_.finest;
    const size_t step = frame_.steps[static_cast<size_t>(c)];
    const uint8_t* base = frame_.bases[static_cast<size_t>(c)];
    size_t kept = 0;
    for (size_t a = 0; a < nalive; ++a) {
      const uint16_t local = alive[a];
      const Eigen::Vector3i v = lo + Eigen::Vector3i(local % s, local / s % s, local / (s * s));
      int px, py;
      const bool hit =
          carver_.projectors_[static_cast<size_t>(c)].pixel(carver_.grid_.centre_mm(v), px, py) &&
          base[static_cast<size_t>(py) * step + static_cast<size_t>(px)] != 0;
      if (hit || ++misses[local] <= k_) alive[kept++] = local;
    }
    return kept;
  }

  const Carver& carver_;
  const Precomputed& pre_;
  const Frame& frame_;
  fusion::BitGrid& hull_;
  const size_t ncam_, f3_;
  const int k_;
  const Eigen::Vector3i dims_;
};

void Carver::carve(std::span<const cv::Mat> views, fusion::BitGrid& hull, CarveReport& report,
                   std::span<const PixelRoi> fg_boxes) {
  Frame& f = *frame_;
  if (!begin_carve(views, fg_boxes, hull, report, f.present)) return;
  // Column counts of each silhouette over its foreground box only (outside it is background).
  for (int c : f.present) {
    const cv::Mat& m = views[static_cast<size_t>(c)];
    f.counts[static_cast<size_t>(c)].build(m, foreground_box(m, fg_boxes, static_cast<size_t>(c)));
    f.bases[static_cast<size_t>(c)] = m.ptr<uint8_t>(0);
    f.steps[static_cast<size_t>(c)] = m.step[0];
  }
  const NodeVisit visit(*this, f, hull);
  // Threads own whole z-layers of top cells, so no two write the same hull row.
  const Eigen::Vector3i top = pre_->nodes[kLevels - 1];
  const int* present = f.present.data();
  const int npresent = static_cast<int>(f.present.size());
#pragma omp parallel for schedule(dynamic) num_threads(options_.threads)
  for (int z = 0; z < top.z(); ++z)
    for (int y = 0; y < top.y(); ++y)
      for (int x = 0; x < top.x(); ++x)
        visit.visit(kLevels - 1, Eigen::Vector3i(x, y, z), 0, present, npresent);
  report.voxels = hull.count();
}

}  // namespace hullpose::carve
