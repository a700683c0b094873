#include "bmForceModel.h"
#include "bmJson.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "bmEdgeQuadrature.h"
#include "bmResources.h"

namespace bm {

std::string ToString(Method m) {
  return m == Method::Lazar ? "lazar" : "zheng";
}

Method MethodFromString(const std::string& s) {
  if (s == "lazar")
    return Method::Lazar;
  if (s == "zheng")
    return Method::Zheng;
  throw std::invalid_argument("unknown method '" + s + "' (lazar or zheng)");
}

std::string ToString(BasisTerm t) {
  switch (t) {
  case BasisTerm::One:
    return "1";
  case BasisTerm::OneMinusSinGamma:
    return "1-sin(gamma_n)";
  case BasisTerm::ChipThickness:
    return "chip_thickness_mm";
  case BasisTerm::CuttingSpeed:
    return "V_m_per_min";
  case BasisTerm::InvCuttingSpeed:
    return "1/V_min_per_m";
  case BasisTerm::InvSpindleSpeed:
    return "1000/n_per_rpm";
  }
  return "?";
}

BasisTerm BasisTermFromString(const std::string& s) {
  for (BasisTerm t :
       {BasisTerm::One, BasisTerm::OneMinusSinGamma, BasisTerm::ChipThickness,
        BasisTerm::CuttingSpeed, BasisTerm::InvCuttingSpeed, BasisTerm::InvSpindleSpeed})
    if (ToString(t) == s)
      return t;
  throw std::invalid_argument("unknown basis term '" + s +
                              "' (1, 1-sin(gamma_n), chip_thickness_mm, V_m_per_min, "
                              "1/V_min_per_m, 1000/n_per_rpm)");
}

nlohmann::json Coefficients::ToJson() const {
  nlohmann::json b = nlohmann::json::array();
  for (auto t : basis)
    b.push_back(ToString(t));
  return {{"basis", b}, {"kc_N_per_mm2", kc}, {"kt_N_per_mm2", kt}};
}

Coefficients Coefficients::FromJson(const nlohmann::json& j) {
  if (!j.is_object())
    throw std::invalid_argument("coefficients must be an object of basis, kc_N_per_mm2 and "
                                "kt_N_per_mm2");
  for (const char* key : {"basis", "kc_N_per_mm2", "kt_N_per_mm2"})
    if (!j.contains(key) || !j.at(key).is_array() || j.at(key).size() > 64)
      throw std::invalid_argument(std::string("coefficients: '") + key +
                                  "' must be an array of at most 64 entries");
  Coefficients c;
  for (const auto& t : j.at("basis")) {
    if (!t.is_string())
      throw std::invalid_argument("coefficients: a 'basis' entry is not a term name");
    c.basis.push_back(BasisTermFromString(t.get<std::string>()));
  }
  // A coefficient reaches every elemental force: finite and within 1e9 N/mm^2 (calibrated sets
  // are below 1e6), so a huge value cannot overflow the force sums.
  auto numbers = [&](const char* key) {
    std::vector<double> v;
    for (const auto& x : j.at(key)) {
      if (!x.is_number() || !std::isfinite(x.get<double>()) || std::abs(x.get<double>()) > 1e9)
        throw std::invalid_argument(std::string("coefficients: '") + key + "' entry " + x.dump() +
                                    " is not a number within +-1e9 N/mm^2");
      v.push_back(x.get<double>());
    }
    return v;
  };
  c.kc = numbers("kc_N_per_mm2");
  c.kt = numbers("kt_N_per_mm2");
  if (c.kc.size() != c.basis.size() || c.kt.size() != c.basis.size())
    throw std::invalid_argument("coefficients: kc and kt need one value per basis term");
  return c;
}

ForceModel::ForceModel(Method m, Coefficients lips, Coefficients chisel)
    : Method_(m), Lips_(std::move(lips)), Chisel_(std::move(chisel)) {
  for (const Coefficients* c : {&Lips_, &Chisel_})
    if (c->kc.size() != c->basis.size() || c->kt.size() != c->basis.size())
      throw std::invalid_argument("force model: kc and kt need one value per basis term");
}

void ForceModel::SetLipCoefficients(const Coefficients& c) {
  *this = ForceModel(Method_, c, Chisel_);
}

namespace {
// Default chisel edge: k_c = 1000 N/mm^2, k_f = 0.5 (Docs/Model.md section 6), same for both
// methods.
Coefficients DefaultChisel() {
  return {{BasisTerm::One}, {1000.0}, {500.0}};
}

// The assumed set (Docs/Model.md section 3): cortical-bone lips with k_f = k_t / k_c = 0.5 and
// k = c (1 + 0.5 (1 - sin gamma_n)), so the coefficients grow as the rake turns negative (Lazar &
// Xirouchakis); c is set so that the reference drill at f = 0.02 mm/rev, n = 1000 rpm gives a
// total thrust of 10 N, the middle of Lee et al.'s (2012) 0-20 N range; the torque follows at
// 11.35 N mm. No speed term. Every lip element's thrust and torque stay positive (a k_f below
// about 0.40 would make the outer lip pull the tool in; Testing/Logic/Core checks both). Also
// shipped as the named set "faieghi-assumed" (Resources/Calibration/faieghi-assumed.json); the
// measured alternatives are in Docs/Calibration.md.
ForceModel FaieghiAssumed(Method m, const ToolModel& tool) {
  CoefficientProvenance p;
  p.calibrated = false;
  const std::string onTool =
      tool.Kind() == "drill"
          ? std::string()
          : "; drilling coefficients applied to a " + tool.Kind() +
                " (no measured data for it: see the reaming-assumed set, Docs/Calibration.md)";
  if (m == Method::Lazar) {
    Coefficients lips{
        {BasisTerm::One, BasisTerm::OneMinusSinGamma}, {600.572, 300.286}, {300.286, 150.143}};
    ForceModel model(Method::Lazar, lips, DefaultChisel());
    p.name = "faieghi-assumed";
    p.source = "assumption: k_f = 0.5, scaled to 10 N thrust for the reference drill at 0.02 "
               "mm/rev, 1000 rpm (middle of Lee et al. 2012's 0-20 N)" +
               onTool;
    model.SetProvenance(p);
    return model;
  }
  // Zheng et al.'s reciprocal-speed form fitted to the assumed Lazar set's entry curves over
  // f in {0.01, 0.02} mm/rev x n in {500, 3000} rpm by bmCalibration.
  Coefficients lips{
      {BasisTerm::One, BasisTerm::InvCuttingSpeed}, {872.070, 17.28516}, {452.591, 7.99249}};
  ForceModel model(Method::Zheng, lips, DefaultChisel());
  p.name = "zheng-fit-to-faieghi-assumed";
  p.source = "Zheng et al.'s k = a + b/V fitted to the faieghi-assumed set's entry curves" + onTool;
  model.SetProvenance(p);
  return model;
}

// The calibrated drilling set "drilling-bovine-orelaja2020" (Resources/Calibration, the same
// numbers): k_c = 1173.85 x 1000/n, k_t = 378.84 x 1000/n N/mm^2 (n in rpm) on lips and chisel,
// the least-squares fit (bmsim calibrate --bones "bovine femur") to Orelaja et al. 2020's bovine
// femur rows of Resources/Calibration/drilling-published.csv with the reference drill's geometry.
// Torque-to-thrust 2.03 mm (measured 1.96-2.05); k_f = 0.323, so the lips' outer elements, whose
// normal rake exceeds what that friction balances, pull the tool in (Docs/Calibration.md
// section 4).
ForceModel BovineOrelaja2020() {
  const Coefficients c{{BasisTerm::InvSpindleSpeed}, {1173.8507241306545}, {378.8399449938085}};
  ForceModel model(Method::Lazar, c, c);
  model.SetProvenance(
      {"drilling-bovine-orelaja2020", true,
       "bmsim calibrate drilling-published.csv --bones \"bovine femur\" (assumptions in the "
       "rows' notes): Orelaja et al., J Healthc Eng 2020, 8817422, doi:10.1155/2020/8817422 "
       "(abstract)"});
  return model;
}

} // namespace

ForceModel ForceModel::Default(Method m, const ToolModel& tool) {
  // Drills with the Lazar method: the calibrated drilling set. Zheng's baseline and every other
  // tool: the assumed set (Docs/Calibration.md section 1 says why).
  if (m == Method::Lazar && tool.Kind() == "drill")
    return BovineOrelaja2020();
  return FaieghiAssumed(m, tool);
}

ForceModel ForceModel::Assumed(Method m, const ToolModel& tool) {
  return FaieghiAssumed(m, tool);
}

nlohmann::json ForceModel::ToJson() const {
  return {{"method", ToString(Method_)},          {"lips", Lips_.ToJson()},
          {"chisel", Chisel_.ToJson()},           {"name", Provenance_.name},
          {"calibrated", Provenance_.calibrated}, {"source", Provenance_.source}};
}

nlohmann::json ForceModel::ProvenanceJson() const {
  return {{"name", Provenance_.name},
          {"calibrated", Provenance_.calibrated},
          {"source", Provenance_.source}};
}

ForceModel ForceModel::FromJson(const nlohmann::json& j, const ToolModel& tool) {
  if (!j.is_object())
    throw std::invalid_argument("force_model must be a JSON object");
  if (j.contains("coefficients")) {
    if (!j.at("coefficients").is_string())
      throw std::invalid_argument("force_model.coefficients must be a name or a path");
    for (auto it = j.begin(); it != j.end(); ++it)
      if (it.key() != "coefficients" && it.key() != "method")
        throw std::invalid_argument("force_model: '" + it.key() +
                                    "' cannot be combined with 'coefficients'");
    const std::string ref = j.at("coefficients").get<std::string>();
    const nlohmann::json file = LoadCoefficientSet(ref);
    try {
      if (j.contains("method") && j.at("method") != file.value("method", std::string("lazar")))
        throw std::invalid_argument("force_model.method disagrees with the set");
      return FromJson(file, tool);
    } catch (const std::exception& e) { // nlohmann's type errors too: name the set
      throw std::invalid_argument("coefficient set '" + ref + "': " + e.what());
    }
  }
  Method m = MethodFromString(j.value("method", std::string("lazar")));
  ForceModel d = Default(m, tool);
  const bool custom = j.contains("lips") || j.contains("chisel");
  Coefficients lips = j.contains("lips") ? Coefficients::FromJson(j.at("lips")) : d.Lips_;
  Coefficients chisel = j.contains("chisel") ? Coefficients::FromJson(j.at("chisel")) : d.Chisel_;
  ForceModel out(m, lips, chisel);
  CoefficientProvenance p = custom ? CoefficientProvenance{} : d.Provenance_;
  if (j.contains("name"))
    p.name = j.at("name").get<std::string>();
  if (j.contains("calibrated"))
    p.calibrated = j.at("calibrated").get<bool>();
  if (j.contains("source"))
    p.source = j.at("source").get<std::string>();
  out.SetProvenance(p);
  return out;
}

nlohmann::json LoadCoefficientSet(const std::string& nameOrPath) {
  if (nameOrPath.empty())
    throw std::invalid_argument("coefficient set: empty name");
  std::filesystem::path file(nameOrPath);
  if (!std::filesystem::is_regular_file(file)) {
    if (nameOrPath.find('/') != std::string::npos || file.has_extension())
      throw std::invalid_argument("coefficient file '" + nameOrPath + "' not found");
    file = ResourcePath(std::filesystem::path("Calibration") / (nameOrPath + ".json"));
    if (!std::filesystem::is_regular_file(file))
      throw std::invalid_argument("no coefficient set named '" + nameOrPath + "' (" +
                                  file.string() + " not found)");
  }
  std::ifstream in(file);
  nlohmann::json j;
  try {
    j = ParseJson(in, "coefficient file " + file.string());
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(e.what());
  }
  if (!j.is_object() || !j.contains("lips"))
    throw std::invalid_argument("coefficient file " + file.string() +
                                " holds no force model (needs \"lips\")");
  return j;
}

ElementTerms ForceModel::Terms(const ToolModel& tool, EdgeKind kind, double r, double f,
                               double n) const {
  const bool useMu = kind == EdgeKind::Chisel || UsesFeedAngleOnLips();
  const CuttingAngles a = tool.Angles(kind, r, f, useMu);
  const Coefficients& C = kind == EdgeKind::Chisel ? Chisel_ : Lips_;
  ElementTerms t;
  t.auPerDelta = f * std::cos(a.mu) / tool.NumLips();
  const double cg = std::cos(a.gammaN), sg = std::sin(a.gammaN);
  const double cl = std::cos(a.lambda), sl = std::sin(a.lambda);
  const double ce = cl, se = sl; // eta_c = lambda
  // T (eq. 3), first column for df_n, second for df_t (Docs/Model.md section 2: eq. 2 prints
  // them swapped).
  const double Tn[3] = {-cg * sl, -cg * cl, -sg};
  const double Tt[3] = {se * cl - ce * sg * sl, ce * sg * cl + se * sl, ce * cg};
  // R (eq. 4), element frame E -> tool frame T.
  const double ct = std::cos(a.tau), st = std::sin(a.tau), cm = std::cos(a.mu), sm = std::sin(a.mu);
  const double R[3][3] = {{ct, 0, -st}, {st * sm, cm, ct * sm}, {st * cm, -sm, ct * cm}};
  for (int i = 0; i < 3; ++i) {
    t.dirN[i] = R[i][0] * Tn[0] + R[i][1] * Tn[1] + R[i][2] * Tn[2];
    t.dirT[i] = R[i][0] * Tt[0] + R[i][1] * Tt[1] + R[i][2] * Tt[2];
  }
  const double V = 2.0 * std::numbers::pi * r * n / 1000.0; // m/min
  t.g.reserve(C.basis.size());
  for (BasisTerm b : C.basis) {
    switch (b) {
    case BasisTerm::One:
      t.g.push_back(1.0);
      break;
    case BasisTerm::OneMinusSinGamma:
      t.g.push_back(1.0 - sg);
      break;
    case BasisTerm::ChipThickness:
      t.g.push_back(t.auPerDelta);
      break;
    case BasisTerm::CuttingSpeed:
      t.g.push_back(V);
      break;
    case BasisTerm::InvCuttingSpeed:
      t.g.push_back(1.0 / std::max(V, 1e-9));
      break;
    case BasisTerm::InvSpindleSpeed:
      t.g.push_back(1000.0 / std::max(n, 1e-9));
      break;
    }
  }
  return t;
}

ElementForce ForceModel::Evaluate(const ToolModel& tool, EdgeKind kind, double r, double f,
                                  double n, double material) const {
  const ElementTerms t = Terms(tool, kind, r, f, n);
  const Coefficients& C = kind == EdgeKind::Chisel ? Chisel_ : Lips_;
  double kc = 0, kt = 0;
  for (size_t i = 0; i < t.g.size(); ++i) {
    kc += C.kc[i] * t.g[i];
    kt += C.kt[i] * t.g[i];
  }
  const double s = material * t.auPerDelta;
  return {s * (kc * t.dirN[0] + kt * t.dirT[0]), s * (kc * t.dirN[1] + kt * t.dirT[1]),
          s * (kc * t.dirN[2] + kt * t.dirT[2])};
}

std::vector<BinForce>
ForceTable(const ToolModel& tool, const ForceModel& model,
           const std::vector<std::pair<EdgeKind, std::array<double, 2>>>& bins, double f,
           double n) {
  static constexpr double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                  0.8611363115940526};
  static constexpr double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                  0.3478548451374538};
  std::vector<BinForce> table(bins.size());
  for (size_t b = 0; b < bins.size(); ++b) {
    const auto [kind, rdr] = bins[b];
    BinForce& t = table[b];
    for (int q = 0; q < 4; ++q) {
      const double r = rdr[0] + 0.5 * rdr[1] * x[q];
      const ElementForce e = model.Evaluate(tool, kind, r, f, n);
      t.fx += 0.5 * w[q] * e.fx;
      t.fy += 0.5 * w[q] * e.fy;
      t.fz += 0.5 * w[q] * e.fz;
      t.torque += -0.5 * w[q] * r * e.fy;
    }
  }
  return table;
}

double EdgeHeight(const ToolModel& tool, double r) {
  const EdgeKind kind = r < tool.EdgeRange(EdgeKind::Lip)[0] ? EdgeKind::Chisel : EdgeKind::Lip;
  return tool.EdgeZ(kind, r) - ForemostCuttingZ(tool);
}

EdgeIntegral IntegrateEdges(const ToolModel& tool, const ForceModel& model, double f, double n,
                            double depthMm, EdgeKind onlyKind, int panels) {
  EdgeIntegral out;
  ForEachEdgeNode(tool, depthMm, onlyKind, panels, [&](EdgeKind kind, double r, double w) {
    ElementForce e = model.Evaluate(tool, kind, r, f, n);
    out.thrustN += w * e.fz;
    out.torqueNmm += -w * r * e.fy;
  });
  return out;
}

} // namespace bm
