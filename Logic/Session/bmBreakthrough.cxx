// bmBreakthrough.cxx - see bmBreakthrough.h.
#include "bmBreakthrough.h"

#include <algorithm>

namespace bm {

Breakthrough MeasureBreakthrough(const std::vector<FrameRecord>& frames,
                                 const std::function<double(const FrameRecord&)>& depthMm,
                                 const BreakthroughOptions& o) {
  Breakthrough b;
  int cutting = 0;
  size_t lastCut = 0;
  double lastCutDepth = 0;
  size_t k = 0;
  for (; k < frames.size(); ++k) {
    if (frames[k].thrustN > 0) {
      ++cutting;
      lastCut = k;
      lastCutDepth = depthMm(frames[k]);
    } else if (cutting >= o.minCuttingFrames &&
               depthMm(frames[k]) - lastCutDepth >= o.minAdvanceMm) {
      break;
    }
  }
  if (k == frames.size())
    return b;
  b.found = true;
  b.timeS = frames[lastCut].timeS;
  b.depthMm = lastCutDepth;
  // The stretch after it: until the tool cuts again or the record ends.
  size_t end = lastCut + 1;
  while (end < frames.size() && frames[end].thrustN <= 0)
    ++end;
  std::vector<double> depth;
  depth.reserve(end - lastCut);
  for (size_t i = lastCut; i < end; ++i)
    depth.push_back(depthMm(frames[i]));
  const auto deepest = std::max_element(depth.begin(), depth.end());
  b.plungeMm = *deepest - lastCutDepth;
  b.stopS = frames[lastCut + size_t(deepest - depth.begin())].timeS - b.timeS;
  const size_t n = depth.size();
  if (n > size_t(o.restFrames)) {
    const double recent = *std::max_element(depth.end() - o.restFrames, depth.end()) -
                          *std::min_element(depth.end() - o.restFrames, depth.end());
    b.stopped = recent < o.restMm;
  }
  return b;
}

} // namespace bm
