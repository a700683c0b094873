// bmEdgeQuadrature.h - composite Gauss-Legendre nodes along a tool's cutting edges.
//
// The reference thrust/torque (bmForceModel.h IntegrateEdges) and the calibration design matrix
// (bmCalibration.h) both integrate elemental forces along the edges' radius r; this is the one
// place that lays the nodes. Each node carries weight = N_c * (Gauss weight * panel width), in mm,
// so that sum(weight * per-delta force) is the whole tool's force.
#pragma once

#include <array>
#include <cmath>

#include "bmToolModel.h"

namespace bm {

/// Axial height (mm, tool frame) of the foremost point of any cutting edge.
double ForemostCuttingZ(const ToolModel& tool);
/// Depth (mm) past the foremost cutting point at which every edge element is engaged.
double FullEngagementDepth(const ToolModel& tool);
/// Volume (mm^3) of the tool below depthMm from its foremost cutting point: what a tool fed that
/// deep into a bone that contains its whole path removes.
double VolumeBelowDepth(const ToolModel& tool, double depthMm);

/// Calls fn(kind, r_mm, weight_mm) for every node on edges of `onlyKind` (None = all kinds)
/// whose edge height above the foremost cutting point is below depthMm.
template <class Fn>
void ForEachEdgeNode(const ToolModel& tool, double depthMm, EdgeKind onlyKind, int panels,
                     Fn&& fn) {
  static constexpr std::array<double, 4> x{-0.8611363115940526, -0.3399810435848563,
                                           0.3399810435848563, 0.8611363115940526};
  static constexpr std::array<double, 4> w{0.3478548451374538, 0.6521451548625461,
                                           0.6521451548625461, 0.3478548451374538};
  const double zMin = ForemostCuttingZ(tool);
  for (EdgeKind kind : {EdgeKind::Chisel, EdgeKind::Lip}) {
    if (onlyKind != EdgeKind::None && kind != onlyKind)
      continue;
    const auto range = tool.EdgeRange(kind);
    if (!(range[1] > range[0]))
      continue;
    const double h = (range[1] - range[0]) / panels;
    for (int p = 0; p < panels; ++p) {
      const double mid = range[0] + (p + 0.5) * h;
      for (int q = 0; q < 4; ++q) {
        const double r = mid + 0.5 * h * x[q];
        if (tool.EdgeZ(kind, r) - zMin >= depthMm)
          continue;
        fn(kind, r, tool.NumLips() * 0.5 * h * w[q]);
      }
    }
  }
}

} // namespace bm
