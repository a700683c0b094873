// bmCalibration.h - cutting coefficients from thrust/torque-vs-depth data (Docs/Model.md
// section 3).
//
// With k_c = sum a_i g_i and k_t = sum b_i g_i, the thrust and torque at a known drilling depth
// (entry phase: the engaged edge elements are known from the depth) are linear in (a, b): one
// weighted linear least-squares solve (Eigen) fits the lips. The chisel edge is modelled alike in
// both methods and is taken as known; its contribution is subtracted first (or, optionally, one
// scale of its coefficients is fitted with the lips, or it shares the lips' coefficients). Thrust
// rows are scaled by 1 / RMS(thrust) and torque rows by 1 / RMS(torque) so both count equally.
//
// Samples may come from different tools (each sample names its own), bones and densities: the
// predicted force of a sample is material x boneFactor x (lips + chisel). Bone factors are known
// (1) or, with CalibrationOptions::fitBoneFactors, fitted per bone label relative to the first
// bone in the samples, alternating a linear solve of the coefficients with a closed-form solve of
// the factors (variable projection by alternation; the factor of the first bone stays 1).
//
// Units: feed mm/rev, speed rpm, depth mm (from the foremost cutting point), thrust N, torque N mm.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bmForceModel.h"

namespace bm {

struct CalibrationSample {
  double feedMmPerRev = 0;
  double speedRpm = 0;
  double depthMm = 0; ///< 1e300 (or more than the tip's length) = fully engaged, steady state
  double thrustN = 0;
  double torqueNmm = 0; ///< NaN = not measured (the sample then only constrains the thrust)
  /// The tool of this sample; null = the tool passed to Calibrate / Predict.
  std::shared_ptr<const ToolModel> tool;
  double material = 1.0; ///< known density scale of k_c and k_t (the engine's voxel material)
  std::string bone;      ///< bone or specimen label (bone factors are fitted per label)
  std::string condition; ///< cross-validation group; empty = "f=<feed> n=<speed>"
};

struct CalibrationOptions {
  /// Fit one material factor per bone label (the first label in the samples stays 1).
  bool fitBoneFactors = false;
  /// Fit one scale of the chisel's coefficients (default: the chisel of chiselFrom as it is).
  bool fitChiselScale = false;
  /// The chisel takes the lips' basis and coefficients (one material law for every edge), fitted
  /// with them; chiselFrom's chisel is then unused. Overrides fitChiselScale.
  bool chiselSharesLipCoefficients = false;
  int maxIterations = 500; ///< alternations of the bone-factor fit
};

struct CalibrationFit {
  ForceModel model;
  std::string referenceBone;                ///< the bone whose factor is 1
  std::map<std::string, double> boneFactor; ///< per bone label (1 when not fitted)
  double rmsThrustErrorN = 0;               ///< in-sample RMS error
  double rmsTorqueErrorNmm = 0;             ///< in-sample RMS error over samples with torque
  double chiselScale = 1;                   ///< fitted (fitChiselScale) or 1
  int iterations = 0;
};

/// Fit the lip coefficients of `method` over `basis` to samples; the chisel model of `chiselFrom`
/// is kept. Throws std::invalid_argument when the samples cannot determine the coefficients.
ForceModel Calibrate(const ToolModel& tool, Method method, const std::vector<BasisTerm>& basis,
                     const ForceModel& chiselFrom, const std::vector<CalibrationSample>& samples);
/// The same with options: bone factors, and the fit's figures.
CalibrationFit CalibrateFit(const ToolModel& tool, Method method,
                            const std::vector<BasisTerm>& basis, const ForceModel& chiselFrom,
                            const std::vector<CalibrationSample>& samples,
                            const CalibrationOptions& options);

/// The model's predicted thrust and torque at a sample's feed, speed and depth, on the sample's
/// tool (or `tool`), times the sample's material and `boneFactor`.
EdgeIntegral Predict(const ToolModel& tool, const ForceModel& model, const CalibrationSample& s,
                     double boneFactor = 1.0);

/// A sample's cross-validation group: its condition label, or "f=<feed> n=<speed>".
std::string ConditionOf(const CalibrationSample& s);

/// One fold of leave-one-condition-out cross-validation.
struct FoldResult {
  std::string condition;                 ///< the held-out group (ConditionOf)
  double feedMmPerRev = 0, speedRpm = 0; ///< the held-out condition's first sample
  double rmsThrustErrorN = 0;            ///< RMS error of predicted thrust on the held-out samples
  double rmsTorqueErrorNmm = 0;          ///< RMS error of predicted torque
  double minPredictedTorqueNmm = 0;      ///< smallest predicted torque on the held-out samples
  double meanPredictedTorqueNmm = 0;
  ForceModel model;                      ///< the model fitted on the other conditions
  double boneFactor = 1;                 ///< the held-out bone's factor from the training fit
  bool boneFactorKnown = true;           ///< false: the bone had no other condition (factor 1 used)
  std::vector<EdgeIntegral> predictions; ///< per held-out sample, in input order
  std::vector<size_t> sampleIndex;       ///< those samples' indices in the input
};

/// Leave-one-condition-out: for each distinct condition (ConditionOf), fit on the others,
/// predict it.
std::vector<FoldResult> CrossValidate(const ToolModel& tool, Method method,
                                      const std::vector<BasisTerm>& basis,
                                      const ForceModel& chiselFrom,
                                      const std::vector<CalibrationSample>& samples);
std::vector<FoldResult> CrossValidate(const ToolModel& tool, Method method,
                                      const std::vector<BasisTerm>& basis,
                                      const ForceModel& chiselFrom,
                                      const std::vector<CalibrationSample>& samples,
                                      const CalibrationOptions& options);

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
