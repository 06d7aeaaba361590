#include "hullpose/thin/topology_stats.hpp"

#include <algorithm>
#include <bit>

#include "hullpose/common/check.hpp"

namespace hullpose::thin {

namespace {

// Calls f(x0, x1) for the runs of set bits of a row (bits past the grid are zero).
template <typename F>
void for_each_run(const uint64_t* row, int words, F&& f) {
  int x = 0;
  for (;;) {
    int w = x >> 6;
    if (w >= words) return;
    uint64_t cur = row[w] & (~uint64_t{0} << (x & 63));
    while (cur == 0) {
      if (++w >= words) return;
      cur = row[w];
    }
    const int start = w * 64 + std::countr_zero(cur);
    uint64_t inv = ~row[w] & (~uint64_t{0} << (start & 63));
    while (inv == 0) {
      if (++w >= words) {
        f(start, words * 64 - 1);
        return;
      }
      inv = ~row[w];
    }
    const int end = w * 64 + std::countr_zero(inv);
    f(start, end - 1);
    x = end;
  }
}

// Popcount of a row of words, and of the OR of a row with itself shifted by one (the lattice
// positions 0..n touched by the row's voxels: voxel x touches lattice points x and x + 1).
int64_t popcount_row(const std::vector<uint64_t>& r) {
  int64_t n = 0;
  for (uint64_t w : r) n += std::popcount(w);
  return n;
}
void dilate_x(std::vector<uint64_t>& r) {
  uint64_t carry = 0;
  for (uint64_t& w : r) {
    const uint64_t next = w >> 63;
    w |= w << 1 | carry;
    carry = next;
  }
}

}  // namespace

int64_t euler_characteristic(const fusion::BitGrid& v) {
  const Eigen::Vector3i d = v.dims();
  const int wpr = v.words_per_row();
  const int words = wpr + 1;  // room for the lattice position n
  std::vector<uint64_t> zero(static_cast<size_t>(wpr), 0);
  auto row = [&](int y, int z) -> const uint64_t* {
    return (y < 0 || z < 0 || y >= d.y() || z >= d.z()) ? zero.data() : v.row(y, z);
  };
  std::vector<uint64_t> acc(static_cast<size_t>(words));
  auto or_rows = [&](std::initializer_list<std::pair<int, int>> rows) {
    std::fill(acc.begin(), acc.end(), 0);
    for (auto [y, z] : rows) {
      const uint64_t* r = row(y, z);
      for (int w = 0; w < wpr; ++w) acc[static_cast<size_t>(w)] |= r[w];
    }
  };
  int64_t cubes = 0, faces = 0, edges = 0, verts = 0;
  // Lattice lines (y, z) with y in 0..ny, z in 0..nz carry x-edges and vertices; voxel rows
  // carry x-faces; mixed ones carry the rest.
  for (int z = 0; z <= d.z(); ++z)
    for (int y = 0; y <= d.y(); ++y) {
      if (y < d.y() && z < d.z()) {
        or_rows({{y, z}});
        cubes += popcount_row(acc);
        dilate_x(acc);
        faces += popcount_row(acc);  // faces ⊥ x
      }
      if (z < d.z()) {  // faces ⊥ y at lattice y, voxel z; edges ∥ z at lattice (x, y)
        or_rows({{y - 1, z}, {y, z}});
        faces += popcount_row(acc);
        dilate_x(acc);
        edges += popcount_row(acc);
      }
      if (y < d.y()) {  // faces ⊥ z at lattice z, voxel y; edges ∥ y at lattice (x, z)
        or_rows({{y, z - 1}, {y, z}});
        faces += popcount_row(acc);
        dilate_x(acc);
        edges += popcount_row(acc);
      }
      or_rows({{y - 1, z - 1}, {y, z - 1}, {y - 1, z}, {y, z}});  // edges ∥ x at lattice (y, z)
      edges += popcount_row(acc);
      dilate_x(acc);
      verts += popcount_row(acc);
    }
  return verts - edges + faces - cubes;
}

int ComponentLabeller::Runs::find(int a) {
  while (parent[static_cast<size_t>(a)] != a) {
    parent[static_cast<size_t>(a)] = parent[static_cast<size_t>(parent[static_cast<size_t>(a)])];
    a = parent[static_cast<size_t>(a)];
  }
  return a;
}

void ComponentLabeller::Runs::connect(bool adjacency26) {
  parent.resize(runs.size());
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  const int slack = adjacency26 ? 1 : 0;
  // Earlier neighbour rows: 26 -> (y-1,z), (y-1,z-1), (y,z-1), (y+1,z-1); 6 -> (y-1,z), (y,z-1).
  static constexpr int k26[4][2] = {{-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
  static constexpr int k6[2][2] = {{-1, 0}, {0, -1}};
  for (int rz = 0; rz < rows_z; ++rz)
    for (int ry = 0; ry < rows_y; ++ry) {
      const int r = rz * rows_y + ry;
      const int n = adjacency26 ? 4 : 2;
      for (int k = 0; k < n; ++k) {
        const int oy = ry + (adjacency26 ? k26[k][0] : k6[k][0]);
        const int oz = rz + (adjacency26 ? k26[k][1] : k6[k][1]);
        if (oy < 0 || oz < 0 || oy >= rows_y) continue;
        const int o = oz * rows_y + oy;
        // Merge-walk the two sorted run lists.
        int i = row_start[static_cast<size_t>(r)], j = row_start[static_cast<size_t>(o)];
        const int ie = row_start[static_cast<size_t>(r) + 1],
                  je = row_start[static_cast<size_t>(o) + 1];
        while (i < ie && j < je) {
          const Run& a = runs[static_cast<size_t>(i)];
          const Run& b = runs[static_cast<size_t>(j)];
          if (a.x0 <= b.x1 + slack && b.x0 <= a.x1 + slack) {
            const int ra = find(i), rb = find(j);
            if (ra != rb) parent[static_cast<size_t>(std::max(ra, rb))] = std::min(ra, rb);
          }
          if (a.x1 < b.x1)
            ++i;
          else
            ++j;
        }
      }
    }
}

int ComponentLabeller::label(const fusion::BitGrid& volume) {
  dims_ = volume.dims();
  Runs& R = object_;
  R.runs.clear();
  R.row_start.clear();
  R.y0 = R.z0 = 0;
  R.rows_y = dims_.y();
  R.rows_z = dims_.z();
  for (int z = 0; z < dims_.z(); ++z)
    for (int y = 0; y < dims_.y(); ++y) {
      R.row_start.push_back(static_cast<int>(R.runs.size()));
      for_each_run(volume.row(y, z), volume.words_per_row(), [&](int x0, int x1) {
        R.runs.push_back({x0, x1});
      });
    }
  R.row_start.push_back(static_cast<int>(R.runs.size()));
  R.connect(true);
  // Roots are the smallest run index of their component (union keeps the minimum), so numbering
  // roots in run order numbers components by their first voxel.
  comp_of_run_.resize(R.runs.size());
  sizes_.clear();
  for (size_t i = 0; i < R.runs.size(); ++i) {
    const int root = R.find(static_cast<int>(i));
    if (root == static_cast<int>(i)) {
      comp_of_run_[i] = static_cast<int>(sizes_.size());
      sizes_.push_back(0);
    } else {
      comp_of_run_[i] = comp_of_run_[static_cast<size_t>(root)];
    }
    sizes_[static_cast<size_t>(comp_of_run_[i])] += R.runs[i].x1 - R.runs[i].x0 + 1;
  }
  return static_cast<int>(sizes_.size());
}

void ComponentLabeller::extract(const std::vector<bool>& keep, fusion::BitGrid& out) const {
  HULLPOSE_ASSERT(keep.size() == sizes_.size());
  out.reset(dims_);
  const Runs& R = object_;
  for (int z = 0; z < dims_.z(); ++z)
    for (int y = 0; y < dims_.y(); ++y) {
      const int r = z * dims_.y() + y;
      uint64_t* row = out.row(y, z);
      for (int i = R.row_start[static_cast<size_t>(r)]; i < R.row_start[static_cast<size_t>(r) + 1];
           ++i) {
        if (!keep[static_cast<size_t>(comp_of_run_[static_cast<size_t>(i)])]) continue;
        for (int x = R.runs[static_cast<size_t>(i)].x0; x <= R.runs[static_cast<size_t>(i)].x1; ++x)
          row[x >> 6] |= uint64_t{1} << (x & 63);
      }
    }
}

int ComponentLabeller::label_background(const fusion::BitGrid& volume) {
  const Eigen::Vector3i d = volume.dims();
  // Only the rows between the object's first and last non-empty row, plus one empty row on
  // each side, can hold a cavity; that frame of empty rows is all outside.
  int y0 = d.y(), y1 = -1, z0 = d.z(), z1 = -1;
  for (int z = 0; z < d.z(); ++z)
    for (int y = 0; y < d.y(); ++y) {
      const uint64_t* r = volume.row(y, z);
      bool any = false;
      for (int w = 0; w < volume.words_per_row() && !any; ++w) any = r[w] != 0;
      if (!any) continue;
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
      z0 = std::min(z0, z);
      z1 = std::max(z1, z);
    }
  if (y1 < 0) y0 = y1 = z0 = z1 = 0;  // empty: one frame of background
  Runs& R = background_;
  R.runs.clear();
  R.row_start.clear();
  R.y0 = y0 - 1;
  R.z0 = z0 - 1;
  R.rows_y = y1 - y0 + 3;
  R.rows_z = z1 - z0 + 3;
  // Background runs of those rows, x in [-1, nx].
  for (int z = z0 - 1; z <= z1 + 1; ++z)
    for (int y = y0 - 1; y <= y1 + 1; ++y) {
      R.row_start.push_back(static_cast<int>(R.runs.size()));
      if (y < 0 || z < 0 || y >= d.y() || z >= d.z()) {
        R.runs.push_back({-1, d.x()});
        continue;
      }
      int next = -1;  // first background x not yet emitted
      for_each_run(volume.row(y, z), volume.words_per_row(), [&](int x0, int x1) {
        if (x0 > next) R.runs.push_back({next, x0 - 1});
        next = x1 + 1;
      });
      R.runs.push_back({next, d.x()});
    }
  R.row_start.push_back(static_cast<int>(R.runs.size()));
  R.connect(false);
  bg_size_.assign(R.runs.size(), 0);
  for (size_t i = 0; i < R.runs.size(); ++i)
    bg_size_[static_cast<size_t>(R.find(static_cast<int>(i)))] += R.runs[i].x1 - R.runs[i].x0 + 1;
  return R.find(0);  // the first run is in the empty frame: the outside
}

int ComponentLabeller::count_cavities(const fusion::BitGrid& volume) {
  const int outside = label_background(volume);
  Runs& R = background_;
  int cavities = 0;
  for (size_t i = 0; i < R.runs.size(); ++i)
    cavities +=
        R.find(static_cast<int>(i)) == static_cast<int>(i) && static_cast<int>(i) != outside;
  return cavities;
}

int ComponentLabeller::fill_cavities(fusion::BitGrid& volume, int64_t max_voxels) {
  const int outside = label_background(volume);
  Runs& R = background_;
  const Eigen::Vector3i d = volume.dims();
  int filled = 0;
  for (size_t i = 0; i < R.runs.size(); ++i)
    filled += R.find(static_cast<int>(i)) == static_cast<int>(i) &&
              static_cast<int>(i) != outside && bg_size_[i] <= max_voxels;
  if (filled == 0) return 0;
  for (int z = std::max(0, R.z0); z < std::min(d.z(), R.z0 + R.rows_z); ++z)
    for (int y = std::max(0, R.y0); y < std::min(d.y(), R.y0 + R.rows_y); ++y) {
      const int r = (z - R.z0) * R.rows_y + (y - R.y0);
      uint64_t* row = volume.row(y, z);
      for (int i = R.row_start[static_cast<size_t>(r)]; i < R.row_start[static_cast<size_t>(r) + 1];
           ++i) {
        const int root = R.find(i);
        if (root == outside || bg_size_[static_cast<size_t>(root)] > max_voxels) continue;
        for (int x = R.runs[static_cast<size_t>(i)].x0; x <= R.runs[static_cast<size_t>(i)].x1; ++x)
          row[x >> 6] |= uint64_t{1} << (x & 63);
      }
    }
  return filled;
}

TopologyInvariants ComponentLabeller::invariants(const fusion::BitGrid& volume) {
  TopologyInvariants t;
  t.components = label(volume);
  t.cavities = count_cavities(volume);
  t.euler = euler_characteristic(volume);
  return t;
}

TopologyInvariants topology_invariants(const fusion::BitGrid& volume) {
  ComponentLabeller labeller;
  return labeller.invariants(volume);
}

}  // namespace hullpose::thin
