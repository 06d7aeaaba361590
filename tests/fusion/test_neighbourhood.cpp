// The generated tables and the pure neighbourhood functions against the notes' definitions.
#include <bit>
#include <catch2/catch.hpp>
#include <random>

#include "hullpose/thin/neighbourhood.hpp"
#include "hullpose/thin/simple_lut.hpp"
#include "support/volumes.hpp"

using namespace hullpose;
namespace nb = hullpose::thin::nb;

TEST_CASE("simple-point LUT holds 25,985,144 simple configurations (notes §1.2)") {
  int64_t n = 0;
  for (uint64_t w : hullpose_simple_lut) n += std::popcount(w);
  CHECK(n == 25985144);
}

TEST_CASE("simple-point test vectors of notes §1.3") {
  struct Vec {
    uint32_t mask;
    int t, tbar;
    bool simple;
  };
  const Vec vecs[] = {
      {0x0002000, 0, 1, false}, {0x0006000, 1, 1, true},  {0x0007000, 2, 1, false},
      {0x0016000, 1, 1, true},  {0x7ffffff, 1, 0, false}, {0x7bfffff, 1, 1, true},
      {0x00021ff, 1, 1, true},  {0x7fc21ff, 2, 1, false}, {0x003fe00, 1, 2, false},
      {0x4002001, 2, 1, false}, {0x2022000, 1, 1, true},  {0x0417410, 1, 0, false},
      {0x003ffff, 1, 1, true},
  };
  for (const Vec& v : vecs) {
    INFO("mask 0x" << std::hex << v.mask);
    CHECK(nb::t26(v.mask) == v.t);
    CHECK(nb::t6bar(v.mask) == v.tbar);
    CHECK(thin::is_simple(v.mask) == v.simple);
    CHECK(thin::tbar_class(v.mask) == std::min(v.tbar, 2));
  }
}

TEST_CASE("LUT and T̄ table equal the BFS reference of §1.1 on random neighbourhoods") {
  std::mt19937 rng(7);
  std::uniform_int_distribution<uint32_t> bits(0, (1u << 27) - 1);
  std::uniform_real_distribution<double> dens(0.1, 0.9);
  for (int i = 0; i < 20000; ++i) {
    // Random density so that both sparse and dense neighbourhoods occur.
    const double p = dens(rng);
    uint32_t code = nb::kCentreBit;
    for (int b = 0; b < 27; ++b)
      if (b != nb::kCentre && std::bernoulli_distribution(p)(rng)) code |= 1u << b;
    (void)bits;
    fusion::BitGrid g({3, 3, 3});
    for (int b = 0; b < 27; ++b)
      if (code >> b & 1u) g.set(b % 3, b / 3 % 3, b / 9);
    INFO("code 0x" << std::hex << code);
    REQUIRE(thin::is_simple(code) == fusion::testing::reference_simple(g, 1, 1, 1));
    REQUIRE(thin::tbar_class(code) == std::min(nb::t6bar(code), 2));
  }
}

TEST_CASE(
    "0-clique tests: the span test sees the tripod, star and tetrahedron, the antipodal test does "
    "not") {
  // Blocks in the (+,+,+) octant of the centre, as offsets.
  const nb::Octant& o = nb::kOctants[7];
  auto block = [](std::initializer_list<std::array<int, 3>> cells) {
    uint32_t m = 0;
    for (auto [x, y, z] : cells) m |= 1u << nb::bit(x, y, z);
    return m;
  };
  const uint32_t tripod = block({{0, 0, 0}, {1, 1, 0}, {0, 1, 1}});
  const uint32_t star = block({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  const uint32_t tetra = block({{0, 0, 0}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}});
  const uint32_t slab = block({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
  const uint32_t antipodal = block({{0, 0, 0}, {1, 1, 1}});
  for (uint32_t b : {tripod, star, tetra}) {
    CHECK(nb::block_spans3(b, o));
    CHECK_FALSE(nb::block_antipodal(b, o));
  }
  CHECK_FALSE(nb::block_spans3(slab, o));
  CHECK(nb::block_spans3(antipodal, o));
  CHECK(nb::block_antipodal(antipodal, o));
}

TEST_CASE(
    "2-clique ring test: crucial iff the ring is empty, disconnected or covers the four "
    "4-neighbours") {
  for (uint32_t g = 0; g < 512; ++g) {
    const uint32_t r = g & ~0x10u;
    // DGtal's formulation (notes §2.2), evaluated directly.
    const bool empty = r == 0;
    const bool full4 = (r & 0xaa) == 0xaa;
    bool connected;
    {
      // 8-connectivity of the set cells of the 3x3 grid without the centre, by flood fill.
      uint32_t comp = r & (0u - r), prev = 0;
      while (comp != prev) {
        prev = comp;
        for (int c = 0; c < 9; ++c)
          if (comp >> c & 1u)
            for (int d = 0; d < 9; ++d)
              if (d != 4 && (r >> d & 1u) && std::abs(c % 3 - d % 3) <= 1 &&
                  std::abs(c / 3 - d / 3) <= 1)
                comp |= 1u << d;
      }
      connected = comp == r;
    }
    INFO("ring 0x" << std::hex << r);
    CHECK(nb::ring_crucial(r) == (empty || !connected || full4));
  }
}

TEST_CASE("plane9 extracts the 3x3 plane of a code, and kPlaneCells inverts it") {
  std::mt19937 rng(3);
  std::uniform_int_distribution<uint32_t> bits(0, (1u << 27) - 1);
  for (int i = 0; i < 2000; ++i) {
    const uint32_t code = bits(rng);
    for (int axis = 0; axis < 3; ++axis)
      for (int value = -1; value <= 1; ++value) {
        uint32_t expect = 0;
        int cell = 0;
        // Cells in order of the two other axes, lower axis fastest.
        const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
        for (int cv = -1; cv <= 1; ++cv)
          for (int cu = -1; cu <= 1; ++cu, ++cell) {
            int d[3];
            d[axis] = value;
            d[u] = cu;
            d[v] = cv;
            expect |= (code >> nb::bit(d[0], d[1], d[2]) & 1u) << cell;
          }
        REQUIRE(nb::plane9(code, axis, value) == expect);
      }
  }
  for (int axis = 0; axis < 3; ++axis)
    for (int cell = 0; cell < 9; ++cell)
      CHECK(nb::plane9(1u << nb::kPlaneCells.bit[axis][cell], axis, 0) == 1u << cell);
}
