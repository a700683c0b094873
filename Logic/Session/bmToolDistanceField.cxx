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
    Leading_.push_back(a.kind == EdgeKind::None && b.rho - a.rho > 1e-9 * H_);
    SegmentRhoMax_.push_back(std::max(a.rho, b.rho));
  }
  // A leading surface is drawn as a run of short segments: its rim is the run's outer radius.
  for (size_t i = 0; i < Segments_.size();) {
    size_t j = i + 1;
    while (Leading_[i] && j < Segments_.size() && Leading_[j])
      ++j;
    const double rim =
        *std::max_element(SegmentRhoMax_.begin() + long(i), SegmentRhoMax_.begin() + long(j));
    std::fill(SegmentRhoMax_.begin() + long(i), SegmentRhoMax_.begin() + long(j), rim);
    i = j;
  }
  // The leading part's box: its segments swept around the axis, grown by the field's margin.
  double leadRho = 0, leadZLo = 1e300, leadZHi = -1e300;
  for (size_t i = 0; i < Segments_.size(); ++i)
    if (Leading_[i]) {
      leadRho = std::max(leadRho, SegmentRhoMax_[i]);
      leadZLo = std::min({leadZLo, Segments_[i][1], Segments_[i][3]});
      leadZHi = std::max({leadZHi, Segments_[i][1], Segments_[i][3]});
    }
  if (leadZLo <= leadZHi) {
    LeadLo_ = Eigen::Vector3d(-leadRho - Far_, -leadRho - Far_, leadZLo - Far_);
    LeadHi_ = Eigen::Vector3d(leadRho + Far_, leadRho + Far_, leadZHi + Far_);
  }
  // 2D table over (rho, z) at half the 3D spacing.
  const double h2 = H_ / 2;
  const double rMax = R * std::sqrt(2.0) + 2 * Far_;
  const int nr = int(std::ceil(rMax / h2)) + 2;
  const double z0 = zr[0] - Far_ - H_;
  const int nz = int(std::ceil((zr[1] - zr[0] + 2 * Far_ + 2 * H_) / h2)) + 2;
  std::vector<double> t(size_t(nr) * nz);
  LeadingTable_.resize(t.size());
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nr; ++i) {
      size_t seg = 0;
      t[size_t(k) * nr + i] = Signed(i * h2, z0 + k * h2, seg);
      LeadingTable_[size_t(k) * nr + i] = Leading_[seg] ? int32_t(seg) : -1;
    }
  TableStep_ = h2;
  TableZ0_ = z0;
  TableNr_ = nr;
  TableNz_ = nz;
  auto table = [&](double rho, double z) {
    const double u = rho / h2, w = (z - z0) / h2;
    const int i = std::clamp(int(u), 0, nr - 2), k = std::clamp(int(w), 0, nz - 2);
    const double a = u - i, c = w - k;
    const double* r0 = &t[size_t(k) * nr + i];
    const double* r1 = r0 + nr;
    return (1 - c) * ((1 - a) * r0[0] + a * r0[1]) + c * ((1 - a) * r1[0] + a * r1[1]);
  };
  Lo_ = {-R - Far_, -R - Far_, zr[0] - Far_};
  Hi_ = {R + Far_, R + Far_, zr[1] + Far_};
  for (int a = 0; a < 3; ++a)
    Dims_[a] = int(std::ceil((Hi_(a) - Lo_(a)) / H_)) + 1;
  Hi_ = Lo_ + H_ * Eigen::Vector3d(Dims_[0] - 1, Dims_[1] - 1, Dims_[2] - 1);
  D_.resize(size_t(Dims_[0]) * Dims_[1] * Dims_[2]);
  for (int k = 0; k < Dims_[2]; ++k)
    for (int j = 0; j < Dims_[1]; ++j)
      for (int i = 0; i < Dims_[0]; ++i) {
        const double x = Lo_(0) + i * H_, y = Lo_(1) + j * H_, z = Lo_(2) + k * H_;
        D_[size_t(i) + size_t(Dims_[0]) * (size_t(j) + size_t(Dims_[1]) * k)] =
            float(table(std::hypot(x, y), z));
      }
  const size_t sy = size_t(Dims_[0]), sz = sy * size_t(Dims_[1]);
  double maxDiff[3] = {0, 0, 0};
  for (int k = 0; k < Dims_[2]; ++k)
    for (int j = 0; j < Dims_[1]; ++j)
      for (int i = 0; i < Dims_[0]; ++i) {
        const size_t v = size_t(i) + sy * size_t(j) + sz * size_t(k);
        const double d = D_[v];
        if (i + 1 < Dims_[0])
          maxDiff[0] = std::max(maxDiff[0], std::abs(double(D_[v + 1]) - d));
        if (j + 1 < Dims_[1])
          maxDiff[1] = std::max(maxDiff[1], std::abs(double(D_[v + sy]) - d));
        if (k + 1 < Dims_[2])
          maxDiff[2] = std::max(maxDiff[2], std::abs(double(D_[v + sz]) - d));
      }
  Lipschitz_ =
      std::sqrt(maxDiff[0] * maxDiff[0] + maxDiff[1] * maxDiff[1] + maxDiff[2] * maxDiff[2]) / H_;
}

bool ToolDistanceField::InGrid(const Eigen::Vector3d& q) const {
  const Eigen::Vector3d g = (q - Lo_) / H_;
  return g(0) >= 0 && g(1) >= 0 && g(2) >= 0 && g(0) < Dims_[0] - 1 && g(1) < Dims_[1] - 1 &&
         g(2) < Dims_[2] - 1;
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
  const int32_t seg = LeadingTable_[size_t(k) * TableNr_ + i];
  return seg >= 0 && rho <= SegmentRhoMax_[size_t(seg)] - rimBandMm;
}

void ToolDistanceField::PartBox(ToolPart part, Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
  lo = part == ToolPart::Whole ? Lo_ : LeadLo_;
  hi = part == ToolPart::Whole ? Hi_ : LeadHi_;
}

bool ToolDistanceField::Has(ToolPart part) const {
  return part == ToolPart::Whole ||
         std::find(Leading_.begin(), Leading_.end(), 1) != Leading_.end();
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

bool ToolDistanceField::Corners(const Eigen::Vector3d& q, double v[8], double& a, double& b,
                                double& c) const {
  const Eigen::Vector3d g = (q - Lo_) / H_;
  if (!(g(0) >= 0 && g(1) >= 0 && g(2) >= 0 && g(0) < Dims_[0] - 1 && g(1) < Dims_[1] - 1 &&
        g(2) < Dims_[2] - 1))
    return false;
  const int i = int(g(0)), j = int(g(1)), k = int(g(2));
  a = g(0) - i;
  b = g(1) - j;
  c = g(2) - k;
  const size_t sx = 1, sy = size_t(Dims_[0]), sz = size_t(Dims_[0]) * Dims_[1];
  const float* p = &D_[size_t(i) + sy * j + sz * k];
  // v[x + 2 y + 4 z] is the corner (x, y, z) of the cell.
  v[0] = p[0], v[1] = p[sx], v[2] = p[sy], v[3] = p[sx + sy];
  v[4] = p[sz], v[5] = p[sx + sz], v[6] = p[sy + sz], v[7] = p[sx + sy + sz];
  return true;
}

double ToolDistanceField::Sample(const Eigen::Vector3d& q, Eigen::Vector3d& grad) const {
  double v[8], a, b, c;
  if (!Corners(q, v, a, b, c)) {
    grad.setZero();
    return Far_;
  }
  const double v00 = v[0] + a * (v[1] - v[0]), v10 = v[2] + a * (v[3] - v[2]);
  const double v01 = v[4] + a * (v[5] - v[4]), v11 = v[6] + a * (v[7] - v[6]);
  const double v0 = v00 + b * (v10 - v00), v1 = v01 + b * (v11 - v01);
  const double dx0 = (1 - b) * (v[1] - v[0]) + b * (v[3] - v[2]),
               dx1 = (1 - b) * (v[5] - v[4]) + b * (v[7] - v[6]);
  grad(0) = ((1 - c) * dx0 + c * dx1) / H_;
  grad(1) = ((1 - c) * (v10 - v00) + c * (v11 - v01)) / H_;
  grad(2) = (v1 - v0) / H_;
  return v0 + c * (v1 - v0);
}

double ToolDistanceField::Value(const Eigen::Vector3d& q) const {
  double v[8], a, b, c;
  if (!Corners(q, v, a, b, c))
    return Far_;
  const double v00 = v[0] + a * (v[1] - v[0]), v10 = v[2] + a * (v[3] - v[2]);
  const double v01 = v[4] + a * (v[5] - v[4]), v11 = v[6] + a * (v[7] - v[6]);
  const double v0 = v00 + b * (v10 - v00), v1 = v01 + b * (v11 - v01);
  return v0 + c * (v1 - v0);
}

} // namespace bm
