#include "bmEdgeQuadrature.h"

#include <algorithm>

namespace bm {

double ForemostCuttingZ(const ToolModel& tool) {
  double zMin = 1e300, zLo = 0, zHi = 0;
  for (EdgeKind k : {EdgeKind::Chisel, EdgeKind::Lip}) {
    const auto range = tool.EdgeRange(k);
    if (!(range[1] > range[0])) continue;
    // Edges are smooth over mm; 4096 samples find the foremost point to well under a micron.
    for (int i = 0; i <= 4096; ++i)
      if (tool.ZRange(range[0] + (range[1] - range[0]) * i / 4096.0, zLo, zHi)) zMin = std::min(zMin, zLo);
  }
  return zMin;
}

} // namespace bm
