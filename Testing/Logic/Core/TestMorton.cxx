// Morton codes and point-shell element codes (bmMorton.h): round trips, the cutting flag, the
// largest coordinate, and the Z-order interleaving itself.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "bmMorton.h"

namespace {

TEST(Morton, InterleavesAxesXFirst) {
  EXPECT_EQ(bm::MortonEncode(0, 0, 0), 0u);
  EXPECT_EQ(bm::MortonEncode(1, 0, 0), 1u);
  EXPECT_EQ(bm::MortonEncode(0, 1, 0), 2u);
  EXPECT_EQ(bm::MortonEncode(0, 0, 1), 4u);
  EXPECT_EQ(bm::MortonEncode(2, 0, 0), 8u);
  EXPECT_EQ(bm::MortonEncode(3, 3, 3), 63u);
}

TEST(Morton, RoundTripsRandomAndExtremeCoordinates) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<uint32_t> coord(0, bm::kMortonMaxCoord);
  for (int n = 0; n < 100000; ++n) {
    const uint32_t i = coord(rng), j = coord(rng), k = coord(rng);
    const auto back = bm::MortonDecode(bm::MortonEncode(i, j, k));
    ASSERT_EQ(back[0], i);
    ASSERT_EQ(back[1], j);
    ASSERT_EQ(back[2], k);
  }
  const uint32_t m = bm::kMortonMaxCoord;
  EXPECT_EQ(m, (1u << 21) - 1);
  for (auto c :
       {std::array<uint32_t, 3>{m, m, m}, {m, 0, 0}, {0, m, 0}, {0, 0, m}, {m, 1, m - 1}}) {
    const auto back = bm::MortonDecode(bm::MortonEncode(c[0], c[1], c[2]));
    EXPECT_EQ(back, c);
  }
  // All 63 bits used at the maximum, the top bit left free for the element's cutting flag.
  EXPECT_EQ(bm::MortonEncode(m, m, m), (uint64_t(1) << 63) - 1);
}

TEST(Morton, ElementCodesKeepCoordinatesAndCuttingFlag) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<uint32_t> coord(0, bm::kMortonMaxCoord);
  for (int n = 0; n < 20000; ++n) {
    const uint32_t i = coord(rng), j = coord(rng), k = coord(rng);
    for (bool cutting : {false, true}) {
      const uint64_t code = bm::PackElement(i, j, k, cutting);
      ASSERT_EQ(bm::ElementIsCutting(code), cutting);
      const auto back = bm::ElementCoords(code);
      ASSERT_EQ(back[0], i);
      ASSERT_EQ(back[1], j);
      ASSERT_EQ(back[2], k);
    }
  }
  const uint32_t m = bm::kMortonMaxCoord;
  const uint64_t top = bm::PackElement(m, m, m, true);
  EXPECT_EQ(top, ~uint64_t(0));
  EXPECT_TRUE(bm::ElementIsCutting(top));
  EXPECT_EQ(bm::ElementCoords(top), (std::array<uint32_t, 3>{m, m, m}));
  EXPECT_FALSE(bm::ElementIsCutting(bm::PackElement(m, m, m, false)));
  // Sorting by code sorts by Morton order; the flag never reorders two different positions.
  EXPECT_LT(bm::PackElement(1, 0, 0, true), bm::PackElement(0, 1, 0, false));
}

// The 32-bit-lane decode gives ElementCoords() for every code of coordinates below 2^12: all
// corners and axes' top bits, and random codes of both cutting flags.
TEST(Morton, SmallCodesDecodeAlikeIn32BitLanes) {
  constexpr uint32_t top = (1u << bm::kSmallCoordBits) - 1;
  std::vector<uint64_t> codes;
  for (uint32_t i : {0u, 1u, 2u, 1023u, 1024u, 2047u, 2048u, top})
    for (uint32_t j : {0u, 1u, 1023u, 1024u, top})
      for (uint32_t k : {0u, 3u, 1024u, 3000u, top})
        codes.push_back(bm::PackElement(i, j, k, (i + j + k) % 2 == 1));
  std::mt19937 rng(11);
  for (int q = 0; q < 20000; ++q)
    codes.push_back(bm::PackElement(rng() & top, rng() & top, rng() & top, rng() % 2 == 0));
  for (uint64_t c : codes)
    ASSERT_TRUE(bm::ElementCodeIsSmall(c));
  EXPECT_FALSE(bm::ElementCodeIsSmall(bm::PackElement(top + 1, 0, 0, false)));
  EXPECT_FALSE(bm::ElementCodeIsSmall(bm::PackElement(0, 0, top + 1, true)));
  const int n = int(codes.size());
  std::vector<float> x(n), y(n), z(n), xs(n), ys(n), zs(n);
  bm::ElementCoordsOf(codes.data(), n, x.data(), y.data(), z.data());
  bm::ElementCoordsOfSmall(codes.data(), n, xs.data(), ys.data(), zs.data());
  for (int q = 0; q < n; ++q) {
    const auto c = bm::ElementCoords(codes[size_t(q)]);
    ASSERT_EQ(x[q], float(c[0]));
    ASSERT_EQ(xs[q], float(c[0])) << "code " << codes[size_t(q)];
    ASSERT_EQ(ys[q], float(c[1])) << "code " << codes[size_t(q)];
    ASSERT_EQ(zs[q], float(c[2])) << "code " << codes[size_t(q)];
  }
}

} // namespace
