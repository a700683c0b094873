// bmMorton.h - Morton (Z-order) codes of integer grid coordinates, 21 bits per axis.
//
// A point-shell element is stored as one 64-bit integer: (morton(i, j, k) << 1) | cuttingFlag
// (Faieghi et al. section II-B). Sorting by code keeps spatial neighbours together, so blocks of
// consecutive elements have tight bounding boxes.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>
#if defined(__BMI2__)
#include <immintrin.h>
#endif

namespace bm {

/// Largest coordinate a Morton code holds per axis (2^21 - 1).
constexpr uint32_t kMortonMaxCoord = (1u << 21) - 1;

constexpr uint64_t MortonSpread(uint32_t v) {
  uint64_t x = v & kMortonMaxCoord;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

constexpr uint32_t MortonCompact(uint64_t x) {
  x &= 0x1249249249249249ULL;
  x = (x ^ (x >> 2)) & 0x10c30c30c30c30c3ULL;
  x = (x ^ (x >> 4)) & 0x100f00f00f00f00fULL;
  x = (x ^ (x >> 8)) & 0x1f0000ff0000ffULL;
  x = (x ^ (x >> 16)) & 0x1f00000000ffffULL;
  x = (x ^ (x >> 32)) & 0x1fffffULL;
  return uint32_t(x);
}

constexpr uint64_t MortonEncode(uint32_t i, uint32_t j, uint32_t k) {
  return MortonSpread(i) | (MortonSpread(j) << 1) | (MortonSpread(k) << 2);
}

constexpr std::array<uint32_t, 3> MortonDecode(uint64_t m) {
#if defined(__BMI2__)
  // One instruction per axis where the CPU has BMI2 (the hot loop decodes every element).
  if (!std::is_constant_evaluated())
    return {uint32_t(_pext_u64(m, 0x1249249249249249ULL)),
            uint32_t(_pext_u64(m, 0x2492492492492492ULL)),
            uint32_t(_pext_u64(m, 0x4924924924924924ULL))};
#endif
  return {MortonCompact(m), MortonCompact(m >> 1), MortonCompact(m >> 2)};
}

/// Point-shell element code: Morton code of (i, j, k) shifted left once, cutting flag in bit 0.
constexpr uint64_t PackElement(uint32_t i, uint32_t j, uint32_t k, bool cutting) {
  return (MortonEncode(i, j, k) << 1) | (cutting ? 1u : 0u);
}
constexpr bool ElementIsCutting(uint64_t code) {
  return code & 1u;
}
constexpr std::array<uint32_t, 3> ElementCoords(uint64_t code) {
  return MortonDecode(code >> 1);
}

} // namespace bm
