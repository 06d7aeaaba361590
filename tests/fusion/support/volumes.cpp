#include "volumes.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

namespace hullpose::fusion::testing {

BitGrid make_volume(const Eigen::Vector3i& dims, const Pred& inside) {
  BitGrid g(dims);
  for (int z = 0; z < dims.z(); ++z)
    for (int y = 0; y < dims.y(); ++y)
      for (int x = 0; x < dims.x(); ++x)
        if (inside(x, y, z)) g.set(x, y, z);
  return g;
}

BitGrid box(int a, int b, int c, int m) {
  return make_volume({a + 2 * m, b + 2 * m, c + 2 * m}, [=](double x, double y, double z) {
    return x >= m && y >= m && z >= m && x < a + m && y < b + m && z < c + m;
  });
}

BitGrid ball(double R, bool even_centre, int m) {
  const int n = static_cast<int>(2 * std::ceil(R)) + 2 * m + (even_centre ? 0 : 1);
  const double c = even_centre ? n / 2.0 - 0.5 : (n - 1) / 2.0;
  return make_volume({n, n, n}, [=](double x, double y, double z) {
    return (x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c) <= R * R;
  });
}

BitGrid cylinder_x(double r, int length, int m) {
  const int w = 2 * static_cast<int>(std::ceil(r)) + 1 + 2 * m;
  const double c = (w - 1) / 2.0;
  return make_volume({length + 2 * m, w, w}, [=](double x, double y, double z) {
    return x >= m && x < length + m && (y - c) * (y - c) + (z - c) * (z - c) <= r * r;
  });
}

BitGrid torus(double R, double r, bool even_centre, int m) {
  const int n = static_cast<int>(2 * std::ceil(R + r)) + 2 * m + (even_centre ? 0 : 1);
  const int h = static_cast<int>(2 * std::ceil(r)) + 1 + 2 * m;
  const double c = even_centre ? n / 2.0 - 0.5 : (n - 1) / 2.0;
  const double cz = (h - 1) / 2.0;
  return make_volume({n, n, h}, [=](double x, double y, double z) {
    const double q = std::hypot(x - c, y - c) - R;
    return q * q + (z - cz) * (z - cz) <= r * r;
  });
}

BitGrid hollow_ball(double R, double t, int m) {
  const int n = static_cast<int>(2 * std::ceil(R)) + 2 * m + 1;
  const double c = (n - 1) / 2.0;
  return make_volume({n, n, n}, [=](double x, double y, double z) {
    const double d = std::sqrt((x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c));
    return d <= R && d > R - t;
  });
}

BitGrid cross_bars(int w, int len, int m) {
  const int n = len + 2 * m;
  const int h = w + 2 * m;
  const int lo = (len - w) / 2 + m;
  return make_volume({n, n, h}, [=](double x, double y, double z) {
    const bool in_z = z >= m && z < m + w;
    const bool bar_x = x >= m && x < m + len && y >= lo && y < lo + w;
    const bool bar_y = y >= m && y < m + len && x >= lo && x < lo + w;
    return in_z && (bar_x || bar_y);
  });
}

BitGrid trefoil_tube(double s, double radius, int m) {
  // Trefoil knot: (sin t + 2 sin 2t, cos t - 2 cos 2t, -sin 3t), |coords| <= 3.
  std::vector<Eigen::Vector3d> pts;
  const int n = static_cast<int>(3 * s + radius) * 2 + 2 * m + 1;
  const double c = (n - 1) / 2.0;
  for (int i = 0; i < 600; ++i) {
    const double t = 2 * M_PI * i / 600;
    pts.emplace_back(c + s * (std::sin(t) + 2 * std::sin(2 * t)),
                     c + s * (std::cos(t) - 2 * std::cos(2 * t)), c - s * std::sin(3 * t));
  }
  return make_volume({n, n, n}, [&](double x, double y, double z) {
    for (const auto& p : pts)
      if ((p - Eigen::Vector3d(x, y, z)).squaredNorm() <= radius * radius) return true;
    return false;
  });
}

BitGrid random_blobs(std::mt19937& rng, int size, int blobs) {
  std::uniform_real_distribution<double> pos(4, size - 5), rad(1.5, size / 5.0);
  std::vector<std::pair<Eigen::Vector3d, double>> b;
  for (int i = 0; i < blobs; ++i) {
    // z first: the order x86-64 GCC evaluated one call's arguments in (unspecified in C++).
    const double z = pos(rng), y = pos(rng), x = pos(rng);
    const Eigen::Vector3d c(x, y, z);
    double r = std::min(
        rad(rng),
        std::min({c.x(), c.y(), c.z(), size - 3 - c.x(), size - 3 - c.y(), size - 3 - c.z()}) - 2);
    b.emplace_back(c, std::max(r, 1.0));
  }
  return make_volume({size, size, size}, [&](double x, double y, double z) {
    for (const auto& [c, r] : b)
      if ((c - Eigen::Vector3d(x, y, z)).squaredNorm() <= r * r) return true;
    return false;
  });
}

BitGrid random_noise(std::mt19937& rng, const Eigen::Vector3i& dims, double density, int m) {
  std::bernoulli_distribution on(density);
  return make_volume(dims + Eigen::Vector3i::Constant(2 * m), [&](double x, double y, double z) {
    const bool in =
        x >= m && y >= m && z >= m && x < dims.x() + m && y < dims.y() + m && z < dims.z() + m;
    return in && on(rng);
  });
}

std::vector<Isometry> all_isometries() {
  std::vector<Isometry> out;
  std::array<int, 3> p = {0, 1, 2};
  do {
    for (int f = 0; f < 8; ++f) out.push_back({p, {(f & 1) != 0, (f & 2) != 0, (f & 4) != 0}});
  } while (std::next_permutation(p.begin(), p.end()));
  return out;
}

BitGrid apply(const Isometry& g, const BitGrid& v) {
  // Output axis i takes input axis perm[i].
  const Eigen::Vector3i d = v.dims();
  const Eigen::Vector3i od(d[g.perm[0]], d[g.perm[1]], d[g.perm[2]]);
  BitGrid out(od);
  v.for_each([&](int x, int y, int z) {
    const int in[3] = {x, y, z};
    int o[3];
    for (int i = 0; i < 3; ++i) {
      o[i] = in[g.perm[i]];
      if (g.flip[i]) o[i] = od[i] - 1 - o[i];
    }
    out.set(o[0], o[1], o[2]);
  });
  return out;
}

namespace {

template <typename F>
int bfs_components(const Eigen::Vector3i& d, const std::function<bool(int, int, int)>& in,
                   bool adj26, F&& on_comp) {
  std::vector<uint8_t> seen(static_cast<size_t>(d.prod()), 0);
  auto idx = [&](int x, int y, int z) { return (static_cast<size_t>(z) * d.y() + y) * d.x() + x; };
  int n = 0;
  for (int z = 0; z < d.z(); ++z)
    for (int y = 0; y < d.y(); ++y)
      for (int x = 0; x < d.x(); ++x) {
        if (!in(x, y, z) || seen[idx(x, y, z)]) continue;
        ++n;
        bool touches_border = false;
        std::deque<Eigen::Vector3i> q{{x, y, z}};
        seen[idx(x, y, z)] = 1;
        while (!q.empty()) {
          const Eigen::Vector3i p = q.front();
          q.pop_front();
          if (p.minCoeff() == 0 || p.x() == d.x() - 1 || p.y() == d.y() - 1 || p.z() == d.z() - 1)
            touches_border = true;
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const int k = std::abs(dx) + std::abs(dy) + std::abs(dz);
                if (k == 0 || (!adj26 && k > 1)) continue;
                const Eigen::Vector3i r = p + Eigen::Vector3i(dx, dy, dz);
                if ((r.array() < 0).any() || (r.array() >= d.array()).any()) continue;
                if (!in(r.x(), r.y(), r.z()) || seen[idx(r.x(), r.y(), r.z())]) continue;
                seen[idx(r.x(), r.y(), r.z())] = 1;
                q.push_back(r);
              }
        }
        on_comp(touches_border);
      }
  return n;
}

}  // namespace

RefInvariants reference_invariants(const BitGrid& v) {
  RefInvariants r;
  r.components = bfs_components(
      v.dims(), [&](int x, int y, int z) { return v.get(x, y, z); }, true, [](bool) {});
  // Background on the grid grown by one voxel: the outside touches the grown border.
  const Eigen::Vector3i g = v.dims() + Eigen::Vector3i::Constant(2);
  bfs_components(
      g, [&](int x, int y, int z) { return !v.get_or_zero(x - 1, y - 1, z - 1); }, false,
      [&](bool border) { r.cavities += border ? 0 : 1; });
  // Khalimsky grid: voxel (x,y,z) is the cell (2x+1, 2y+1, 2z+1); a cell is in the closure iff an
  // adjacent voxel is set; dimension = number of odd coordinates.
  const Eigen::Vector3i d = v.dims();
  for (int k = 0; k <= 2 * d.z(); ++k)
    for (int j = 0; j <= 2 * d.y(); ++j)
      for (int i = 0; i <= 2 * d.x(); ++i) {
        bool present = false;
        for (int vz = (k - 1) / 2; vz <= k / 2 && !present; ++vz)
          for (int vy = (j - 1) / 2; vy <= j / 2 && !present; ++vy)
            for (int vx = (i - 1) / 2; vx <= i / 2 && !present; ++vx)
              if (std::abs(2 * vx + 1 - i) <= 1 && std::abs(2 * vy + 1 - j) <= 1 &&
                  std::abs(2 * vz + 1 - k) <= 1 && v.get_or_zero(vx, vy, vz))
                present = true;
        if (present) r.euler += ((i & 1) + (j & 1) + (k & 1)) % 2 == 0 ? 1 : -1;
      }
  return r;
}

bool reference_simple(const BitGrid& v, int x, int y, int z) {
  bool a[3][3][3];
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        a[dz + 1][dy + 1][dx + 1] = v.get_or_zero(x + dx, y + dy, z + dz);
  auto count = [&](bool object, bool adj26, bool only18, bool need_face) {
    bool seen[3][3][3] = {};
    int n = 0;
    for (int s = 0; s < 27; ++s) {
      const int sx = s % 3, sy = s / 3 % 3, sz = s / 9;
      const int m = std::abs(sx - 1) + std::abs(sy - 1) + std::abs(sz - 1);
      auto allowed = [&](int px, int py, int pz) {
        const int mm = std::abs(px - 1) + std::abs(py - 1) + std::abs(pz - 1);
        return mm != 0 && (!only18 || mm <= 2) && a[pz][py][px] == object;
      };
      if (!allowed(sx, sy, sz) || seen[sz][sy][sx]) continue;
      bool has_face = false;
      std::vector<std::array<int, 3>> stack{{sx, sy, sz}};
      seen[sz][sy][sx] = true;
      while (!stack.empty()) {
        const auto [px, py, pz] = stack.back();
        stack.pop_back();
        if (std::abs(px - 1) + std::abs(py - 1) + std::abs(pz - 1) == 1) has_face = true;
        for (int t = 0; t < 27; ++t) {
          const int qx = t % 3, qy = t / 3 % 3, qz = t / 9;
          const int dist = std::abs(qx - px) + std::abs(qy - py) + std::abs(qz - pz);
          const int cheb = std::max({std::abs(qx - px), std::abs(qy - py), std::abs(qz - pz)});
          if (cheb != 1 || (!adj26 && dist != 1)) continue;
          if (!allowed(qx, qy, qz) || seen[qz][qy][qx]) continue;
          seen[qz][qy][qx] = true;
          stack.push_back({qx, qy, qz});
        }
      }
      (void)m;
      if (!need_face || has_face) ++n;
    }
    return n;
  };
  const int t = count(true, true, false, false);
  const int tbar = count(false, false, true, true);
  return t == 1 && tbar == 1;
}

int crucial_cliques_missed(const BitGrid& X, const BitGrid& Y) {
  const Eigen::Vector3i d = X.dims();
  auto x = [&](const Eigen::Vector3i& p) { return X.get_or_zero(p.x(), p.y(), p.z()); };
  auto y = [&](const Eigen::Vector3i& p) { return Y.get_or_zero(p.x(), p.y(), p.z()); };
  int missed = 0;
  auto unit = [](int a) {
    Eigen::Vector3i e = Eigen::Vector3i::Zero();
    e[a] = 1;
    return e;
  };
  for (int z = -1; z <= d.z(); ++z)
    for (int yy = -1; yy <= d.y(); ++yy)
      for (int xx = -1; xx <= d.x(); ++xx) {
        const Eigen::Vector3i p(xx, yy, z);
        // 3-cliques: non-simple voxels.
        if (x(p) && !reference_simple(X, xx, yy, z) && !y(p)) ++missed;
        for (int a = 0; a < 3; ++a) {
          const Eigen::Vector3i e = unit(a), u = unit((a + 1) % 3), v = unit((a + 2) % 3);
          // 2-clique {p, p + e}: project the 2x3x3 block on a 3x3 plane, test T8 / T4̄ by BFS.
          if (x(p) && x(p + e) && !y(p) && !y(p + e)) {
            bool w[3][3];
            for (int i = -1; i <= 1; ++i)
              for (int j = -1; j <= 1; ++j)
                w[i + 1][j + 1] =
                    (i != 0 || j != 0) && (x(p + i * u + j * v) || x(p + e + i * u + j * v));
            auto comps = [&](bool val, bool adj8, bool need4) {
              bool seen[3][3] = {};
              int n = 0;
              for (int s = 0; s < 9; ++s) {
                const int si = s % 3, sj = s / 3;
                if (s == 4 || w[si][sj] != val || seen[si][sj]) continue;
                bool has4 = false;
                std::vector<std::pair<int, int>> st{{si, sj}};
                seen[si][sj] = true;
                while (!st.empty()) {
                  const auto [ci, cj] = st.back();
                  st.pop_back();
                  if (std::abs(ci - 1) + std::abs(cj - 1) == 1) has4 = true;
                  for (int t = 0; t < 9; ++t) {
                    const int ti = t % 3, tj = t / 3;
                    const int dist = std::abs(ti - ci) + std::abs(tj - cj);
                    if (t == 4 || seen[ti][tj] || w[ti][tj] != val) continue;
                    if (std::max(std::abs(ti - ci), std::abs(tj - cj)) != 1 || (!adj8 && dist != 1))
                      continue;
                    seen[ti][tj] = true;
                    st.push_back({ti, tj});
                  }
                }
                if (!need4 || has4) ++n;
              }
              return n;
            };
            if (!(comps(true, true, false) == 1 && comps(false, false, true) == 1)) ++missed;
          }
          // 1-clique around the edge through p + (u + v)/2, parallel to e.
          {
            const Eigen::Vector3i P[4] = {p, p + u, p + v, p + u + v};
            const bool diag = (x(P[0]) && x(P[3])) || (x(P[1]) && x(P[2]));
            if (diag) {
              bool capA = false, capB = false, hit = false;
              for (const auto& q : P) {
                capA = capA || x(q - e);
                capB = capB || x(q + e);
                hit = hit || (x(q) && y(q));
              }
              if (capA == capB && !hit) ++missed;
            }
          }
        }
        // 0-clique: block p + {0,1}³ spanning all three axes.
        {
          bool lo[3] = {}, hi[3] = {}, hit = false;
          for (int k = 0; k < 8; ++k) {
            const Eigen::Vector3i q = p + Eigen::Vector3i(k & 1, k >> 1 & 1, k >> 2 & 1);
            if (!x(q)) continue;
            hit = hit || y(q);
            for (int a = 0; a < 3; ++a) ((q - p)[a] ? hi : lo)[a] = true;
          }
          if (lo[0] && hi[0] && lo[1] && hi[1] && lo[2] && hi[2] && !hit) ++missed;
        }
      }
  return missed;
}

}  // namespace hullpose::fusion::testing
