// bmToolDistanceField.h - the tool as a signed distance field (Kim, Park & Park 2008 section 2.2).
//
// The tool is a solid of revolution (bmToolModel.h), so its exact signed distance is a function of
// (rho, z): the distance to the half-section outline, negative inside. It is tabulated on a 2D
// grid over (rho, z) and read by bilinear interpolation there (value and its analytic gradient,
// carried back to the tool frame through rho = |(x, y)|). Kim et al. read a 3D grid trilinearly;
// for a tool of revolution the 2D table is finer for the same memory, and its 4 corners (under a
// megabyte for the whole table) stay in cache where a 3D grid's 8 (tens of megabytes) do not, which
// is most of a seated reamer's contact query (Docs/RealTime.md). Unlike Kim et al.,
// who model only the tip as a cone that includes the drill's flutes, the whole modelled tool is
// covered (the time-averaged envelope), so the shank meets the hole wall too.
//
// It also tells which part of the tool a point is nearest to: the non-cutting surfaces that face
// the feed (outward normal with a -z_t component, e.g. a reamer's guide nipple) are the ones that
// must stop, as a rigid contact, when they meet bone along the axis (Docs/Interaction.md
// section 3).
//
// Units: mm, tool frame T (origin at the foremost cutting point, z_t toward the shank).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "bmToolModel.h"

namespace bm {

/// Which surface points of the tool a contact query counts.
enum class ToolPart {
  Whole,             ///< every surface (default)
  NonCuttingLeading, ///< non-cutting surfaces facing the feed (outward normal . z_t < 0)
  Leading,           ///< every surface facing the feed, cutting or not (what an advance meets)
};

class ToolDistanceField {
public:
  ToolDistanceField() = default;
  /// resolution: cells along the tool's bounding box's longest side (>= 8, default 256); the grid
  /// reaches marginCells cells beyond the tool (default 4). Throws std::invalid_argument.
  ToolDistanceField(const ToolModel& tool, int resolution = 256, int marginCells = 4);

  double Spacing() const { return H_; }
  /// Tool-frame box covered by the grid, mm.
  const Eigen::Vector3d& Lo() const { return Lo_; }
  const Eigen::Vector3d& Hi() const { return Hi_; }
  /// Signed distance (mm, < 0 inside the tool) at tool-frame point q (mm), bilinear in (rho, z);
  /// gradient (unit-less) in `grad` (on the axis: along it). Outside the grid's box: returns Far()
  /// and a zero gradient.
  double Sample(const Eigen::Vector3d& q, Eigen::Vector3d& grad) const;
  /// Sample's value alone (mm), without the gradient: equal to it up to rounding (the arithmetic
  /// may contract differently), for bounds that keep a margin.
  double Value(const Eigen::Vector3d& q) const;
  /// The value reported outside the grid (the margin), mm.
  double Far() const { return Far_; }
  /// Whether Sample interpolates at tool-frame point q (mm) rather than reporting Far().
  bool InGrid(const Eigen::Vector3d& q) const;
  /// Lipschitz bound of Sample inside the grid (unit-less, mm per mm): |Sample(q) - Sample(q')| <=
  /// LipschitzBound() |q - q'| for q, q' both InGrid (the grid is a box, so the segment between
  /// them is too). Each component of the bilinear gradient in (rho, z) is a convex combination of
  /// the cells' edge differences along that axis, and q -> (rho, z) is 1-Lipschitz, so the bound is
  /// the norm of the largest edge difference per axis over the step, taken from the table.
  double LipschitzBound() const { return Lipschitz_; }
  /// Exact signed distance from the outline (mm) at radius rho and height z (for tests).
  double Exact(double rho, double z) const;
  /// Whether the outline nearest to tool-frame point q (mm) belongs to `part` (nearest node of a
  /// table at half the grid spacing; outside the table: the nearest edge of it) and q lies at
  /// least rimBandMm (mm, default 0) inside the outer radius of that part's surface. The rim band
  /// keeps a partial-volume wall beside a part (a pilot hole's wall along the guide nipple's side)
  /// from counting as bone in front of it: the part's side is across the axis, where the contact
  /// has its dead band.
  bool InPart(const Eigen::Vector3d& q, ToolPart part, double rimBandMm = 0) const;
  /// Tool-frame box (mm) holding every point InPart can accept for `part`: the whole field for
  /// Whole, else the part's outline swept around the axis, grown by the field's margin.
  void PartBox(ToolPart part, Eigen::Vector3d& lo, Eigen::Vector3d& hi) const;
  /// Whether any of the outline belongs to `part` (a drill or a burr has no leading non-cutting
  /// surface).
  bool Has(ToolPart part) const;

private:
  /// For tool-frame point q (mm) in the grid's box: its radius rho (mm), the table cell holding
  /// (rho, z) (r0: its corner (i, k); r0 + TableNr_ the row above) and the fractions a (along rho)
  /// and c (along z) in it; false outside the box.
  bool Cell(const Eigen::Vector3d& q, double& rho, const double*& r0, double& a, double& c) const;
  /// Index of the outline segment nearest to (rho, z) and its squared distance (mm^2).
  size_t Nearest(double rho, double z, double& dist2) const;
  /// Exact(rho, z), with the nearest segment's index in `segment`.
  double Signed(double rho, double z, size_t& segment) const;

  std::vector<std::array<double, 4>> Segments_; // (rho0, z0, rho1, z1)
  /// A part other than the whole tool: which segments belong to it, its table and its box.
  struct Part {
    std::vector<unsigned char> member; // per segment: in the part
    std::vector<int32_t> table; // nearest segment if it is in the part, else -1; (rho, z) grid
    std::vector<double> rhoMax; // per segment: outer radius of its run of the part's ones, mm
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
    bool any = false;
  };
  /// The part's tables (part != Whole).
  const Part& PartOf(ToolPart part) const { return Parts_[part == ToolPart::Leading ? 1 : 0]; }
  std::array<Part, 2> Parts_; // NonCuttingLeading, Leading
  double TableStep_ = 0, InvStep_ = 0, TableZ0_ = 0;
  int TableNr_ = 0, TableNz_ = 0;
  const ToolModel* Tool_ = nullptr;
  double H_ = 0, Far_ = 0, Lipschitz_ = 0;
  Eigen::Vector3d Lo_ = Eigen::Vector3d::Zero(), Hi_ = Eigen::Vector3d::Zero();
  std::array<int, 3> Dims_{0, 0, 0}; // the box's cells at spacing H_ (Hi_ = Lo_ + H_ (Dims_ - 1))
  std::vector<double> T_;            // signed distance, mm, on the (rho, z) table's nodes
};

// Read for every bone point of every contact query and candidate gather: defined here so that the
// calls inline (the same arithmetic, so the same bits, as out of line).
inline bool ToolDistanceField::InGrid(const Eigen::Vector3d& q) const {
  return q(0) >= Lo_(0) && q(1) >= Lo_(1) && q(2) >= Lo_(2) && q(0) < Hi_(0) && q(1) < Hi_(1) &&
         q(2) < Hi_(2);
}

inline bool ToolDistanceField::Cell(const Eigen::Vector3d& q, double& rho, const double*& r0,
                                    double& a, double& c) const {
  if (!InGrid(q))
    return false;
  rho = std::sqrt(q(0) * q(0) + q(1) * q(1));
  const double u = rho * InvStep_, w = (q(2) - TableZ0_) * InvStep_;
  const int i = std::min(int(u), TableNr_ - 2), k = std::min(int(w), TableNz_ - 2);
  a = u - i;
  c = w - k;
  r0 = &T_[size_t(k) * TableNr_ + i];
  return true;
}

inline double ToolDistanceField::Sample(const Eigen::Vector3d& q, Eigen::Vector3d& grad) const {
  double rho, a, c;
  const double* r0;
  if (!Cell(q, rho, r0, a, c)) {
    grad.setZero();
    return Far_;
  }
  const double* r1 = r0 + TableNr_;
  const double v0 = r0[0] + a * (r0[1] - r0[0]), v1 = r1[0] + a * (r1[1] - r1[0]);
  const double dRho = ((1 - c) * (r0[1] - r0[0]) + c * (r1[1] - r1[0])) * InvStep_;
  const double s = rho > 0 ? dRho / rho : 0.0; // on the axis the field is flat across it
  grad(0) = s * q(0);
  grad(1) = s * q(1);
  grad(2) = (v1 - v0) * InvStep_;
  return v0 + c * (v1 - v0);
}

inline double ToolDistanceField::Value(const Eigen::Vector3d& q) const {
  double rho, a, c;
  const double* r0;
  if (!Cell(q, rho, r0, a, c))
    return Far_;
  const double* r1 = r0 + TableNr_;
  const double v0 = r0[0] + a * (r0[1] - r0[0]), v1 = r1[0] + a * (r1[1] - r1[0]);
  return v0 + c * (v1 - v0);
}

} // namespace bm
