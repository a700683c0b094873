// bmSessionTestUtil.h - small scenes and helpers shared by the session tests (kept small so the
// whole BMSessionTests run stays within a few minutes under ThreadSanitizer on 2 cores).
#pragma once

#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include <Eigen/Dense>

#include "bmMachiningSetup.h"
#include "bmProxy.h"
#include "bmScene.h"

namespace bm::test {

/// A spherical burr of radius r (mm) on a short shaft, over a block of the given size (mm, top
/// face at z = 0) at voxmapRes cells along its longest side; the scene's spindle speed speedRpm
/// (0 = 1000 rpm in the scene, for tests that pass a stopped spindle to each frame themselves).
/// shaftRadiusMm <= 0: the burr's default shaft (0.4 r).
inline Scene BurrScene(double radiusMm, std::array<double, 3> blockMm, int voxmapRes,
                       int shellRes = 128, double speedRpm = 1000, double shaftMm = 1.0,
                       double shaftRadiusMm = 0) {
  nlohmann::json j = Scene::Builtin("drilling").ToJson();
  j["tool"] = {{"type", "burr"}, {"radius_mm", radiusMm}, {"shaft_length_mm", shaftMm}};
  if (shaftRadiusMm > 0)
    j["tool"]["shaft_radius_mm"] = shaftRadiusMm;
  j["bone"]["size_mm"] = {blockMm[0], blockMm[1], blockMm[2]};
  j["voxmap_resolution"] = voxmapRes;
  j["shell_resolution"] = shellRes;
  j["threads"] = 1;
  j["trial"]["speed_rpm"] = speedRpm > 0 ? speedRpm : 1000.0;
  j.erase("force_model");
  return Scene::FromJson(j);
}

/// A small guided reamer (hemispherical head of radius 1 mm, 5 lips; guide nipple of radius
/// nippleRadiusMm, 0 = none, 0.3 mm ahead of the face) over a 2.4 x 2.4 x 1.2 mm block at
/// voxmapRes cells along its longest side, shell 64.
inline Scene GuidedReamerScene(double nippleRadiusMm, int voxmapRes) {
  nlohmann::json j = Scene::Builtin("drilling").ToJson();
  j["tool"] = {{"type", "reamer"},
               {"arc_radius_mm", 1.0},
               {"arc_centre_offset_mm", 0.0},
               {"alpha_deg", 0.0},
               {"outer_radius_mm", 1.0},
               {"lips", 5},
               {"nipple_radius_mm", nippleRadiusMm},
               {"nipple_length_mm", 0.3},
               {"head_thickness_mm", 0.2},
               {"shaft_radius_mm", 0.4},
               {"shaft_length_mm", 1.0}};
  j["bone"]["size_mm"] = {2.4, 2.4, 1.2};
  j["voxmap_resolution"] = voxmapRes;
  j["shell_resolution"] = 64;
  j["threads"] = 1;
  j.erase("force_model");
  return Scene::FromJson(j);
}

/// The reference drill over a block.
inline Scene DrillScene(std::array<double, 3> blockMm, int voxmapRes, int shellRes) {
  nlohmann::json j = Scene::Builtin("drilling").ToJson();
  j["bone"]["size_mm"] = {blockMm[0], blockMm[1], blockMm[2]};
  j["voxmap_resolution"] = voxmapRes;
  j["shell_resolution"] = shellRes;
  j["threads"] = 1;
  return Scene::FromJson(j);
}

/// Empties the voxels whose centre lies inside the tool at tool-origin position p (axis +z):
/// the hole a tool already sunk to p would have cut.
inline void CarveTool(MachiningSetup& s, const Eigen::Vector3d& p) {
  Voxmap& v = s.Bone();
  const auto d = v.Dims();
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i) {
        const auto w = v.GridToWorld({double(i), double(j), double(k)});
        const Eigen::Vector3d q = Eigen::Vector3d(w[0], w[1], w[2]) - p;
        double lo = 0, hi = 0;
        if (s.Tool().ZRange(std::hypot(q(0), q(1)), lo, hi) && q(2) >= lo && q(2) <= hi)
          v.SetFill(v.Index(i, j, k), 0);
      }
}

/// Mean and ripple of v[from, to): ripple = standard deviation about the least-squares quadratic
/// trend / |mean|. The trend takes out slow changes (a coupling spring still loading up, the
/// engagement growing), so what remains is the frame-to-frame ripple (voxel phase, buzz).
inline std::pair<double, double> MeanRipple(const std::vector<double>& v, size_t from, size_t to) {
  const Eigen::Index n = Eigen::Index(to - from);
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd y(n);
  double m = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = double(i) / double(n);
    A.row(i) << 1.0, t, t * t;
    y(i) = v[from + size_t(i)];
    m += y(i);
  }
  m /= double(n);
  const Eigen::VectorXd c = A.colPivHouseholderQr().solve(y);
  const double sd = std::sqrt((y - A * c).squaredNorm() / double(n - 3));
  return {m, m != 0 ? sd / std::abs(m) : 0.0};
}

} // namespace bm::test
