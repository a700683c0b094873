// bmMorton.h - Morton (Z-order) codes of integer grid coordinates, 21 bits per axis.
//
// A point-shell element is stored as one 64-bit integer: (morton(i, j, k) << 1) | cuttingFlag
// (Faieghi et al. section II-B). Sorting by code keeps spatial neighbours together, so blocks of
// consecutive elements have tight bounding boxes.
#pragma once

#include <array>
#include <cstdint>

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

/// Shifts and masks, not BMI2's pext: pext is one fast instruction on Intel but microcoded on AMD
/// before Zen 3 (18 to 300 cycles: with it the CPU engine's frame was 10x slower on an EPYC of
/// the development VMs), and the batch form below vectorises on every x86-64.
constexpr std::array<uint32_t, 3> MortonDecode(uint64_t m) {
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
/// MortonCompact() of a code of at most 30 bits, in 32-bit arithmetic: its bits 0, 3, ..., 27.
constexpr uint32_t MortonCompact10(uint32_t x) {
  x &= 0x09249249u;
  x = (x ^ (x >> 2)) & 0x030C30C3u;
  x = (x ^ (x >> 4)) & 0x0300F00Fu;
  x = (x ^ (x >> 8)) & 0xFF0000FFu;
  x = (x ^ (x >> 16)) & 0x000003FFu;
  return x;
}

/// Coordinates below 2^kSmallCoordBits on every axis (element codes below 2^(3 kSmallCoordBits +
/// 1)) can be decoded by ElementCoordsOfSmall(); every point shell up to resolution 2048 has them.
constexpr int kSmallCoordBits = 12;
constexpr bool ElementCodeIsSmall(uint64_t code) {
  return (code >> 1) < (uint64_t(1) << (3 * kSmallCoordBits));
}

/// ElementCoords() of n element codes as floats (exact: coordinates < 2^21), in a loop the
/// compiler vectorises (the engine's pass decodes every visited element of every frame; the
/// kernels' bmCommon.cl decodes with the same shifts and masks).
inline void ElementCoordsOf(const uint64_t* __restrict codes, int n, float* __restrict x,
                            float* __restrict y, float* __restrict z) {
  for (int q = 0; q < n; ++q) { // an int index: GCC 12 does not vectorise an unsigned one
    const uint64_t m = codes[q] >> 1;
    x[q] = float(int32_t(MortonCompact(m)));
    y[q] = float(int32_t(MortonCompact(m >> 1)));
    z[q] = float(int32_t(MortonCompact(m >> 2)));
  }
}
/// ElementCoordsOf() of codes that are all ElementCodeIsSmall(): the same values from 32-bit
/// lanes (twice as many per vector): the Morton code's low 30 bits hold 10 bits of each axis, its
/// next 6 bits the 2 above them.
inline void ElementCoordsOfSmall(const uint64_t* __restrict codes, int n, float* __restrict x,
                                 float* __restrict y, float* __restrict z) {
  for (int q = 0; q < n; ++q) {
    const uint64_t m = codes[q] >> 1;
    const uint32_t lo = uint32_t(m) & 0x3FFFFFFFu, hi = uint32_t(m >> 30);
    x[q] = float(int32_t(MortonCompact10(lo) | ((hi & 1u) | ((hi >> 2) & 2u)) << 10));
    y[q] = float(int32_t(MortonCompact10(lo >> 1) | (((hi >> 1) & 1u) | ((hi >> 3) & 2u)) << 10));
    z[q] = float(int32_t(MortonCompact10(lo >> 2) | (((hi >> 2) & 1u) | ((hi >> 4) & 2u)) << 10));
  }
}

} // namespace bm
