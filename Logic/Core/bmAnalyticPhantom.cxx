// bmAnalyticPhantom.cxx - see bmAnalyticPhantom.h.
#include "bmAnalyticPhantom.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "bmAnalyticGlenoid.h"

namespace bm {

namespace {

constexpr double kPi = std::numbers::pi;

// Glenoid constants (see the header; the shape is bmAnalyticGlenoid.h's).
constexpr double gA = glenoid::kA, gB = glenoid::kB, gRc = glenoid::kRc, gH = glenoid::kH,
                 gRp = glenoid::kRp, gDp = glenoid::kDp;
constexpr std::array<double, 3> gC{-60.0, 20.0, 40.0}, gN{-1, 0, 0}, gU{0, 0, 1}, gV{0, 1, 0};
// Block.
constexpr double bHalf = 3.0, bDepth = 4.0;

// Shoulder.
constexpr double sR = 22.0, sGap = 3.5, sT = 16.0, sHalfY = 20.0, sHalfZ = 30.0, sShell = 1.5;
constexpr double sX1 = -(sR + sGap), sX0 = sX1 - sT; // the plate's x range

PhantomTissue ShoulderTissue(const std::array<double, 3>& p) {
  const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  if (r <= sR)
    return r >= sR - sShell ? PhantomTissue::Cortical : PhantomTissue::HeadCancellous;
  if (p[0] >= sX0 && p[0] <= sX1 && std::abs(p[1]) <= sHalfY && std::abs(p[2]) <= sHalfZ) {
    const double depth =
        std::min({p[0] - sX0, sX1 - p[0], sHalfY - std::abs(p[1]), sHalfZ - std::abs(p[2])});
    return depth <= sShell ? PhantomTissue::Cortical : PhantomTissue::Cancellous;
  }
  return PhantomTissue::Outside;
}

double Dot(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

using Glenoid = glenoid::Region;

Glenoid ClassifyGlenoid(const std::array<double, 3>& p) {
  const std::array<double, 3> d{p[0] - gC[0], p[1] - gC[1], p[2] - gC[2]};
  return glenoid::Classify(Dot(d, gU), Dot(d, gV), Dot(d, gN));
}

double GlenoidVolume() {
  // Solid under the concave face, minus the pilot hole (closed forms + a periodic quadrature).
  const int n = 20000;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    double t = 2 * kPi * i / n;
    double rho2 =
        (gA * gB) * (gA * gB) /
        ((gB * std::cos(t)) * (gB * std::cos(t)) + (gA * std::sin(t)) * (gA * std::sin(t)));
    sum += gRc * gRc * gRc - std::pow(gRc * gRc - rho2, 1.5);
  }
  double capIntegral = sum * (2 * kPi / n) / 3.0; // integral over the ellipse of sqrt(Rc^2 - r^2)
  double solid = kPi * gA * gB * (gH + gRc) - capIntegral;
  double hole = kPi * gRp * gRp * (gDp + gRc) -
                2 * kPi / 3 * (gRc * gRc * gRc - std::pow(gRc * gRc - gRp * gRp, 1.5));
  return solid - hole;
}

} // namespace

std::vector<std::string> PhantomNames() {
  return {"glenoid", "block", "shoulder"};
}

PhantomInfo GetPhantomInfo(const std::string& name) {
  PhantomInfo info;
  info.name = name;
  if (name == "glenoid") {
    info.centreMm = gC;
    info.axisOut = gN;
    info.boneVolumeMm3 = GlenoidVolume();
    double rim = gRc - std::sqrt(gRc * gRc - gA * gA); // face height at the ends of the long axis
    // local w in [-H, rim] along n = -x; u along z; v along y
    info.boneBounds.lo = {gC[0] - rim, gC[1] - gB, gC[2] - gA};
    info.boneBounds.hi = {gC[0] + gH, gC[1] + gB, gC[2] + gA};
    info.pilotHoleRadiusMm = gRp;
    info.pilotHoleDepthMm = gDp;
  } else if (name == "block") {
    info.centreMm = {0, 0, 0};
    info.axisOut = {0, 0, 1};
    info.boneVolumeMm3 = (2 * bHalf) * (2 * bHalf) * bDepth;
    info.boneBounds.lo = {-bHalf, -bHalf, -bDepth};
    info.boneBounds.hi = {bHalf, bHalf, 0};
  } else if (name == "shoulder") {
    info.centreMm = {sX1, 0, 0};
    info.axisOut = {1, 0, 0};
    info.boneVolumeMm3 = 4.0 / 3.0 * kPi * sR * sR * sR + sT * (2 * sHalfY) * (2 * sHalfZ);
    info.boneBounds.lo = {sX0, -sR, -sHalfZ};
    info.boneBounds.hi = {sR, sR, sHalfZ};
  } else {
    throw std::invalid_argument("unknown phantom '" + name + "' (glenoid, block or shoulder)");
  }
  return info;
}

PhantomTissue PhantomTissueAt(const std::string& name, const std::array<double, 3>& p) {
  if (name == "glenoid") {
    switch (ClassifyGlenoid(p)) {
    case Glenoid::Outside:
      return PhantomTissue::Outside;
    case Glenoid::Hole:
      return PhantomTissue::Fluid;
    case Glenoid::Cortical:
      return PhantomTissue::Cortical;
    case Glenoid::Cancellous:
      return PhantomTissue::Cancellous;
    }
  }
  if (name == "block")
    return (std::abs(p[0]) <= bHalf && std::abs(p[1]) <= bHalf && p[2] <= 0 && p[2] >= -bDepth)
               ? PhantomTissue::Cortical
               : PhantomTissue::Outside;
  if (name == "shoulder")
    return ShoulderTissue(p);
  throw std::invalid_argument("unknown phantom '" + name + "' (glenoid, block or shoulder)");
}

bool PhantomIsBone(const std::string& name, const std::array<double, 3>& p) {
  const PhantomTissue t = PhantomTissueAt(name, p);
  return t != PhantomTissue::Outside && t != PhantomTissue::Fluid;
}

} // namespace bm
