// bmFeedBalance.h - the feed at which cutting thrust balances the axial coupling force
// (Docs/Interaction.md section 2).
//
// Thrust is increasing in feed. At full engagement it is the edge integral F_full(f)
// (bmForceModel.h IntegrateEdges), tabulated here on a log grid of feeds for the spindle speed in
// use (rebuilt when the speed changes) and read by log-log interpolation. During partial
// engagement the thrust is taken as s F_full(f), s the engaged fraction that the engine reported in
// the last frame (its thrust over F_full at that frame's feed): the choice the session makes,
// because it costs no second engine pass and is exact at full engagement; its error is the change
// of the fraction within one frame (the tool moves less than half a voxel per frame).
//
// The proxy advance u (mm this frame, along -axis) then solves
//   s F_full(f(u)) = F0 - C u,   f(u) = 60 u / (n T)
// (F0 the axial coupling force at zero advance, C = K + B / T its stiffness against the advance),
// by bisection: the left side increases and the right side decreases in u, so the root is unique.
//
// Units: f mm/rev, n rpm, forces N, u mm, T s, C N/mm.
#pragma once

#include <vector>

#include "bmForceModel.h"
#include "bmToolModel.h"

namespace bm {

class FeedBalance {
public:
  /// Feeds tabulated from fMin to fMax (mm/rev, defaults 1e-5 and 1.0).
  FeedBalance(const ToolModel& tool, const ForceModel& model, double fMinMmPerRev = 1e-5,
              double fMaxMmPerRev = 1.0);
  /// Fully engaged thrust at feed f (mm/rev) and speed n (rpm), N. A new speed rebuilds the table
  /// (a few ms): call it once for the session's speed before the haptic loop starts.
  double FullThrust(double f, double n);
  /// The advance u in [0, uMax] (mm) described above; 0 when F0 <= 0 or s <= 0.
  double SolveAdvance(double s, double f0N, double cNPerMm, double speedRpm, double frameS,
                      double uMaxMm);
  double MinFeed() const { return FMin_; }

private:
  void Rebuild(double n);
  const ToolModel& Tool_;
  const ForceModel& Model_;
  double FMin_, FMax_;
  double Speed_ = -1;
  std::vector<double> LogF_, LogT_;
};

} // namespace bm
