#include "bmGlenoidGeometry.h"

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace bm {

namespace {
constexpr double kDeg = 180.0 / std::numbers::pi;
Eigen::Vector3d E(const Vec3& a) {
  return {a[0], a[1], a[2]};
}
Vec3 V(const Eigen::Vector3d& a) {
  return {a[0], a[1], a[2]};
}
} // namespace

PlaneFit FitPlane(const std::vector<Vec3>& points) {
  if (points.size() < 3)
    throw std::invalid_argument("a plane fit needs at least 3 points, got " +
                                std::to_string(points.size()));
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points)
    mean += E(p);
  mean /= double(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) {
    const Eigen::Vector3d d = E(p) - mean;
    cov += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  PlaneFit f;
  f.centroid = V(mean);
  f.normal = V(es.eigenvectors().col(0).normalized()); // eigenvalues ascending
  f.rmsMm = std::sqrt(std::max(0.0, es.eigenvalues()[0]) / double(points.size()));
  return f;
}

SphereFit FitSphere(const std::vector<Vec3>& points) {
  const size_t n = points.size();
  if (n < 4)
    throw std::invalid_argument("a sphere fit needs at least 4 points, got " + std::to_string(n));
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points)
    mean += E(p);
  mean /= double(n);
  // Algebraic: |q|^2 = 2 c.q + k with q = p - mean, k = r^2 - |c|^2.
  Eigen::MatrixXd A(n, 4);
  Eigen::VectorXd b(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d q = E(points[i]) - mean;
    A.row(Eigen::Index(i)) << 2 * q[0], 2 * q[1], 2 * q[2], 1.0;
    b[Eigen::Index(i)] = q.squaredNorm();
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 4)
    throw std::invalid_argument("a sphere fit needs points that are not on one plane");
  const Eigen::Vector4d x = qr.solve(b);
  Eigen::Vector3d c = x.head<3>();
  double r = std::sqrt(std::max(0.0, x[3] + c.squaredNorm()));
  // Geometric refinement (Gauss-Newton on |q - c| - r).
  for (int it = 0; it < 20; ++it) {
    Eigen::MatrixXd J(n, 4);
    Eigen::VectorXd res(n);
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d d = E(points[i]) - mean - c;
      const double len = std::max(d.norm(), 1e-12);
      J.row(Eigen::Index(i)) << -d[0] / len, -d[1] / len, -d[2] / len, -1.0;
      res[Eigen::Index(i)] = len - r;
    }
    const Eigen::Vector4d step = J.colPivHouseholderQr().solve(-res);
    c += step.head<3>();
    r += step[3];
    if (step.norm() < 1e-9)
      break;
  }
  SphereFit f;
  f.centre = V(c + mean);
  f.radiusMm = std::abs(r);
  double ss = 0;
  for (const auto& p : points) {
    const double e = (E(p) - mean - c).norm() - f.radiusMm;
    ss += e * e;
  }
  f.rmsMm = std::sqrt(ss / double(n));
  return f;
}

std::vector<Vec3> SupportRim(const std::vector<Vec3>& points, const Vec3& centre, const Vec3& n,
                             const Vec3& eu, const Vec3& ev, int count, double maxRadiusMm) {
  std::vector<Vec3> local;
  std::vector<const Vec3*> src;
  local.reserve(points.size());
  for (const auto& p : points) {
    const Vec3 d = Sub(p, centre);
    const double u = Dot(d, eu), v = Dot(d, ev);
    if (u * u + v * v <= maxRadiusMm * maxRadiusMm) {
      local.push_back({u, v, Dot(d, n)});
      src.push_back(&p);
    }
  }
  std::vector<Vec3> rim;
  if (local.empty())
    return rim;
  rim.reserve(size_t(count));
  for (int k = 0; k < count; ++k) {
    const double phi = 2 * std::numbers::pi * k / count, cu = std::cos(phi), sv = std::sin(phi);
    double best = -std::numeric_limits<double>::infinity();
    size_t bi = 0;
    for (size_t i = 0; i < local.size(); ++i) {
      const double s = local[i][2] + cu * local[i][0] + sv * local[i][1];
      if (s > best)
        best = s, bi = i;
    }
    rim.push_back(*src[bi]);
  }
  return rim;
}

PlaneFit FitRimPlane(const std::vector<Vec3>& rim, int samples) {
  if (rim.size() < 3 || samples < 3)
    throw std::invalid_argument("a rim plane needs at least 3 rim points");
  std::vector<double> cum(rim.size() + 1, 0.0);
  for (size_t i = 0; i < rim.size(); ++i)
    cum[i + 1] = cum[i] + Distance(rim[i], rim[(i + 1) % rim.size()]);
  const double total = cum.back();
  if (!(total > 0))
    return FitPlane(rim);
  std::vector<Vec3> even;
  even.reserve(size_t(samples));
  size_t seg = 0;
  for (int k = 0; k < samples; ++k) {
    const double s = total * k / samples;
    while (seg + 1 < rim.size() && cum[seg + 1] <= s)
      ++seg;
    const double len = cum[seg + 1] - cum[seg];
    const double f = len > 0 ? (s - cum[seg]) / len : 0.0;
    even.push_back(AddScaled(rim[seg], Sub(rim[(seg + 1) % rim.size()], rim[seg]), f));
  }
  return FitPlane(even);
}

std::pair<double, double> RimExtents(const std::vector<Vec3>& rim, const Vec3& centre,
                                     const Vec3& n, const Vec3& up) {
  Vec3 eu = AddScaled(up, n, -Dot(up, n));
  eu = Norm(eu) > 1e-6 ? Normalized(eu) : Normalized(Cross(n, Vec3{1, 0, 0}));
  return ExtentsAlong(rim, centre, eu, Cross(n, eu));
}

std::pair<double, double> ExtentsAlong(const std::vector<Vec3>& points, const Vec3& origin,
                                       const Vec3& a1, const Vec3& a2) {
  double lo1 = 1e30, hi1 = -1e30, lo2 = 1e30, hi2 = -1e30;
  for (const auto& p : points) {
    const Vec3 d = Sub(p, origin);
    lo1 = std::min(lo1, Dot(d, a1)), hi1 = std::max(hi1, Dot(d, a1));
    lo2 = std::min(lo2, Dot(d, a2)), hi2 = std::max(hi2, Dot(d, a2));
  }
  return {hi1 - lo1, hi2 - lo2};
}

ScapularFrame MakeScapularFrame(const Vec3& g, const Vec3& t, const Vec3& i) {
  ScapularFrame f;
  f.origin = g;
  const Vec3 gt = Sub(g, t), gi = Sub(g, i);
  if (Norm(gt) < 1e-6 || Norm(gi) < 1e-6)
    throw std::invalid_argument("scapular frame: the trigonum and the inferior angle must differ "
                                "from the glenoid centre");
  f.lateral = Normalized(gt);
  Vec3 nrm = Cross(Sub(t, g), Sub(i, g));
  if (Norm(nrm) < 1e-3 * Norm(gt) * Norm(gi))
    throw std::invalid_argument("scapular frame: glenoid centre, trigonum and inferior angle are "
                                "collinear (no scapular plane)");
  nrm = Normalized(nrm);
  if (nrm[1] > 0) // anterior is -y in LPS
    nrm = Scale(nrm, -1);
  f.anterior = nrm;
  f.superior = Normalized(Cross(f.lateral, f.anterior));
  if (Dot(f.superior, gi) < 0)
    f.superior = Scale(f.superior, -1);
  return f;
}

double Version3DDeg(const ScapularFrame& f, const Vec3& n) {
  return std::atan2(Dot(n, f.anterior), Dot(n, f.lateral)) * kDeg;
}

double InclinationDeg(const ScapularFrame& f, const Vec3& n) {
  return std::atan2(Dot(n, f.superior), Dot(n, f.lateral)) * kDeg;
}

Vec3 DirectionFromAngles(const ScapularFrame& f, double versionDeg, double inclinationDeg) {
  if (!(std::abs(versionDeg) < 89) || !(std::abs(inclinationDeg) < 89))
    throw std::invalid_argument("version and inclination must be within (-89, 89) deg");
  return Normalized(Add(f.lateral, Add(Scale(f.anterior, std::tan(versionDeg / kDeg)),
                                       Scale(f.superior, std::tan(inclinationDeg / kDeg)))));
}

double FriedmanVersionDeg(const std::vector<Vec3>& rim, const Vec3& centre, const Vec3& medialTip,
                          Vec3* anteriorRim, Vec3* posteriorRim) {
  const double z = centre[2];
  std::vector<Vec3> cross;
  for (size_t i = 0; i < rim.size(); ++i) {
    const Vec3& a = rim[i];
    const Vec3& b = rim[(i + 1) % rim.size()];
    const double da = a[2] - z, db = b[2] - z;
    if ((da <= 0 && db > 0) || (da > 0 && db <= 0))
      cross.push_back(AddScaled(a, Sub(b, a), da / (da - db)));
  }
  if (cross.size() < 2)
    throw std::runtime_error("Friedman version: the glenoid rim does not cross the axial plane "
                             "through the glenoid centre twice");
  // The two crossings farthest apart; anterior = the one farther toward -y (LPS).
  size_t ia = 0, ib = 1;
  double best = -1;
  for (size_t i = 0; i < cross.size(); ++i)
    for (size_t j = i + 1; j < cross.size(); ++j) {
      const double d = Distance(cross[i], cross[j]);
      if (d > best)
        best = d, ia = i, ib = j;
    }
  Vec3 ant = cross[ia], post = cross[ib];
  if (ant[1] > post[1])
    std::swap(ant, post);
  if (anteriorRim)
    *anteriorRim = ant;
  if (posteriorRim)
    *posteriorRim = post;
  const double mx = 0.5 * (ant[0] + post[0]), my = 0.5 * (ant[1] + post[1]);
  double ax = mx - medialTip[0], ay = my - medialTip[1];
  const double al = std::hypot(ax, ay);
  if (al < 1e-6)
    throw std::runtime_error("Friedman version: the medial tip lies on the glenoid line");
  ax /= al, ay /= al;
  const double lx = ant[0] - post[0], ly = ant[1] - post[1];
  double nx = ly, ny = -lx; // a perpendicular of the glenoid line, turned lateral
  if (nx * ax + ny * ay < 0)
    nx = -nx, ny = -ny;
  double px = -ay, py = ax; // the axis' perpendicular, turned anterior (-y)
  if (py > 0)
    px = -px, py = -py;
  return std::atan2(nx * px + ny * py, nx * ax + ny * ay) * kDeg;
}

} // namespace bm
