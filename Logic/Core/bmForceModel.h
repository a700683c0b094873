// bmForceModel.h - elemental oblique-cutting forces (Faieghi et al. 2020 eqs. 1-6, Docs/Model.md
// section 2).
//
// For a cutting-edge element at radial distance r with radial extent delta:
//   A_u = (f delta / N_c) cos(mu),  df_n = k_c A_u,  df_t = k_t A_u  (k_t = k_f k_c)
//   dF_E = T[:,0] df_n + T[:,1] df_t   (eta_c = lambda, Stabler's chip-flow law)
//   dF_T = R(tau, mu) dF_E
// Tool-local frame of the element: x radial (outward), y along the cutting velocity, z along the
// tool axis from tip to shank. Sign convention: thrust F = sum dF_z (positive pushes the tool back
// out of the bone), resisting torque M = -sum r dF_y (positive opposes the spindle).
//
// Coefficients are linear in chosen basis functions: k_c = sum_i a_i g_i, k_t = sum_i b_i g_i, so
// thrust and torque are linear in (a, b) and calibration is one least-squares solve.
//
// Methods:
//  - Lazar (default, Faieghi et al.): basis {1, 1 - sin gamma_n}, feed angle mu kept everywhere.
//  - Zheng (baseline, Zheng et al. 2012/13): basis {1, 1/V}, mu = 0 on the lips.
//
// Every coefficient set carries its provenance (name, calibrated flag, source), written to and read
// from JSON, so reports can say which set produced a force and whether it was fitted to measured
// data (Docs/Calibration.md lists the shipped sets).
//
// Units: r, delta in mm; f in mm/rev; n in rpm; V in m/min; k in N/mm^2; forces in N.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "bmToolModel.h"

namespace bm {

enum class Method { Lazar, Zheng };
std::string ToString(Method m);
/// "lazar" or "zheng"; throws std::invalid_argument otherwise.
Method MethodFromString(const std::string& s);

/// A basis function of the cutting coefficients.
enum class BasisTerm {
  One,              ///< 1
  OneMinusSinGamma, ///< 1 - sin(gamma_n)
  ChipThickness,    ///< f cos(mu) / N_c, mm
  CuttingSpeed,     ///< V = 2 pi r n / 1000, m/min
  InvCuttingSpeed,  ///< 1 / V, min/m
  InvSpindleSpeed,  ///< 1000 / n (n in rpm): 1 at 1000 rpm, the whole tool's speed effect
};
std::string ToString(BasisTerm t);
BasisTerm BasisTermFromString(const std::string& s);

/// k_c = sum kc[i] g_i, k_t = k_f k_c = sum kt[i] g_i (N/mm^2).
struct Coefficients {
  std::vector<BasisTerm> basis;
  std::vector<double> kc;
  std::vector<double> kt;
  nlohmann::json ToJson() const;
  static Coefficients FromJson(const nlohmann::json& j);
};

/// Where a coefficient set comes from: shown in reports and summaries.
struct CoefficientProvenance {
  std::string name = "unnamed"; ///< e.g. "faieghi-assumed", "drilling-bovine-orelaja2020"
  bool calibrated = false;      ///< true only when fitted to measured forces
  std::string source;           ///< data and citation, or the assumption made
};

/// Force on one element per mm of its radial extent delta, in the element's tool-local frame.
struct ElementForce {
  double fx = 0; ///< radial, N/mm
  double fy = 0; ///< along the cutting velocity, N/mm
  double fz = 0; ///< axial (thrust direction), N/mm
};

/// Parts of an element's force that are linear in the coefficients: force per mm of delta =
/// sum_i (kc_i dirN + kt_i dirT) g_i * auPerDelta.
struct ElementTerms {
  double auPerDelta = 0;        ///< A_u / delta = f cos(mu) / N_c, mm
  std::array<double, 3> dirN{}; ///< R T[:,0]: unit normal-force direction (x, y, z)
  std::array<double, 3> dirT{}; ///< R T[:,1]: unit friction-force direction
  std::vector<double> g;        ///< basis values
};

class ForceModel {
public:
  ForceModel() = default;
  /// lips: coefficients of the main lips (the method's basis); chisel: of the chisel edge, whose
  /// model is the same in both methods (Faieghi et al. compare the lips only).
  ForceModel(Method m, Coefficients lips, Coefficients chisel);

  /// Default coefficients (Docs/Calibration.md section 1). Drills with the Lazar method: the
  /// calibrated set "drilling-bovine-orelaja2020", k_c = 1173.85 x 1000/n and k_t = 378.84 x
  /// 1000/n N/mm^2 (n in rpm) on lips and chisel, fitted to Orelaja et al. 2020's bovine femur
  /// rows (the reference drill: 7.77 N and 15.98 N mm at f = 0.02 mm/rev, 1000 rpm; a third less
  /// at 1500 rpm). Zheng's method, and every tool other than a drill: Assumed(m, tool).
  static ForceModel Default(Method m, const ToolModel& tool);
  /// The assumed, uncalibrated set "faieghi-assumed" that the paper's reproductions use: the
  /// Lazar model with k_f = 0.5 gives the reference drill at f = 0.02 mm/rev, n = 1000 rpm a
  /// thrust of 10 N (the middle of Lee et al.'s range) and 11.35 N mm at every speed; Zheng's
  /// model ("zheng-fit-to-faieghi-assumed") is fitted to the Lazar set's entry-phase curves over
  /// the four conditions f in {0.01, 0.02} x n in {500, 3000} through the same calibration code,
  /// so the two methods are compared on equal footing.
  static ForceModel Assumed(Method m, const ToolModel& tool);

  Method GetMethod() const { return Method_; }
  const Coefficients& LipCoefficients() const { return Lips_; }
  const Coefficients& ChiselCoefficients() const { return Chisel_; }
  void SetLipCoefficients(const Coefficients& c);
  nlohmann::json ToJson() const;
  const CoefficientProvenance& Provenance() const { return Provenance_; }
  void SetProvenance(const CoefficientProvenance& p) { Provenance_ = p; }
  /// {"name": ..., "calibrated": true|false, "source": ...}: what every report and summary
  /// prints as its "coefficients".
  nlohmann::json ProvenanceJson() const;
  /// {"method": "lazar"|"zheng", "lips": {...}, "chisel": {...}, "name": ..., "calibrated": ...,
  /// "source": ...}; missing parts take defaults. {"coefficients": NAME_OR_PATH} loads a
  /// coefficient file (LoadCoefficientSet) instead; other keys then must not be given, except a
  /// "method" that agrees with the file's.
  static ForceModel FromJson(const nlohmann::json& j, const ToolModel& tool);
  /// Whether the feed angle is kept on the lips (Lazar yes, Zheng no; chisel edges keep it).
  bool UsesFeedAngleOnLips() const { return Method_ == Method::Lazar; }

  /// Decompose an element at radius r (mm) on an edge of `kind` at feed f (mm/rev), speed n (rpm).
  ElementTerms Terms(const ToolModel& tool, EdgeKind kind, double r, double f, double n) const;
  /// Force per mm of delta for an element (material scale multiplies k_c and k_t).
  ElementForce Evaluate(const ToolModel& tool, EdgeKind kind, double r, double f, double n,
                        double material = 1.0) const;

private:
  Method Method_ = Method::Lazar;
  Coefficients Lips_;
  Coefficients Chisel_;
  CoefficientProvenance Provenance_;
};

/// A coefficient file: NAME_OR_PATH is a path to a JSON file (ForceModel::ToJson) when such a file
/// exists, else the name of a shipped set, Resources/Calibration/NAME.json. Throws
/// std::invalid_argument naming the file when it is missing or malformed.
nlohmann::json LoadCoefficientSet(const std::string& nameOrPath);

/// Force of one radial bin of an edge per mm of delta, averaged over the bin's width (4-point
/// Gauss-Legendre): taking the bin centre overstates the chisel's thrust near the axis, where the
/// feed angle changes within microns (+0.5 % at shell 512). torque = average of -r dF_y.
struct BinForce {
  double fx = 0, fy = 0, fz = 0; ///< N/mm
  double torque = 0;             ///< N mm/mm
};
/// The table of every bin for feed f (mm/rev) and speed n (rpm), as the VPS engines use it.
std::vector<BinForce>
ForceTable(const ToolModel& tool, const ForceModel& model,
           const std::vector<std::pair<EdgeKind, std::array<double, 2>>>& bins, double f, double n);

/// Thrust (N) and resisting torque (N mm) of the fully engaged tool, integrated along every
/// cutting edge by composite Gauss-Legendre quadrature: the number a VPS result converges to.
struct EdgeIntegral {
  double thrustN = 0;
  double torqueNmm = 0;
};
/// Elements count as engaged when their edge height above the foremost cutting point is below
/// depthMm (infinity = full engagement, the steady-state reference). Lips scale by N_c.
/// onlyKind = None integrates every edge kind, otherwise only that kind.
EdgeIntegral IntegrateEdges(const ToolModel& tool, const ForceModel& model, double f, double n,
                            double depthMm = 1e300, EdgeKind onlyKind = EdgeKind::None,
                            int panels = 2000);
/// Height (mm) of the cutting edge at radius r above the tool's foremost cutting point.
double EdgeHeight(const ToolModel& tool, double r);

} // namespace bm
