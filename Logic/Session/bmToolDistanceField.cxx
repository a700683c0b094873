#include "bmToolDistanceField.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bm {

ToolDistanceField::ToolDistanceField(const ToolModel& tool, int resolution, int marginCells)
    : Tool_(&tool) {
  if (resolution < 8)
    throw std::invalid_argument("tool distance field: resolution must be >= 8");
  if (marginCells < 1)
    throw std::invalid_argument("tool distance field: margin must be >= 1 cell");
  const double R = tool.OuterRadius();
  const auto zr = tool.AxialRange();
  H_ = std::max(2 * R, zr[1] - zr[0]) / resolution;
  Far_ = marginCells * H_;
  // Outline segments, leaving out those along the axis (inside the solid).
  const auto prof = tool.Profile(H_ / 2);
  for (size_t i = 0; i + 1 < prof.size(); ++i) {
    const auto& a = prof[i];
    const auto& b = prof[i + 1];
    if (a.rho < 1e-12 && b.rho < 1e-12)
      continue;
    Segments_.push_back({a.rho, a.z, b.rho, b.z});
    // The outline runs from the tip around to the back, so the outward normal is (dz, -drho) / L:
    // it faces the feed (-z_t) where rho grows along the segment.
    const bool facesFeed = b.rho - a.rho > 1e-9 * H_;
    Parts_[0].member.push_back(facesFeed && a.kind == EdgeKind::None);
    Parts_[1].member.push_back(facesFeed);
  }
  for (Part& part : Parts_) {
    // A part's surface is drawn as a run of short segments: its rim is the run's outer radius.
    part.rhoMax.resize(Segments_.size());
    for (size_t i = 0; i < Segments_.size(); ++i)
      part.rhoMax[i] = std::max(Segments_[i][0], Segments_[i][2]);
    for (size_t i = 0; i < Segments_.size();) {
      size_t j = i + 1;
      while (part.member[i] && j < Segments_.size() && part.member[j])
        ++j;
      const double rim =
          *std::max_element(part.rhoMax.begin() + long(i), part.rhoMax.begin() + long(j));
      std::fill(part.rhoMax.begin() + long(i), part.rhoMax.begin() + long(j), rim);
      i = j;
    }
    // The part's box: its segments swept around the axis, grown by the field's margin.
    double rhoMax = 0, zLo = 1e300, zHi = -1e300;
    for (size_t i = 0; i < Segments_.size(); ++i)
      if (part.member[i]) {
        rhoMax = std::max(rhoMax, part.rhoMax[i]);
        zLo = std::min({zLo, Segments_[i][1], Segments_[i][3]});
        zHi = std::max({zHi, Segments_[i][1], Segments_[i][3]});
      }
    part.any = zLo <= zHi;
    if (part.any) {
      part.lo = Eigen::Vector3d(-rhoMax - Far_, -rhoMax - Far_, zLo - Far_);
      part.hi = Eigen::Vector3d(rhoMax + Far_, rhoMax + Far_, zHi + Far_);
    }
  }
  // The table over (rho, z) at half the box's spacing, read by bilinear interpolation.
  const double h2 = H_ / 2;
  const double rMax = (R + Far_ + H_) * std::sqrt(2.0) + H_; // the box's corners, and a cell
  const int nr = int(std::ceil(rMax / h2)) + 2;
  const double z0 = zr[0] - Far_ - H_;
  const int nz = int(std::ceil((zr[1] - zr[0] + 2 * Far_ + 2 * H_) / h2)) + 2;
  std::vector<double> t(size_t(nr) * nz);
  for (Part& part : Parts_)
    part.table.resize(t.size());
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nr; ++i) {
      size_t seg = 0;
      t[size_t(k) * nr + i] = Signed(i * h2, z0 + k * h2, seg);
      for (Part& part : Parts_)
        part.table[size_t(k) * nr + i] = part.member[seg] ? int32_t(seg) : -1;
    }
  TableStep_ = h2;
  InvStep_ = 1 / h2;
  TableZ0_ = z0;
  TableNr_ = nr;
  TableNz_ = nz;
  T_.swap(t);
  Lo_ = {-R - Far_, -R - Far_, zr[0] - Far_};
  Hi_ = {R + Far_, R + Far_, zr[1] + Far_};
  for (int a = 0; a < 3; ++a)
    Dims_[a] = int(std::ceil((Hi_(a) - Lo_(a)) / H_)) + 1;
  Hi_ = Lo_ + H_ * Eigen::Vector3d(Dims_[0] - 1, Dims_[1] - 1, Dims_[2] - 1);
  // Every point of the box has rho <= |(Hi_0, Hi_1)| < rMax and z in the table's range, so the
  // cells Sample reads there are the table's own (no clamping inside the box).
  double maxDiffRho = 0, maxDiffZ = 0;
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nr; ++i) {
      const double d = T_[size_t(k) * nr + i];
      if (i + 1 < nr)
        maxDiffRho = std::max(maxDiffRho, std::abs(T_[size_t(k) * nr + i + 1] - d));
      if (k + 1 < nz)
        maxDiffZ = std::max(maxDiffZ, std::abs(T_[size_t(k + 1) * nr + i] - d));
    }
  // Bilinear in (rho, z): each partial derivative is a convex combination of the cell's edge
  // differences over the step, and rho is 1-Lipschitz in q, so this bounds the slope in q.
  Lipschitz_ = std::sqrt(maxDiffRho * maxDiffRho + maxDiffZ * maxDiffZ) / h2;
}

size_t ToolDistanceField::Nearest(double rho, double z, double& dist2) const {
  size_t best = 0;
  dist2 = 1e300;
  for (size_t i = 0; i < Segments_.size(); ++i) {
    const auto& s = Segments_[i];
    const double dx = s[2] - s[0], dz = s[3] - s[1];
    const double L2 = dx * dx + dz * dz;
    double u = L2 > 0 ? ((rho - s[0]) * dx + (z - s[1]) * dz) / L2 : 0.0;
    u = std::clamp(u, 0.0, 1.0);
    const double ex = s[0] + u * dx - rho, ez = s[1] + u * dz - z;
    if (const double d2 = ex * ex + ez * ez; d2 < dist2) {
      dist2 = d2;
      best = i;
    }
  }
  return best;
}

bool ToolDistanceField::InPart(const Eigen::Vector3d& q, ToolPart part, double rimBandMm) const {
  if (part == ToolPart::Whole)
    return true;
  const double rho = std::hypot(q(0), q(1));
  const int i = std::clamp(int(std::lround(rho / TableStep_)), 0, TableNr_ - 1);
  const int k = std::clamp(int(std::lround((q(2) - TableZ0_) / TableStep_)), 0, TableNz_ - 1);
  const Part& p = PartOf(part);
  const int32_t seg = p.table[size_t(k) * TableNr_ + i];
  return seg >= 0 && rho <= p.rhoMax[size_t(seg)] - rimBandMm;
}

void ToolDistanceField::PartBox(ToolPart part, Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
  lo = part == ToolPart::Whole ? Lo_ : PartOf(part).lo;
  hi = part == ToolPart::Whole ? Hi_ : PartOf(part).hi;
}

bool ToolDistanceField::Has(ToolPart part) const {
  return part == ToolPart::Whole || PartOf(part).any;
}

double ToolDistanceField::Exact(double rho, double z) const {
  size_t seg = 0;
  return Signed(rho, z, seg);
}

double ToolDistanceField::Signed(double rho, double z, size_t& segment) const {
  double best = 1e300;
  segment = Nearest(rho, z, best);
  double zLo = 0, zHi = 0;
  const bool inside = Tool_->ZRange(rho, zLo, zHi) && z >= zLo && z <= zHi;
  const double d = std::sqrt(best);
  return inside ? -d : d;
}

} // namespace bm
