// bmElementResidency.h - when an element counts as cutting bone (Docs/Model.md section 5).
//
// Removal is material-conserving: each frame an engaged element lowers its voxel's fill by the
// volume it sweeps. Where the two grids alias, a voxel can hold a little more (or less) element
// area than its own cross-section and would empty before the tool surface has passed through it;
// deciding engagement from the fill alone then drops elements for a while and the force dips with
// the voxel phase. So engagement is decided when an element ENTERS a voxel: it is engaged if the
// voxel holds bone then, and it stays engaged while it stays in that voxel, in consecutive frames.
// An element that enters an emptied voxel (a hole already cut, a retraction) does not cut. The
// state depends only on the previous frame, so results stay deterministic.
#pragma once

#include <cstdint>

#include "bmVoxmap.h"

namespace bm {

struct ElementResidency {
  int64_t voxel = -1; ///< voxel index of the last visit, -1 outside the grid
  uint32_t frame = 0; ///< frame number of the last visit
  uint32_t engaged = 0;

  /// Whether a visit in `frameNo` to voxel `idx` continues an engaged stay in that voxel: the
  /// element cuts whatever the voxel's fill (Visit() does not read it).
  bool Stays(uint32_t frameNo, int64_t idx) const {
    return frame + 1 == frameNo && voxel == idx && engaged;
  }
  /// Updates the state for a visit in `frameNo` to voxel `idx` (-1: outside) whose fill at the
  /// frame's start was `fill` (not read when Stays()); returns whether the element cuts this frame.
  bool Visit(uint32_t frameNo, int64_t idx, Voxmap::Fill fill) {
    const bool stayed = Stays(frameNo, idx);
    const bool e = idx >= 0 && (fill > 0 || stayed);
    voxel = idx;
    frame = frameNo;
    engaged = e ? 1u : 0u;
    return e;
  }
};

/// The same rule in one 64-bit word per element, for the CPU engine's pass (8 bytes read and 8
/// written per element and frame instead of 16 and 16): bit 0 = engaged, bits 1..63 = the voxel
/// index + 1 (0 = outside the grid). The frame of the last visit is not in the word: the engine
/// keeps it per block of elements, since a block it does not cull visits every one of its
/// elements; `fresh` says the element's block was visited in the previous frame. Then "stays" is
/// one comparison of words, and the results are ElementResidency's.
struct PackedResidency {
  /// The word of a visit to voxel `idx` (-1: outside), engaged or not.
  static constexpr uint64_t Word(int64_t idx, bool engaged) {
    return (uint64_t(idx + 1) << 1) | (engaged ? 1u : 0u);
  }
  /// ElementResidency::Stays() for the previous visit's word `prev`.
  static constexpr bool Stays(uint64_t prev, bool fresh, int64_t idx) {
    return fresh && prev == Word(idx, true);
  }
};

} // namespace bm
