#include "bmCalibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include <Eigen/Dense>

#include "bmEdgeQuadrature.h"

namespace bm {

namespace {
constexpr int kPanels = 400;

ForceModel ZeroLips(Method method, const std::vector<BasisTerm>& basis,
                    const ForceModel& chiselFrom, bool shared) {
  Coefficients z{basis, std::vector<double>(basis.size(), 0.0),
                 std::vector<double>(basis.size(), 0.0)};
  return ForceModel(method, z, shared ? z : chiselFrom.ChiselCoefficients());
}

const ToolModel& ToolOf(const ToolModel& tool, const CalibrationSample& s) {
  return s.tool ? *s.tool : tool;
}

// Rows of d(thrust)/d(a,b) and d(torque)/d(a,b) for one sample at material 1, plus the chisel's
// share (zero when the chisel shares the lips' coefficients: its elements are then in the rows).
void DesignRows(const ToolModel& tool, const ForceModel& basisModel, const CalibrationSample& s,
                bool shared, Eigen::RowVectorXd& thrustRow, Eigen::RowVectorXd& torqueRow,
                EdgeIntegral& chisel) {
  const Eigen::Index m = thrustRow.size() / 2;
  thrustRow.setZero();
  torqueRow.setZero();
  const EdgeKind kinds = shared ? EdgeKind::None : EdgeKind::Lip;
  ForEachEdgeNode(tool, s.depthMm, kinds, kPanels, [&](EdgeKind kind, double r, double w) {
    ElementTerms t = basisModel.Terms(tool, kind, r, s.feedMmPerRev, s.speedRpm);
    for (Eigen::Index i = 0; i < m; ++i) {
      const double c = w * t.auPerDelta * t.g[i];
      thrustRow(i) += c * t.dirN[2];
      thrustRow(m + i) += c * t.dirT[2];
      torqueRow(i) += -r * c * t.dirN[1];
      torqueRow(m + i) += -r * c * t.dirT[1];
    }
  });
  chisel = shared ? EdgeIntegral{}
                  : IntegrateEdges(tool, basisModel, s.feedMmPerRev, s.speedRpm, s.depthMm,
                                   EdgeKind::Chisel, kPanels);
}

void CheckSample(const CalibrationSample& s, size_t i) {
  const std::string where = "calibration sample " + std::to_string(i + 1) + ": ";
  if (!(s.feedMmPerRev > 0) || !std::isfinite(s.feedMmPerRev))
    throw std::invalid_argument(where + "feed must be > 0 mm/rev");
  if (!(s.speedRpm > 0) || !std::isfinite(s.speedRpm))
    throw std::invalid_argument(where + "speed must be > 0 rpm");
  if (!(s.depthMm >= 0))
    throw std::invalid_argument(where + "depth must be >= 0 mm");
  if (!std::isfinite(s.thrustN))
    throw std::invalid_argument(where + "thrust must be a number");
  if (!(s.material > 0) || !std::isfinite(s.material))
    throw std::invalid_argument(where + "material (density scale) must be > 0");
}
} // namespace

std::string ConditionOf(const CalibrationSample& s) {
  if (!s.condition.empty())
    return s.condition;
  char buf[64];
  std::snprintf(buf, sizeof buf, "f=%g n=%g", s.feedMmPerRev, s.speedRpm);
  return buf;
}

CalibrationFit CalibrateFit(const ToolModel& tool, Method method,
                            const std::vector<BasisTerm>& basis, const ForceModel& chiselFrom,
                            const std::vector<CalibrationSample>& samples,
                            const CalibrationOptions& options) {
  const Eigen::Index m = Eigen::Index(basis.size());
  if (m == 0)
    throw std::invalid_argument("calibration: empty basis");
  if (Eigen::Index(samples.size()) < m)
    throw std::invalid_argument("calibration: fewer samples than coefficients");
  for (size_t i = 0; i < samples.size(); ++i)
    CheckSample(samples[i], i);
  const bool shared = options.chiselSharesLipCoefficients;
  const ForceModel basisModel = ZeroLips(method, basis, chiselFrom, shared);
  const Eigen::Index n = Eigen::Index(samples.size());

  // Bone labels: index 0 is the reference.
  std::vector<std::string> bones;
  std::vector<int> boneOf(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    auto it = std::find(bones.begin(), bones.end(), samples[i].bone);
    boneOf[i] = int(it - bones.begin());
    if (it == bones.end())
      bones.push_back(samples[i].bone);
  }

  // Design rows at material 1 and factor 1, computed once.
  Eigen::MatrixXd rowsT(n, 2 * m), rowsM(n, 2 * m);
  Eigen::VectorXd chiselT(n), chiselM(n), yT(n), yM(n);
  std::vector<bool> hasTorque(samples.size());
  double sT = 0, sM = 0;
  int nM = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const CalibrationSample& s = samples[size_t(i)];
    EdgeIntegral chisel;
    Eigen::RowVectorXd rT(2 * m), rM(2 * m);
    DesignRows(ToolOf(tool, s), basisModel, s, shared, rT, rM, chisel);
    rowsT.row(i) = s.material * rT;
    rowsM.row(i) = s.material * rM;
    chiselT(i) = s.material * chisel.thrustN;
    chiselM(i) = s.material * chisel.torqueNmm;
    yT(i) = s.thrustN;
    hasTorque[size_t(i)] = std::isfinite(s.torqueNmm);
    yM(i) = hasTorque[size_t(i)] ? s.torqueNmm : 0.0;
    sT += s.thrustN * s.thrustN;
    if (hasTorque[size_t(i)]) {
      sM += s.torqueNmm * s.torqueNmm;
      ++nM;
    }
  }
  const double wT = 1.0 / std::max(std::sqrt(sT / double(n)), 1e-12);
  const double wM = nM ? 1.0 / std::max(std::sqrt(sM / nM), 1e-12) : 0.0;

  // With a fitted chisel scale the chisel is one more column instead of a known offset.
  const bool fitChisel = options.fitChiselScale && !shared;
  const Eigen::Index cols = 2 * m + (fitChisel ? 1 : 0);
  Eigen::MatrixXd fullT(n, cols), fullM(n, cols);
  fullT.leftCols(2 * m) = rowsT;
  fullM.leftCols(2 * m) = rowsM;
  if (fitChisel) {
    fullT.col(2 * m) = chiselT;
    fullM.col(2 * m) = chiselM;
  }
  const Eigen::VectorXd offT = fitChisel ? Eigen::VectorXd::Zero(n) : chiselT;
  const Eigen::VectorXd offM = fitChisel ? Eigen::VectorXd::Zero(n) : chiselM;

  std::vector<double> factor(bones.size(), 1.0);
  const bool fitFactors = options.fitBoneFactors && bones.size() > 1;
  Eigen::VectorXd x;
  int iter = 0;
  for (;; ++iter) {
    const Eigen::Index rows = n + nM;
    Eigen::MatrixXd A(rows, cols);
    Eigen::VectorXd y(rows);
    Eigen::Index k = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double f = factor[size_t(boneOf[size_t(i)])];
      A.row(k) = wT * f * fullT.row(i);
      y(k++) = wT * (yT(i) - f * offT(i));
      if (hasTorque[size_t(i)]) {
        A.row(k) = wM * f * fullM.row(i);
        y(k++) = wM * (yM(i) - f * offM(i));
      }
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
    if (qr.rank() < cols)
      throw std::invalid_argument(
          "calibration: the samples do not determine all coefficients (rank " +
          std::to_string(qr.rank()) + " < " + std::to_string(cols) +
          "): add conditions that vary what the basis terms depend on, or drop a term");
    x = qr.solve(y);
    if (!fitFactors || iter >= options.maxIterations)
      break;
    // Closed-form factor per bone (the reference stays 1).
    const Eigen::VectorXd pT = fullT * x + offT, pM = fullM * x + offM;
    std::vector<double> num(bones.size(), 0.0), den(bones.size(), 0.0);
    for (Eigen::Index i = 0; i < n; ++i) {
      const size_t b = size_t(boneOf[size_t(i)]);
      num[b] += wT * wT * pT(i) * yT(i);
      den[b] += wT * wT * pT(i) * pT(i);
      if (hasTorque[size_t(i)]) {
        num[b] += wM * wM * pM(i) * yM(i);
        den[b] += wM * wM * pM(i) * pM(i);
      }
    }
    double change = 0;
    for (size_t b = 1; b < bones.size(); ++b) {
      if (!(den[b] > 0))
        throw std::invalid_argument("calibration: bone '" + bones[b] +
                                    "' has no predicted force to scale");
      const double f = num[b] / den[b];
      change = std::max(change, std::abs(f - factor[b]) / std::max(std::abs(f), 1e-300));
      factor[b] = f;
    }
    if (change < 1e-13)
      break;
  }

  Coefficients c{basis, {}, {}};
  for (Eigen::Index i = 0; i < m; ++i) {
    c.kc.push_back(x(i));
    c.kt.push_back(x(m + i));
  }
  CalibrationFit fit;
  Coefficients chisel = chiselFrom.ChiselCoefficients();
  if (fitChisel) {
    fit.chiselScale = x(2 * m);
    for (double& v : chisel.kc)
      v *= fit.chiselScale;
    for (double& v : chisel.kt)
      v *= fit.chiselScale;
  }
  fit.model = ForceModel(method, c, shared ? c : chisel);
  CoefficientProvenance prov;
  prov.name = "fitted";
  prov.calibrated = true;
  prov.source = "least-squares fit (bmCalibration)";
  fit.model.SetProvenance(prov);
  fit.referenceBone = bones.empty() ? "" : bones[0];
  for (size_t b = 0; b < bones.size(); ++b)
    fit.boneFactor[bones[b]] = factor[b];
  fit.iterations = iter + 1;
  const Eigen::VectorXd pT = fullT * x + offT, pM = fullM * x + offM;
  double eT = 0, eM = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double f = factor[size_t(boneOf[size_t(i)])];
    eT += (f * pT(i) - yT(i)) * (f * pT(i) - yT(i));
    if (hasTorque[size_t(i)])
      eM += (f * pM(i) - yM(i)) * (f * pM(i) - yM(i));
  }
  fit.rmsThrustErrorN = std::sqrt(eT / double(n));
  fit.rmsTorqueErrorNmm = nM ? std::sqrt(eM / nM) : 0.0;
  return fit;
}

ForceModel Calibrate(const ToolModel& tool, Method method, const std::vector<BasisTerm>& basis,
                     const ForceModel& chiselFrom, const std::vector<CalibrationSample>& samples) {
  return CalibrateFit(tool, method, basis, chiselFrom, samples, {}).model;
}

EdgeIntegral Predict(const ToolModel& tool, const ForceModel& model, const CalibrationSample& s,
                     double boneFactor) {
  EdgeIntegral p = IntegrateEdges(ToolOf(tool, s), model, s.feedMmPerRev, s.speedRpm, s.depthMm,
                                  EdgeKind::None, kPanels);
  p.thrustN *= s.material * boneFactor;
  p.torqueNmm *= s.material * boneFactor;
  return p;
}

std::vector<FoldResult> CrossValidate(const ToolModel& tool, Method method,
                                      const std::vector<BasisTerm>& basis,
                                      const ForceModel& chiselFrom,
                                      const std::vector<CalibrationSample>& samples) {
  return CrossValidate(tool, method, basis, chiselFrom, samples, {});
}

std::vector<FoldResult> CrossValidate(const ToolModel& tool, Method method,
                                      const std::vector<BasisTerm>& basis,
                                      const ForceModel& chiselFrom,
                                      const std::vector<CalibrationSample>& samples,
                                      const CalibrationOptions& options) {
  std::vector<std::string> conditions;
  for (const auto& s : samples)
    if (std::find(conditions.begin(), conditions.end(), ConditionOf(s)) == conditions.end())
      conditions.push_back(ConditionOf(s));
  if (conditions.size() < 2)
    throw std::invalid_argument("cross-validation needs >= 2 conditions");
  if (!options.fitBoneFactors) // the historical order: sorted by (feed, speed)
    std::sort(conditions.begin(), conditions.end(), [&](const auto& a, const auto& b) {
      auto key = [&](const std::string& c) {
        for (const auto& s : samples)
          if (ConditionOf(s) == c)
            return std::pair{s.feedMmPerRev, s.speedRpm};
        return std::pair{0.0, 0.0};
      };
      return key(a) < key(b) || (key(a) == key(b) && a < b);
    });
  std::vector<FoldResult> folds;
  for (const auto& cond : conditions) {
    std::vector<CalibrationSample> train;
    std::vector<size_t> test;
    for (size_t i = 0; i < samples.size(); ++i) {
      if (ConditionOf(samples[i]) == cond)
        test.push_back(i);
      else
        train.push_back(samples[i]);
    }
    FoldResult f;
    f.condition = cond;
    f.feedMmPerRev = samples[test[0]].feedMmPerRev;
    f.speedRpm = samples[test[0]].speedRpm;
    const CalibrationFit fit = CalibrateFit(tool, method, basis, chiselFrom, train, options);
    f.model = fit.model;
    const auto it = fit.boneFactor.find(samples[test[0]].bone);
    f.boneFactorKnown = it != fit.boneFactor.end();
    f.boneFactor = f.boneFactorKnown ? it->second : 1.0;
    double eT = 0, eM = 0, minM = 1e300, sumM = 0;
    int nM = 0;
    for (size_t i : test) {
      const CalibrationSample& s = samples[i];
      EdgeIntegral p = Predict(tool, f.model, s, f.boneFactor);
      f.predictions.push_back(p);
      f.sampleIndex.push_back(i);
      eT += (p.thrustN - s.thrustN) * (p.thrustN - s.thrustN);
      if (std::isfinite(s.torqueNmm)) {
        eM += (p.torqueNmm - s.torqueNmm) * (p.torqueNmm - s.torqueNmm);
        ++nM;
      }
      if (s.depthMm > 0)
        minM = std::min(minM, p.torqueNmm);
      sumM += p.torqueNmm;
    }
    f.rmsThrustErrorN = std::sqrt(eT / double(test.size()));
    f.rmsTorqueErrorNmm = nM ? std::sqrt(eM / nM) : 0.0;
    f.minPredictedTorqueNmm = minM;
    f.meanPredictedTorqueNmm = sumM / double(test.size());
    folds.push_back(std::move(f));
  }
  return folds;
}

std::vector<CalibrationSample> EntryCurves(const ToolModel& tool, const ForceModel& model,
                                           const std::vector<std::pair<double, double>>& conditions,
                                           int steps,
                                           const std::function<void(CalibrationSample&)>& perturb) {
  const double full = EdgeHeight(tool, tool.EdgeRange(EdgeKind::Lip)[1]);
  std::vector<CalibrationSample> out;
  for (const auto& [f, n] : conditions)
    for (int i = 1; i <= steps; ++i) {
      CalibrationSample s;
      s.feedMmPerRev = f;
      s.speedRpm = n;
      s.depthMm = full * i / steps;
      EdgeIntegral p = Predict(tool, model, s);
      s.thrustN = p.thrustN;
      s.torqueNmm = p.torqueNmm;
      if (perturb)
        perturb(s);
      out.push_back(s);
    }
  return out;
}

std::vector<std::pair<double, double>> LeeConditions() {
  return {{0.01, 500}, {0.02, 500}, {0.01, 3000}, {0.02, 3000}};
}

} // namespace bm
