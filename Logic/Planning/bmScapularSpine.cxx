#include "bmScapularSpine.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace bm {

namespace {

struct WeightedPoint {
  Vec3 p;
  double w;
};

/// Weighted centroid and the eigenvectors of the weighted covariance, by ascending eigenvalue.
void Principal(const std::vector<WeightedPoint>& pts, Vec3& centroid, Eigen::Matrix3d& axes) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  double W = 0;
  for (const auto& q : pts)
    m += q.w * Eigen::Vector3d(q.p[0], q.p[1], q.p[2]), W += q.w;
  m /= W;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& q : pts) {
    const Eigen::Vector3d d = Eigen::Vector3d(q.p[0], q.p[1], q.p[2]) - m;
    cov += q.w * d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov / W);
  centroid = {m[0], m[1], m[2]};
  axes = es.eigenvectors();
}

Vec3 Column(const Eigen::Matrix3d& m, int c) {
  return {m(0, c), m(1, c), m(2, c)};
}

double Quantile(std::vector<double> v, double q) {
  if (v.empty())
    return 0;
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size())));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

std::string Mm(double v, const char* unit = " mm") {
  std::ostringstream s;
  s.precision(1);
  s << std::fixed << v << unit;
  return s.str();
}

} // namespace

SpineRootResult FindSpineRoot(const SegmentedBone& bone, int label, const Vec3& centre,
                              const SpineRootOptions& o) {
  SpineRootResult out;
  const double h = bone.Spacing(), voxelVolume = h * h * h;
  const auto& d = bone.Dims();
  std::vector<WeightedPoint> pts;
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i) {
        const int64_t idx = bone.Index(i, j, k);
        if (bone.Label(idx) != label)
          continue;
        const Vec3 p = bone.Centre(i, j, k);
        if (Distance(p, centre) > o.exclusionRadiusMm)
          pts.push_back({p, double(bone.Fraction(idx))});
      }
  if (pts.size() < 100) {
    out.reason = "too little scapula beyond " + Mm(o.exclusionRadiusMm) + " of the glenoid";
    return out;
  }
  // 1. The blade's mid-plane, refitted to the voxels near it.
  Vec3 m{}, n{};
  Eigen::Matrix3d axes;
  Principal(pts, m, axes);
  n = Column(axes, 0);
  std::vector<WeightedPoint> near;
  std::vector<double> dist;
  for (int it = 0; it < 3; ++it) {
    dist.clear();
    for (const auto& q : pts)
      dist.push_back(std::abs(Dot(Sub(q.p, m), n)));
    const double keep = std::max(3.0, 2.5 * Quantile(dist, 0.5));
    near.clear();
    for (const auto& q : pts)
      if (std::abs(Dot(Sub(q.p, m), n)) <= keep)
        near.push_back(q);
    if (near.size() < 100)
      break;
    Principal(near, m, axes);
    n = Column(axes, 0);
  }
  dist.clear();
  for (const auto& q : near)
    dist.push_back(std::abs(Dot(Sub(q.p, m), n)));
  const double half = Quantile(dist, 0.95);
  // 2. The spine: bone standing off the blade, on the side holding more of it.
  const double off = half + std::max(3.0, 2 * h);
  std::vector<WeightedPoint> side[2];
  double volume[2] = {0, 0};
  for (const auto& q : pts) {
    const double s = Dot(Sub(q.p, m), n);
    if (std::abs(s) > off) {
      const int k = s > 0 ? 0 : 1;
      side[k].push_back({AddScaled(q.p, n, -s), q.w}); // projected on the mid-plane
      volume[k] += q.w * voxelVolume;
    }
  }
  const int k = volume[0] >= volume[1] ? 0 : 1;
  if (volume[k] < o.minSpineVolumeMm3) {
    out.reason = "no scapular spine: " + Mm(volume[k], " mm^3") + " of bone stands more than " +
                 Mm(off) + " off the blade (" + Mm(o.minSpineVolumeMm3, " mm^3") + " needed)";
    return out;
  }
  SpineRoot r;
  r.bladeNormal = k == 0 ? n : Scale(n, -1);
  r.bladeHalfThicknessMm = half;
  r.spineVolumeMm3 = volume[k];
  Vec3 sc{};
  Principal(side[k], sc, axes);
  Vec3 e = Column(axes, 2);
  e = Normalized(AddScaled(e, n, -Dot(e, n)));
  double lo = 1e30, hi = -1e30;
  for (const auto& q : side[k]) {
    const double t = Dot(Sub(q.p, sc), e);
    lo = std::min(lo, t), hi = std::max(hi, t);
  }
  // Medial: the end of the ridge farther from the glenoid.
  const Vec3 endA = AddScaled(sc, e, hi), endB = AddScaled(sc, e, lo);
  if (Distance(endB, centre) > Distance(endA, centre))
    e = Scale(e, -1);
  r.axis = e;
  r.spineLengthMm = hi - lo;
  if (r.spineLengthMm < o.minSpineLengthMm) {
    out.reason = "no scapular spine: the bone off the blade spans " + Mm(r.spineLengthMm) +
                 " along its axis (" + Mm(o.minSpineLengthMm) + " needed)";
    return out;
  }
  // 3. The root: the last blade bone along the axis, medially, before a gap of more than 5 mm.
  const int across = int(std::ceil((half + h) / h));
  auto blade = [&](const Vec3& p) {
    for (int a = -across; a <= across; ++a)
      if (bone.LabelAt(AddScaled(p, n, a * h)) == label)
        return true;
    return false;
  };
  const double step = 0.5 * h;
  double last = 0;
  bool any = false;
  for (double t = 0; t <= 400 && t - last <= 5; t += step)
    if (blade(AddScaled(sc, e, t)))
      last = t, any = true;
  if (!any) {
    out.reason = "the spine's axis does not run along the blade";
    return out;
  }
  r.trigonum = AddScaled(sc, e, last);
  out.root = r;
  return out;
}

} // namespace bm
