// bmKimParkContact.h - Kim, Park & Park's contact model (MODEL_NOTES section 3): bone surface
// point shell (bmBoneSurfaceShell.h) against the tool's signed distance field
// (bmToolDistanceField.h).
//
// For a tool pose (R, p) every bone point x_i under the tool's box is carried into the tool frame,
// q_i = R^T (x_i - p), and its signed distance d_i read by trilinear interpolation. A point deeper
// than the dead band t (d_i < -t) pushes the tool out along the bone normal N_i:
//   F_c = sum k_i (-d_i - t) N_i,   k_i = k_A h^2 m_i
// (k_A a stiffness per unit area, N/mm^3; h^2 the point's area; m_i its material scale), with
// Jacobian dF_c/dp = sum k_i N_i (R grad d_i)^T, which the proxy's 3x3 solve uses (eq. 4). The dead
// band is 0 for Kim et al.'s method; the cutting model uses about one voxel so that voxels the
// engine is still thinning at the hole's wall do not push.
//
// Units: mm, N, N/mm, N/mm^3.
#pragma once

#include <Eigen/Core>

#include "bmBoneSurfaceShell.h"
#include "bmToolDistanceField.h"

namespace bm {

struct ContactResult {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();    ///< F_c on the tool, N (world)
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero(); ///< dF_c/dp, N/mm
  int points = 0;                                     ///< points in contact
  double maxDepthMm = 0; ///< deepest penetration beyond the dead band, mm
  Eigen::Vector3d normal =
      Eigen::Vector3d::Zero(); ///< unit sum of the contacting points' normals weighted by depth
};

class KimParkContact {
public:
  /// stiffnessPerArea: k_A, N/mm^3 (default 2000: 1 mm^2 of contact 0.01 mm deep holds 20 N).
  KimParkContact(const ToolDistanceField& sdf, BoneSurfaceShell& shell,
                 double stiffnessPerArea = 2000);
  const ToolDistanceField& Field() const { return Sdf_; }
  BoneSurfaceShell& Shell() { return Shell_; }
  double StiffnessPerArea() const { return KA_; }
  /// World box (mm) covering the tool's field at pose (R, p), or only `part` of it (default: the
  /// whole tool).
  void ToolBox(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, Eigen::Vector3d& lo,
               Eigen::Vector3d& hi, ToolPart part = ToolPart::Whole) const;
  /// Contact of the tool at pose (R, p) with dead band deadBandMm (mm, >= 0, default 0), counting
  /// only the bone points nearest to `part` of the tool's surface (default: the whole tool) and,
  /// for a part, at least rimBandMm (mm, default 0) inside its rim (ToolDistanceField::InPart).
  ContactResult Query(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double deadBandMm = 0,
                      ToolPart part = ToolPart::Whole, double rimBandMm = 0) const;
  /// Kim et al.'s Boolean removal: bone voxels whose centre is deeper than depthMm inside the tool
  /// at (R, p) are removed and the shell regenerated. Returns voxels removed; fill units in
  /// removedFill.
  int64_t Cut(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double depthMm,
              int64_t& removedFill);

private:
  const ToolDistanceField& Sdf_;
  BoneSurfaceShell& Shell_;
  double KA_;
};

} // namespace bm
