// bmCalibration.h - cutting coefficients from thrust/torque-vs-depth data (Docs/Model.md
// section 3).
//
// With k_c = sum a_i g_i and k_t = sum b_i g_i, the thrust and torque at a known drilling depth
// (entry phase: the engaged edge elements are known from the depth) are linear in (a, b): one
// weighted linear least-squares solve (Eigen) fits the lips. The chisel edge is modelled alike in
// both methods and is taken as known; its contribution is subtracted first. Thrust rows are scaled
// by 1 / RMS(thrust) and torque rows by 1 / RMS(torque) so both count equally.
//
// Units: feed mm/rev, speed rpm, depth mm (from the foremost cutting point), thrust N, torque N mm.
#pragma once

#include <functional>
#include <vector>

#include "bmForceModel.h"

namespace bm {

struct CalibrationSample {
  double feedMmPerRev = 0;
  double speedRpm = 0;
  double depthMm = 0;
  double thrustN = 0;
  double torqueNmm = 0;
};

/// Fit the lip coefficients of `method` over `basis` to samples; the chisel model of `chiselFrom`
/// is kept. Throws std::invalid_argument when the samples cannot determine the coefficients.
ForceModel Calibrate(const ToolModel& tool, Method method, const std::vector<BasisTerm>& basis,
                     const ForceModel& chiselFrom, const std::vector<CalibrationSample>& samples);

/// The model's predicted thrust and torque at a sample's feed, speed and depth.
EdgeIntegral Predict(const ToolModel& tool, const ForceModel& model, const CalibrationSample& s);

/// One fold of leave-one-condition-out cross-validation.
struct FoldResult {
  double feedMmPerRev = 0, speedRpm = 0; ///< the held-out condition
  double rmsThrustErrorN = 0;            ///< RMS error of predicted thrust on the held-out samples
  double rmsTorqueErrorNmm = 0;          ///< RMS error of predicted torque
  double minPredictedTorqueNmm = 0;      ///< smallest predicted torque on the held-out samples
  double meanPredictedTorqueNmm = 0;
  ForceModel model; ///< the model fitted on the other conditions
};

/// Leave-one-condition-out: for each distinct (feed, speed), fit on the others, predict it.
std::vector<FoldResult> CrossValidate(const ToolModel& tool, Method method,
                                      const std::vector<BasisTerm>& basis,
                                      const ForceModel& chiselFrom,
                                      const std::vector<CalibrationSample>& samples);

/// Entry-phase curves from a known model: for each condition, `steps` depths evenly from 0 to
/// full engagement (the tip's cutting-edge height). `perturb`, if given, maps (sample) -> sample
/// to add a documented trend or noise to the synthetic measurements.
std::vector<CalibrationSample>
EntryCurves(const ToolModel& tool, const ForceModel& model,
            const std::vector<std::pair<double, double>>& conditions, int steps,
            const std::function<void(CalibrationSample&)>& perturb = {});

/// The four drilling conditions of Lee et al. 2012: f in {0.01, 0.02} mm/rev x n in {500, 3000}
/// rpm.
std::vector<std::pair<double, double>> LeeConditions();

} // namespace bm
