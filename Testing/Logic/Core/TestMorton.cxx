// Morton codes and point-shell element codes (bmMorton.h): round trips, the cutting flag, the
// largest coordinate, and the Z-order interleaving itself.
#include <gtest/gtest.h>

#include <random>

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

} // namespace
