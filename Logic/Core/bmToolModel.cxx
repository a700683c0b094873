#include "bmToolModel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <type_traits>

#include <nlohmann/json.hpp>

namespace bm {

namespace {
constexpr double kPi = std::numbers::pi;
double Deg(double d) {
  return d * kPi / 180.0;
}
double Clamp1(double x) {
  return std::clamp(x, -1.0, 1.0);
}

double FeedAngle(double r, double f, bool use) {
  if (!use)
    return 0.0;
  return std::atan2(f, 2.0 * kPi * std::max(r, 1e-12));
}

// Samples a curve rho(s), z(s) for s in [0, 1] into segments no longer than maxSeg.
template <class F>
void AppendCurve(std::vector<ProfilePoint>& out, F point, EdgeKind kind, double approxLength,
                 double maxSeg) {
  int n = std::max(1, int(std::ceil(approxLength / std::max(maxSeg, 1e-6))));
  for (int i = 0; i < n; ++i) {
    auto [rho, z] = point(double(i) / n);
    out.push_back({rho, z, kind});
  }
}

void AppendLine(std::vector<ProfilePoint>& out, double r0, double z0, double r1, double z1,
                EdgeKind kind, double maxSeg) {
  double len = std::hypot(r1 - r0, z1 - z0);
  AppendCurve(
      out,
      [&](double s) {
        return std::pair{r0 + s * (r1 - r0), z0 + s * (z1 - z0)};
      },
      kind, len, maxSeg);
}

// Largest tool length or radius accepted (mm) and most lips: a tool parameter beyond them is
// refused with the range in the message.
constexpr double kMaxToolSizeMm = 1000.0;
constexpr int kMaxToolLips = 64;

void CheckPositive(double v, const char* name) {
  if (!(v > 0) || !std::isfinite(v))
    throw std::invalid_argument(std::string("tool parameter '") + name + "' must be > 0");
  if (v > kMaxToolSizeMm)
    throw std::invalid_argument(std::string("tool parameter '") + name + "' must be at most " +
                                std::to_string(int(kMaxToolSizeMm)) + " mm, got " +
                                std::to_string(v));
}

// Every length and angle finite and within [lo, hi] (the message gives the range).
void CheckRange(double v, double lo, double hi, const char* name) {
  if (!(v >= lo && v <= hi))
    throw std::invalid_argument(std::string("tool parameter '") + name + "' must be in [" +
                                std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                                std::to_string(v));
}

void CheckLips(int lips) {
  if (lips < 1)
    throw std::invalid_argument("tool parameter 'lips' must be >= 1");
  if (lips > kMaxToolLips)
    throw std::invalid_argument("tool parameter 'lips' must be in [1, " +
                                std::to_string(kMaxToolLips) + "], got " + std::to_string(lips));
}
} // namespace

// ---------------------------------------------------------------------------------------------
// TwistDrill

TwistDrill::TwistDrill(const TwistDrillParams& p) : P_(p) {
  CheckPositive(P_.radius, "radius");
  CheckPositive(P_.fluteLength, "flute_length");
  if (!(P_.pointAngleDeg > 10 && P_.pointAngleDeg < 90))
    throw std::invalid_argument("tool parameter 'point_angle_deg' must be in (10, 90)");
  if (!(P_.helixAngleDeg >= 0 && P_.helixAngleDeg < 60))
    throw std::invalid_argument("tool parameter 'helix_angle_deg' must be in [0, 60)");
  if (!(P_.chiselAngleDeg > 90 && P_.chiselAngleDeg < 180))
    throw std::invalid_argument("tool parameter 'chisel_angle_deg' must be in (90, 180)");
  CheckRange(P_.webHalfWidth, 0.0, kMaxToolSizeMm, "web_half_width");
  if (!(P_.webHalfWidth >= 0 && ChiselCornerRadius() < P_.radius))
    throw std::invalid_argument("tool parameter 'web_half_width' must be >= 0 and leave a lip");
  CheckLips(P_.lips);
  if (P_.fluteLength <= TipHeight(P_.radius))
    throw std::invalid_argument("tool parameter 'flute_length' must exceed the tip height");
}

double TwistDrill::ChiselCornerRadius() const {
  return P_.webHalfWidth / std::sin(Deg(P_.chiselAngleDeg));
}

double TwistDrill::TipHeight(double rho) const {
  // The lip's projection is a line at distance w from the axis; it meets the chisel edge at the
  // corner radius R_c = w / sin(psi). Heights are measured from the (flat) chisel edge.
  const double w = P_.webHalfWidth, rc = ChiselCornerRadius();
  if (rho <= rc)
    return 0.0;
  return (std::sqrt(rho * rho - w * w) - std::sqrt(rc * rc - w * w)) /
         std::tan(Deg(P_.pointAngleDeg));
}

bool TwistDrill::ZRange(double rho, double& zLo, double& zHi) const {
  if (rho > P_.radius || rho < 0)
    return false;
  zLo = TipHeight(rho);
  zHi = P_.fluteLength;
  return true;
}

std::array<double, 2> TwistDrill::EdgeRange(EdgeKind kind) const {
  switch (kind) {
  case EdgeKind::Lip:
    return {ChiselCornerRadius(), P_.radius};
  case EdgeKind::Chisel:
    return {0.0, ChiselCornerRadius()};
  default:
    return {0.0, 0.0};
  }
}

CuttingAngles TwistDrill::Angles(EdgeKind kind, double r, double f, bool useFeedAngle) const {
  CuttingAngles a;
  const double epsLip = Deg(P_.pointAngleDeg);
  if (kind == EdgeKind::Chisel) {
    // Chisel edge perpendicular to the axis: eps = 90 deg, lambda = beta = tau = 0; mu matters
    // here because r is small, so both force models keep it.
    a.eps = kPi / 2;
    a.mu = FeedAngle(r, f, true);
    a.gammaN = -std::atan(std::tan(epsLip) * std::cos(kPi / 2 - Deg(P_.chiselAngleDeg)));
    return a;
  }
  a.eps = epsLip;
  a.mu = FeedAngle(r, f, useFeedAngle);
  a.beta = std::asin(std::min(1.0, P_.webHalfWidth / std::max(r, 1e-12)));
  const double se = std::sin(a.eps), ce = std::cos(a.eps);
  const double sb = std::sin(a.beta), cb = std::cos(a.beta);
  a.lambda = std::asin(Clamp1(sb * std::cos(a.mu) * se + std::sin(a.mu) * ce));
  const double tanThetaL = (r / P_.radius) * std::tan(Deg(P_.helixAngleDeg));
  // Eq. 6 with the printed "cos p" read as cos(eps); atan2 keeps it finite where cos(beta) -> 0.
  a.gammaN = std::atan2(tanThetaL * cb, se - ce * tanThetaL * sb) -
             std::atan2(sb * ce - se * std::tan(a.mu), cb);
  a.tau = std::acos(Clamp1(se * cb / std::cos(a.lambda)));
  return a;
}

double TwistDrill::LipAzimuth(int lip, double r) const {
  double base = 2.0 * kPi * lip / P_.lips;
  if (r < ChiselCornerRadius())
    return base + kPi / 2; // the chisel edge joins the lips' inner ends
  return base + std::asin(std::min(1.0, P_.webHalfWidth / std::max(r, 1e-12)));
}

std::vector<ProfilePoint> TwistDrill::Profile(double maxSeg) const {
  std::vector<ProfilePoint> out;
  const double w = ChiselCornerRadius(), R = P_.radius, L = P_.fluteLength;
  if (w > 0)
    AppendLine(out, 0, 0, w, 0, EdgeKind::Chisel, maxSeg);
  AppendCurve(
      out,
      [&](double s) {
        double rho = w + s * (R - w);
        return std::pair{rho, TipHeight(rho)};
      },
      EdgeKind::Lip, (R - w) / std::sin(Deg(P_.pointAngleDeg)), maxSeg);
  AppendLine(out, R, TipHeight(R), R, L, EdgeKind::None, maxSeg);
  AppendLine(out, R, L, 0, L, EdgeKind::None, maxSeg);
  out.push_back({0, L, EdgeKind::None});
  return out;
}

nlohmann::json TwistDrill::Parameters() const {
  return {{"type", "drill"},
          {"radius_mm", P_.radius},
          {"point_angle_deg", P_.pointAngleDeg},
          {"helix_angle_deg", P_.helixAngleDeg},
          {"chisel_angle_deg", P_.chiselAngleDeg},
          {"web_half_width_mm", P_.webHalfWidth},
          {"lips", P_.lips},
          {"flute_length_mm", P_.fluteLength}};
}

// ---------------------------------------------------------------------------------------------
// ArcLipTool (glenoid reamer, burr)

ArcLipParams ArcLipTool::Burr(double radiusMm, int lips) {
  ArcLipParams p;
  p.kind = "burr";
  p.arcRadius = radiusMm;
  p.arcCentreOffset = 0;
  p.alphaDeg = 0;
  p.rakeDeg = 0;
  p.outerRadius = radiusMm;
  p.lips = lips;
  p.nippleRadius = 0;
  p.nippleLength = 0;
  p.headThickness = 0;
  p.shaftRadius = 0.4 * radiusMm;
  p.shaftLength = 10.0;
  return p;
}

ArcLipTool::ArcLipTool(const ArcLipParams& p) : P_(p) {
  CheckPositive(P_.arcRadius, "arc_radius");
  CheckPositive(P_.outerRadius, "outer_radius");
  CheckPositive(P_.shaftRadius, "shaft_radius");
  CheckPositive(P_.shaftLength, "shaft_length");
  if (P_.kind != "reamer" && P_.kind != "burr")
    throw std::invalid_argument("arc-lip tool kind must be 'reamer' or 'burr'");
  CheckLips(P_.lips);
  CheckRange(P_.alphaDeg, 0.0, 89.0, "alpha_deg");
  CheckRange(P_.rakeDeg, -60.0, 60.0, "rake_deg");
  CheckRange(P_.arcCentreOffset, 0.0, kMaxToolSizeMm, "arc_centre_offset");
  CheckRange(P_.nippleRadius, 0.0, kMaxToolSizeMm, "nipple_radius");
  CheckRange(P_.nippleLength, 0.0, kMaxToolSizeMm, "nipple_length");
  CheckRange(P_.headThickness, 0.0, kMaxToolSizeMm, "head_thickness");
  if (P_.arcCentreOffset < 0)
    throw std::invalid_argument("tool parameter 'arc_centre_offset' must be >= 0");
  if (std::abs(P_.outerRadius - P_.arcCentreOffset) > P_.arcRadius)
    throw std::invalid_argument("tool parameter 'outer_radius' lies beyond the lip arc");
  if (P_.nippleRadius < 0 || P_.nippleRadius >= P_.outerRadius)
    throw std::invalid_argument("tool parameter 'nipple_radius' must be in [0, outer_radius)");
  if (P_.shaftRadius > P_.outerRadius)
    throw std::invalid_argument("tool parameter 'shaft_radius' must not exceed outer_radius");
  if (P_.kind == "reamer")
    CheckPositive(P_.headThickness, "head_thickness");
  if (LipInnerRadius() >= P_.outerRadius)
    throw std::invalid_argument("tool has no cutting lip: nipple or alpha leave no radius to cut");
}

double ArcLipTool::OuterRadius() const {
  return P_.outerRadius;
}

double ArcLipTool::FaceHeight(double rho) const {
  // Lip arc centred at (w, R) in (rho, z): its lowest point (rho = w) is at z = 0.
  double d = rho - P_.arcCentreOffset;
  return P_.arcRadius - std::sqrt(std::max(0.0, P_.arcRadius * P_.arcRadius - d * d));
}

double ArcLipTool::LipInnerRadius() const {
  double betaLimit =
      P_.arcRadius * std::sin(Deg(P_.alphaDeg)); // beta = asin(R sin a / r) needs r >= this
  return std::max({P_.nippleRadius, betaLimit * (1 + 1e-9), 0.0});
}

std::array<double, 2> ArcLipTool::AxialRange() const {
  double zMin = P_.nippleRadius > 0 ? -P_.nippleLength : 0.0;
  double back = BackHeight();
  return {std::min(zMin, 0.0), back + P_.shaftLength};
}

double ArcLipTool::BackHeight() const {
  if (P_.kind == "burr")
    return P_.arcRadius +
           std::sqrt(std::max(0.0, P_.arcRadius * P_.arcRadius - P_.shaftRadius * P_.shaftRadius));
  return FaceHeight(P_.outerRadius) + P_.headThickness;
}

bool ArcLipTool::ZRange(double rho, double& zLo, double& zHi) const {
  if (rho < 0 || rho > P_.outerRadius)
    return false;
  zLo = (P_.nippleRadius > 0 && rho <= P_.nippleRadius) ? -P_.nippleLength : FaceHeight(rho);
  if (rho <= P_.shaftRadius) {
    zHi = BackHeight() + P_.shaftLength;
  } else if (P_.kind == "burr") {
    zHi = P_.arcRadius + std::sqrt(std::max(0.0, P_.arcRadius * P_.arcRadius - rho * rho));
  } else {
    zHi = BackHeight();
  }
  return true;
}

std::array<double, 2> ArcLipTool::EdgeRange(EdgeKind kind) const {
  if (kind == EdgeKind::Lip)
    return {LipInnerRadius(), P_.outerRadius};
  return {0.0, 0.0};
}

CuttingAngles ArcLipTool::Angles(EdgeKind, double r, double f, bool useFeedAngle) const {
  CuttingAngles a;
  a.eps = std::acos(Clamp1((r - P_.arcCentreOffset) / P_.arcRadius));
  a.beta = std::asin(std::min(1.0, P_.arcRadius * std::sin(Deg(P_.alphaDeg)) / std::max(r, 1e-12)));
  a.mu = FeedAngle(r, f, useFeedAngle);
  const double se = std::sin(a.eps), ce = std::cos(a.eps);
  a.lambda = std::asin(Clamp1(std::sin(a.beta) * std::cos(a.mu) * se + std::sin(a.mu) * ce));
  a.gammaN = Deg(P_.rakeDeg);
  a.tau = std::acos(Clamp1(se * std::cos(a.beta) / std::cos(a.lambda)));
  return a;
}

double ArcLipTool::LipAzimuth(int lip, double r) const {
  return 2.0 * kPi * lip / P_.lips +
         std::asin(std::min(1.0, P_.arcRadius * std::sin(Deg(P_.alphaDeg)) / std::max(r, 1e-12)));
}

std::vector<ProfilePoint> ArcLipTool::Profile(double maxSeg) const {
  std::vector<ProfilePoint> out;
  const double rn = P_.nippleRadius, rl = LipInnerRadius(), ro = P_.outerRadius;
  auto face = [&](double a, double b, EdgeKind kind) {
    if (b <= a)
      return;
    AppendCurve(
        out,
        [&](double s) {
          double rho = a + s * (b - a);
          return std::pair{rho, FaceHeight(rho)};
        },
        kind, (b - a) * 2.0, maxSeg);
  };
  if (rn > 0) {
    AppendLine(out, 0, -P_.nippleLength, rn, -P_.nippleLength, EdgeKind::None, maxSeg);
    AppendLine(out, rn, -P_.nippleLength, rn, FaceHeight(rn), EdgeKind::None, maxSeg);
  }
  face(rn, rl, EdgeKind::None);
  face(rl, ro, EdgeKind::Lip);
  const double back = BackHeight(), top = back + P_.shaftLength, rs = P_.shaftRadius;
  if (P_.kind == "burr") {
    const double R = P_.arcRadius;
    double th1 = std::asin(std::min(1.0, rs / R));
    AppendCurve(
        out,
        [&](double s) {
          double th = kPi / 2 - s * (kPi / 2 - th1); // from the equator up to the shaft
          return std::pair{R * std::sin(th), R + R * std::cos(th)};
        },
        EdgeKind::None, R * (kPi / 2 - th1), maxSeg);
  } else {
    AppendLine(out, ro, FaceHeight(ro), ro, back, EdgeKind::None, maxSeg);
    AppendLine(out, ro, back, rs, back, EdgeKind::None, maxSeg);
  }
  AppendLine(out, rs, back, rs, top, EdgeKind::None, maxSeg);
  AppendLine(out, rs, top, 0, top, EdgeKind::None, maxSeg);
  out.push_back({0, top, EdgeKind::None});
  return out;
}

nlohmann::json ArcLipTool::Parameters() const {
  return {{"type", P_.kind},
          {"arc_radius_mm", P_.arcRadius},
          {"arc_centre_offset_mm", P_.arcCentreOffset},
          {"alpha_deg", P_.alphaDeg},
          {"rake_deg", P_.rakeDeg},
          {"outer_radius_mm", P_.outerRadius},
          {"lips", P_.lips},
          {"nipple_radius_mm", P_.nippleRadius},
          {"nipple_length_mm", P_.nippleLength},
          {"head_thickness_mm", P_.headThickness},
          {"shaft_radius_mm", P_.shaftRadius},
          {"shaft_length_mm", P_.shaftLength}};
}

// ---------------------------------------------------------------------------------------------

namespace {
template <class T>
void Take(const nlohmann::json& spec, const char* key, T& dst, std::vector<std::string>& used) {
  used.push_back(key);
  if (!spec.contains(key))
    return;
  if constexpr (std::is_integral_v<T>) {
    // Out of the integer's range or not whole: refused, not converted (NaN, 1e300: undefined).
    const nlohmann::json& v = spec.at(key);
    if (v.is_number()) {
      const double x = v.get<double>();
      if (!(x >= double(std::numeric_limits<T>::min()) &&
            x <= double(std::numeric_limits<T>::max())) ||
          x != std::floor(x))
        throw std::invalid_argument(std::string("tool field '") + key +
                                    "' must be a whole number within the integers, got " +
                                    v.dump());
    }
  }
  try {
    dst = spec.at(key).get<T>();
  } catch (const std::exception&) {
    throw std::invalid_argument(std::string("tool field '") + key + "' has the wrong type");
  }
}
} // namespace

std::unique_ptr<ToolModel> MakeTool(const nlohmann::json& spec) {
  if (!spec.is_object())
    throw std::invalid_argument("tool must be a JSON object");
  std::string type = spec.value("type", std::string("drill"));
  std::vector<std::string> used{"type"};
  std::unique_ptr<ToolModel> tool;
  if (type == "drill") {
    TwistDrillParams p;
    Take(spec, "radius_mm", p.radius, used);
    Take(spec, "point_angle_deg", p.pointAngleDeg, used);
    Take(spec, "helix_angle_deg", p.helixAngleDeg, used);
    Take(spec, "chisel_angle_deg", p.chiselAngleDeg, used);
    Take(spec, "web_half_width_mm", p.webHalfWidth, used);
    Take(spec, "lips", p.lips, used);
    Take(spec, "flute_length_mm", p.fluteLength, used);
    tool = std::make_unique<TwistDrill>(p);
  } else if (type == "reamer" || type == "burr") {
    ArcLipParams p;
    if (type == "burr") {
      double r = spec.value("radius_mm", 2.0);
      used.push_back("radius_mm");
      p = ArcLipTool::Burr(r);
    }
    Take(spec, "arc_radius_mm", p.arcRadius, used);
    Take(spec, "arc_centre_offset_mm", p.arcCentreOffset, used);
    Take(spec, "alpha_deg", p.alphaDeg, used);
    Take(spec, "rake_deg", p.rakeDeg, used);
    Take(spec, "outer_radius_mm", p.outerRadius, used);
    Take(spec, "lips", p.lips, used);
    Take(spec, "nipple_radius_mm", p.nippleRadius, used);
    Take(spec, "nipple_length_mm", p.nippleLength, used);
    Take(spec, "head_thickness_mm", p.headThickness, used);
    Take(spec, "shaft_radius_mm", p.shaftRadius, used);
    Take(spec, "shaft_length_mm", p.shaftLength, used);
    tool = std::make_unique<ArcLipTool>(p);
  } else {
    throw std::invalid_argument("unknown tool type '" + type + "' (drill, reamer or burr)");
  }
  for (auto it = spec.begin(); it != spec.end(); ++it)
    if (std::find(used.begin(), used.end(), it.key()) == used.end())
      throw std::invalid_argument("unknown tool field '" + it.key() + "' for a " + type);
  return tool;
}

} // namespace bm
