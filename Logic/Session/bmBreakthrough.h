// bmBreakthrough.h - the breakthrough plunge of a session: how far the tool travelled past the
// far cortex before the hand stopped it. Surgeons train to control it; Nigam et al. (J Orthop Res
// 2022) measure this overshoot to tell experts' drilling from novices'.
//
// Breakthrough is the last cutting frame (thrust > 0) after which, with no thrust in between, the
// tool's foremost cutting point goes at least minAdvanceMm deeper: it is through, nothing in
// front of it. The plunge is the deepest point reached afterwards (until the tool cuts again or
// the record ends) less the breakthrough depth. The hand stopped when the tool's depth grew by
// less than restMm over the last restFrames frames of that stretch; otherwise the plunge is a
// lower bound (the record ended, or the session's runaway rule paused it, with the tool moving).
//
// Units: s, mm.
#pragma once

#include <functional>
#include <vector>

#include "bmFrameRecord.h"

namespace bm {

struct Breakthrough {
  bool found = false;
  double timeS = 0;     ///< session time of the last cutting frame, s
  double depthMm = 0;   ///< its depth below the entry, mm
  double plungeMm = 0;  ///< deepest depth after it, less depthMm, mm
  bool stopped = false; ///< the tool came to rest within the record
  double stopS = 0;     ///< time from breakthrough to the deepest point, s
};

struct BreakthroughOptions {
  int minCuttingFrames = 10; ///< cutting frames before a breakthrough can count
  double minAdvanceMm = 0.5; ///< advance without thrust that makes it one, mm
  int restFrames = 50;       ///< frames over which a resting tool moves less than restMm
  double restMm = 0.01;      ///< mm
};

/// The first breakthrough in `frames` (in order). depthMm: the depth of a frame's foremost
/// cutting point below the entry along the trial axis, mm (ToolDepthMm of its proxy pose).
Breakthrough MeasureBreakthrough(const std::vector<FrameRecord>& frames,
                                 const std::function<double(const FrameRecord&)>& depthMm,
                                 const BreakthroughOptions& o = {});

} // namespace bm
