#include "bmCalibration.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <Eigen/Dense>

#include "bmEdgeQuadrature.h"

namespace bm {

namespace {
constexpr int kPanels = 400;

ForceModel ZeroLips(Method method, const std::vector<BasisTerm>& basis,
                    const ForceModel& chiselFrom) {
  Coefficients z{basis, std::vector<double>(basis.size(), 0.0),
                 std::vector<double>(basis.size(), 0.0)};
  return ForceModel(method, z, chiselFrom.ChiselCoefficients());
}

// Rows of d(thrust)/d(a,b) and d(torque)/d(a,b) for one sample, plus the chisel's share.
void DesignRows(const ToolModel& tool, const ForceModel& basisModel, const CalibrationSample& s,
                Eigen::RowVectorXd& thrustRow, Eigen::RowVectorXd& torqueRow,
                EdgeIntegral& chisel) {
  const Eigen::Index m = thrustRow.size() / 2;
  thrustRow.setZero();
  torqueRow.setZero();
  ForEachEdgeNode(tool, s.depthMm, EdgeKind::Lip, kPanels, [&](EdgeKind kind, double r, double w) {
    ElementTerms t = basisModel.Terms(tool, kind, r, s.feedMmPerRev, s.speedRpm);
    for (Eigen::Index i = 0; i < m; ++i) {
      const double c = w * t.auPerDelta * t.g[i];
      thrustRow(i) += c * t.dirN[2];
      thrustRow(m + i) += c * t.dirT[2];
      torqueRow(i) += -r * c * t.dirN[1];
      torqueRow(m + i) += -r * c * t.dirT[1];
    }
  });
  chisel = IntegrateEdges(tool, basisModel, s.feedMmPerRev, s.speedRpm, s.depthMm, EdgeKind::Chisel,
                          kPanels);
}
} // namespace

ForceModel Calibrate(const ToolModel& tool, Method method, const std::vector<BasisTerm>& basis,
                     const ForceModel& chiselFrom, const std::vector<CalibrationSample>& samples) {
  const Eigen::Index m = Eigen::Index(basis.size());
  if (m == 0)
    throw std::invalid_argument("calibration: empty basis");
  if (Eigen::Index(samples.size()) < m)
    throw std::invalid_argument("calibration: fewer samples than coefficients");
  const ForceModel basisModel = ZeroLips(method, basis, chiselFrom);
  const Eigen::Index n = Eigen::Index(samples.size());
  Eigen::MatrixXd A(2 * n, 2 * m);
  Eigen::VectorXd y(2 * n);
  double sT = 0, sM = 0;
  for (const auto& s : samples) {
    sT += s.thrustN * s.thrustN;
    sM += s.torqueNmm * s.torqueNmm;
  }
  const double wT = 1.0 / std::max(std::sqrt(sT / n), 1e-12),
               wM = 1.0 / std::max(std::sqrt(sM / n), 1e-12);
  for (Eigen::Index i = 0; i < n; ++i) {
    EdgeIntegral chisel;
    Eigen::RowVectorXd rT(2 * m), rM(2 * m);
    DesignRows(tool, basisModel, samples[i], rT, rM, chisel);
    A.row(2 * i) = wT * rT;
    A.row(2 * i + 1) = wM * rM;
    y(2 * i) = wT * (samples[i].thrustN - chisel.thrustN);
    y(2 * i + 1) = wM * (samples[i].torqueNmm - chisel.torqueNmm);
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 2 * m)
    throw std::invalid_argument(
        "calibration: the samples do not determine all coefficients (rank " +
        std::to_string(qr.rank()) + " < " + std::to_string(2 * m) + ")");
  Eigen::VectorXd x = qr.solve(y);
  Coefficients c{basis, {}, {}};
  for (Eigen::Index i = 0; i < m; ++i) {
    c.kc.push_back(x(i));
    c.kt.push_back(x(m + i));
  }
  return ForceModel(method, c, chiselFrom.ChiselCoefficients());
}

EdgeIntegral Predict(const ToolModel& tool, const ForceModel& model, const CalibrationSample& s) {
  return IntegrateEdges(tool, model, s.feedMmPerRev, s.speedRpm, s.depthMm, EdgeKind::None,
                        kPanels);
}

std::vector<FoldResult> CrossValidate(const ToolModel& tool, Method method,
                                      const std::vector<BasisTerm>& basis,
                                      const ForceModel& chiselFrom,
                                      const std::vector<CalibrationSample>& samples) {
  std::map<std::pair<double, double>, int> conditions;
  for (const auto& s : samples)
    conditions[{s.feedMmPerRev, s.speedRpm}]++;
  if (conditions.size() < 2)
    throw std::invalid_argument("cross-validation needs >= 2 conditions");
  std::vector<FoldResult> folds;
  for (const auto& [cond, count] : conditions) {
    std::vector<CalibrationSample> train, test;
    for (const auto& s : samples)
      (s.feedMmPerRev == cond.first && s.speedRpm == cond.second ? test : train).push_back(s);
    FoldResult f;
    f.feedMmPerRev = cond.first;
    f.speedRpm = cond.second;
    f.model = Calibrate(tool, method, basis, chiselFrom, train);
    double eT = 0, eM = 0, minM = 1e300, sumM = 0;
    for (const auto& s : test) {
      EdgeIntegral p = Predict(tool, f.model, s);
      eT += (p.thrustN - s.thrustN) * (p.thrustN - s.thrustN);
      eM += (p.torqueNmm - s.torqueNmm) * (p.torqueNmm - s.torqueNmm);
      if (s.depthMm > 0)
        minM = std::min(minM, p.torqueNmm);
      sumM += p.torqueNmm;
    }
    f.rmsThrustErrorN = std::sqrt(eT / test.size());
    f.rmsTorqueErrorNmm = std::sqrt(eM / test.size());
    f.minPredictedTorqueNmm = minM;
    f.meanPredictedTorqueNmm = sumM / test.size();
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
