#include "bmEdgeQuadrature.h"

#include <algorithm>

namespace bm {

double ForemostCuttingZ(const ToolModel& tool) {
  double zMin = 1e300;
  for (EdgeKind k : {EdgeKind::Chisel, EdgeKind::Lip}) {
    const auto range = tool.EdgeRange(k);
    if (!(range[1] > range[0]))
      continue;
    // Edges are smooth over mm; 4096 samples find the foremost point to well under a micron.
    for (int i = 0; i <= 4096; ++i)
      zMin = std::min(zMin, tool.EdgeZ(k, range[0] + (range[1] - range[0]) * i / 4096.0));
  }
  return zMin;
}

double FullEngagementDepth(const ToolModel& tool) {
  const double zMin = ForemostCuttingZ(tool);
  double zMax = zMin;
  for (EdgeKind k : {EdgeKind::Chisel, EdgeKind::Lip}) {
    const auto range = tool.EdgeRange(k);
    if (!(range[1] > range[0]))
      continue;
    for (int i = 0; i <= 4096; ++i)
      zMax = std::max(zMax, tool.EdgeZ(k, range[0] + (range[1] - range[0]) * i / 4096.0));
  }
  return zMax - zMin;
}

double VolumeBelowDepth(const ToolModel& tool, double depthMm) {
  // V = integral over rho of 2 pi rho * (length of the inside interval below the cut plane).
  const double zCut = ForemostCuttingZ(tool) + depthMm, R = tool.OuterRadius();
  const int n = 200000;
  const double h = R / n;
  double v = 0, zLo = 0, zHi = 0;
  for (int i = 0; i < n; ++i) {
    const double rho = (i + 0.5) * h;
    if (!tool.ZRange(rho, zLo, zHi))
      continue;
    v += 2.0 * 3.14159265358979323846 * rho * std::max(0.0, std::min(zHi, zCut) - zLo) * h;
  }
  return v;
}

} // namespace bm
