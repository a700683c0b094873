// bmsim calibrate - fit cutting coefficients to measured thrust and torque (bmCalibration.h),
// cross-validate ours and Zheng et al.'s model leave-one-condition-out, chart predicted against
// measured, and write a coefficient file that scenes name ("force_model": {"coefficients": ...}).
#include "bmsimArgs.h"
#include "bmsimCommand.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bmAtomicFile.h"
#include "bmCalibration.h"
#include "bmCalibrationData.h"
#include "bmSvgScatter.h"
#include "bmToolModel.h"

namespace {
std::vector<bm::BasisTerm> ParseBasis(const std::string& list, const char* option) {
  std::vector<bm::BasisTerm> out;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      out.push_back(bm::BasisTermFromString(item));
    } catch (const std::invalid_argument& e) {
      throw bm::cli::UsageError(std::string(option) + ": " + e.what());
    }
  }
  if (out.empty())
    throw bm::cli::UsageError(std::string(option) + " is empty");
  return out;
}

std::string Num(double v, const char* fmt = "%.6g") {
  char buf[48];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

std::string Quote(const std::string& s) {
  std::string q = "\"";
  for (char c : s)
    q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

struct MethodRun {
  bm::Method method;
  std::vector<bm::BasisTerm> basis;
  bm::CalibrationFit fit;
  std::vector<bm::FoldResult> folds;
  std::vector<bm::EdgeIntegral> fitted; ///< in-sample prediction per sample
  std::vector<bm::EdgeIntegral> held;   ///< cross-validated prediction per sample (NaN: none)
  std::string cvError;                  ///< why cross-validation was not possible, if it was not
};

} // namespace

namespace bm::cli {

static void CalibrateOptions(ParsedArgs& p) {
  p.Words("DATA.csv", "measured thrust/torque per condition (columns: "
                      "Logic/Core/bmCalibrationData.h)")
      .Value("basis", "LIST",
             "our (Lazar) model's basis, comma-separated (default 1000/n_per_rpm); terms: 1, "
             "1-sin(gamma_n), chip_thickness_mm, V_m_per_min, 1/V_min_per_m, 1000/n_per_rpm")
      .Value("zheng-basis", "LIST",
             "Zheng et al.'s lip basis (default 1,1/V_min_per_m); Zheng's chisel is the built-in "
             "one (k_c 1000 N/mm^2, k_f 0.5), as in the paper")
      .Choice("bone-factors", {"auto", "fit", "none"},
              "fit: one material factor per bone label, the first bone's = 1 (default when the "
              "data name several bones); none: all 1")
      .Choice("chisel", {"shared", "scaled", "fixed"},
              "our model's chisel edge: shared (default): the lips' basis and coefficients, "
              "fitted with them; scaled: the built-in chisel times a fitted scale; fixed: the "
              "built-in chisel")
      .Value("bones", "LIST", "fit only rows of these bone labels (comma-separated)")
      .Value("name", "NAME", "the coefficient set's name (default: the data file's name)")
      .Value("o,out", "DIR",
             "write coefficients.json (ours), zheng.json, folds.csv, predictions.csv and "
             "chart.svg there (created; files replaced)");
}

static int CalibrateCommand(const ParsedArgs& p) {
  if (p.Positional().size() != 1)
    throw UsageError("name one data file (DATA.csv)");
  const std::filesystem::path data = p.Positional()[0];
  const auto ours = ParseBasis(p.Get("basis", "1000/n_per_rpm"), "--basis");
  const auto zheng = ParseBasis(p.Get("zheng-basis", "1,1/V_min_per_m"), "--zheng-basis");
  const std::string boneMode = p.Get("bone-factors", "auto");
  if (boneMode != "auto" && boneMode != "fit" && boneMode != "none")
    throw UsageError("--bone-factors must be fit or none");
  const std::string chiselMode = p.Get("chisel", "shared");
  if (chiselMode != "shared" && chiselMode != "scaled" && chiselMode != "fixed")
    throw UsageError("--chisel must be shared, scaled or fixed");
  std::vector<std::string> onlyBones;
  if (const auto list = p.Get("bones")) {
    std::stringstream ss(*list);
    std::string item;
    while (std::getline(ss, item, ','))
      onlyBones.push_back(item);
  }
  const std::string name = p.Get("name", data.stem().string());
  const std::string outDir = p.Get("out", "");

  auto records = ReadCalibrationCsv(data);
  if (!onlyBones.empty()) {
    for (const auto& b : onlyBones)
      if (std::none_of(records.begin(), records.end(),
                       [&](const CalibrationRecord& r) { return r.sample.bone == b; }))
        throw UsageError("--bones: no row of bone '" + b + "' in " + data.string());
    std::erase_if(records, [&](const CalibrationRecord& r) {
      return std::find(onlyBones.begin(), onlyBones.end(), r.sample.bone) == onlyBones.end();
    });
  }
  const auto samples = SamplesOf(records);
  std::vector<std::string> bones, sources;
  for (const auto& r : records) {
    if (std::find(bones.begin(), bones.end(), r.sample.bone) == bones.end())
      bones.push_back(r.sample.bone);
    if (!r.source.empty() && std::find(sources.begin(), sources.end(), r.source) == sources.end())
      sources.push_back(r.source);
  }
  CalibrationOptions ourOptions, zhengOptions;
  ourOptions.fitBoneFactors = boneMode == "fit" || (boneMode == "auto" && bones.size() > 1);
  ourOptions.fitChiselScale = chiselMode == "scaled";
  ourOptions.chiselSharesLipCoefficients = chiselMode == "shared";
  zhengOptions.fitBoneFactors = ourOptions.fitBoneFactors;
  const TwistDrill referenceDrill; // samples all carry their own tool; this is never used

  std::vector<MethodRun> runs;
  for (auto [method, basis] : {std::pair{Method::Lazar, ours}, std::pair{Method::Zheng, zheng}}) {
    MethodRun run{method, basis, {}, {}, {}, {}, {}};
    const CalibrationOptions& options = method == Method::Lazar ? ourOptions : zhengOptions;
    // The built-in chisel (k_c 1000 N/mm^2, k_f 0.5), independent of any fitted set.
    const Coefficients builtIn{{BasisTerm::One}, {1000.0}, {500.0}};
    const ForceModel chisel(method, builtIn, builtIn);
    try {
      run.fit = CalibrateFit(referenceDrill, method, basis, chisel, samples, options);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(ToString(method) + " fit: " + e.what());
    }
    for (const auto& s : samples)
      run.fitted.push_back(
          Predict(referenceDrill, run.fit.model, s, run.fit.boneFactor.at(s.bone)));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    run.held.assign(samples.size(), EdgeIntegral{nan, nan});
    try {
      run.folds = CrossValidate(referenceDrill, method, basis, chisel, samples, options);
    } catch (const std::invalid_argument& e) {
      run.cvError = e.what(); // reported; the fit itself stands
    }
    for (const auto& f : run.folds)
      for (size_t k = 0; k < f.sampleIndex.size(); ++k)
        run.held[f.sampleIndex[k]] = f.predictions[k];
    runs.push_back(std::move(run));
  }

  size_t conditions = 0;
  {
    std::vector<std::string> seen;
    for (const auto& s : samples)
      if (std::find(seen.begin(), seen.end(), ConditionOf(s)) == seen.end())
        seen.push_back(ConditionOf(s));
    conditions = seen.size();
  }
  std::cout << "data: " << data.string() << " (" << records.size() << " rows, " << bones.size()
            << " bones, " << conditions << " conditions); our chisel: " << chiselMode << "\n";
  for (const auto& run : runs) {
    const auto& c = run.fit.model.LipCoefficients();
    std::cout << "\n"
              << ToString(run.method) << " fit (" << run.fit.iterations
              << " alternations): RMS error thrust " << Num(run.fit.rmsThrustErrorN, "%.3f")
              << " N, torque " << Num(run.fit.rmsTorqueErrorNmm, "%.3f") << " N mm\n";
    for (size_t i = 0; i < c.basis.size(); ++i)
      std::cout << "  " << ToString(c.basis[i]) << ": k_c " << Num(c.kc[i]) << ", k_t "
                << Num(c.kt[i]) << " N/mm^2\n";
    std::cout << "  chisel scale " << Num(run.fit.chiselScale, "%.4f") << "; bone factors:";
    for (const auto& b : bones)
      std::cout << " " << (b.empty() ? "(none)" : b) << " "
                << Num(run.fit.boneFactor.at(b), "%.4f");
    std::cout << "\n  leave-one-condition-out:";
    if (!run.cvError.empty()) {
      std::cout << " not possible: " << run.cvError << "\n";
      continue;
    }
    std::cout << "\n";
    int negative = 0;
    double sumT = 0, sumM = 0;
    for (const auto& f : run.folds) {
      std::cout << "    " << f.condition << ": RMS thrust " << Num(f.rmsThrustErrorN, "%.3f")
                << " N, torque " << Num(f.rmsTorqueErrorNmm, "%.3f") << " N mm, min torque "
                << Num(f.minPredictedTorqueNmm, "%.3f") << " N mm"
                << (f.boneFactorKnown ? "" : " (bone factor unknown: 1 used)") << "\n";
      negative += f.minPredictedTorqueNmm < 0;
      sumT += f.rmsThrustErrorN;
      sumM += f.rmsTorqueErrorNmm;
    }
    std::cout << "    mean fold RMS thrust " << Num(sumT / run.folds.size(), "%.3f")
              << " N, torque " << Num(sumM / run.folds.size(), "%.3f")
              << " N mm; folds with negative torque: " << negative << " of " << run.folds.size()
              << "\n";
  }
  // Torque-to-thrust ratio and speed effect of our fit, per row's tool at the row's feed.
  std::cout << "\nour fit per row (reference bone scale x row's bone factor):\n";
  for (size_t i = 0; i < records.size(); ++i) {
    const auto& s = samples[i];
    const EdgeIntegral& q = runs[0].fitted[i];
    std::cout << "  line " << records[i].line << " " << s.condition << ": thrust "
              << Num(q.thrustN, "%.2f") << " N (measured " << Num(s.thrustN, "%.2f") << "), torque "
              << Num(q.torqueNmm, "%.2f") << " N mm (measured "
              << (std::isfinite(s.torqueNmm) ? Num(s.torqueNmm, "%.2f") : std::string("-"))
              << "), torque/thrust " << Num(q.torqueNmm / q.thrustN, "%.3f") << " mm\n";
  }

  // The speed effect of each fit for the first row's tool, feed and bone.
  std::cout << "\nspeed effect at the first row's tool and feed (" << samples[0].condition
            << "):\n";
  for (const auto& run : runs) {
    std::cout << "  " << ToString(run.method) << ":";
    for (double n : {500.0, 1000.0, 1500.0, 2000.0, 3000.0}) {
      CalibrationSample s = samples[0];
      s.speedRpm = n;
      s.depthMm = 1e300;
      const EdgeIntegral q =
          Predict(referenceDrill, run.fit.model, s, run.fit.boneFactor.at(s.bone));
      std::cout << "  " << n << " rpm " << Num(q.thrustN, "%.2f") << " N / "
                << Num(q.torqueNmm, "%.2f") << " N mm";
    }
    std::cout << "\n";
  }

  if (outDir.empty())
    return 0;

  // Coefficient files: the fitted sets, named, calibrated, with their source and figures.
  auto modelJson = [&](const MethodRun& run, const std::string& setName) {
    ForceModel m = run.fit.model;
    CoefficientProvenance prov;
    prov.name = setName;
    prov.calibrated = true;
    std::string src = "bmsim calibrate " + data.filename().string();
    if (!onlyBones.empty()) {
      src += " --bones \"";
      for (size_t i = 0; i < onlyBones.size(); ++i)
        src += (i ? "," : "") + onlyBones[i];
      src += "\"";
    }
    src += " (assumptions in the rows' notes): ";
    for (size_t i = 0; i < sources.size(); ++i)
      src += (i ? "; " : "") + sources[i];
    prov.source = src;
    m.SetProvenance(prov);
    nlohmann::json j = m.ToJson();
    j["reference_bone"] = run.fit.referenceBone;
    nlohmann::json factors = nlohmann::json::object();
    for (const auto& [b, f] : run.fit.boneFactor)
      factors[b] = f;
    j["bone_factors"] = factors;
    j["chisel_scale"] = run.fit.chiselScale;
    j["fit_rms_thrust_N"] = run.fit.rmsThrustErrorN;
    j["fit_rms_torque_Nmm"] = run.fit.rmsTorqueErrorNmm;
    nlohmann::json folds = nlohmann::json::array();
    for (const auto& f : run.folds)
      folds.push_back({{"condition", f.condition},
                       {"rms_thrust_error_N", f.rmsThrustErrorN},
                       {"rms_torque_error_Nmm", f.rmsTorqueErrorNmm},
                       {"min_torque_Nmm", f.minPredictedTorqueNmm}});
    j["cross_validation"] = folds;
    if (!run.cvError.empty())
      j["cross_validation_error"] = run.cvError;
    return j.dump(2) + "\n";
  };
  std::ostringstream foldsCsv, predCsv;
  foldsCsv << "method,condition,rms_thrust_error_N,rms_torque_error_Nmm,min_torque_Nmm,"
              "mean_torque_Nmm,bone_factor,bone_factor_known\n";
  predCsv << "method,line,condition,measured_thrust_N,measured_torque_Nmm,fit_thrust_N,"
             "fit_torque_Nmm,cv_thrust_N,cv_torque_Nmm\n";
  for (const auto& run : runs) {
    for (const auto& f : run.folds)
      foldsCsv << ToString(run.method) << "," << Quote(f.condition) << "," << Num(f.rmsThrustErrorN)
               << "," << Num(f.rmsTorqueErrorNmm) << "," << Num(f.minPredictedTorqueNmm) << ","
               << Num(f.meanPredictedTorqueNmm) << "," << Num(f.boneFactor) << ","
               << (f.boneFactorKnown ? 1 : 0) << "\n";
    for (size_t i = 0; i < samples.size(); ++i)
      predCsv << ToString(run.method) << "," << records[i].line << ","
              << Quote(samples[i].condition) << "," << Num(samples[i].thrustN) << ","
              << (std::isfinite(samples[i].torqueNmm) ? Num(samples[i].torqueNmm) : "") << ","
              << Num(run.fitted[i].thrustN) << "," << Num(run.fitted[i].torqueNmm) << ","
              << Num(run.held[i].thrustN) << "," << Num(run.held[i].torqueNmm) << "\n";
  }
  std::vector<ScatterPanel> panels(2);
  panels[0] = {"thrust", "measured thrust (N)", "predicted thrust (N)", true, {}};
  panels[1] = {"torque", "measured torque (N mm)", "predicted torque (N mm)", true, {}};
  const char* colors[2] = {"#1f77b4", "#d62728"};
  for (size_t r = 0; r < runs.size(); ++r) {
    const std::string mname = r == 0 ? "ours (lazar)" : "zheng";
    ScatterSeries fT{mname + " fit", colors[r], false, {}},
        cT{mname + " cross-validated", colors[r], true, {}};
    ScatterSeries fM = fT, cM = cT;
    for (size_t i = 0; i < samples.size(); ++i) {
      fT.points.push_back({samples[i].thrustN, runs[r].fitted[i].thrustN});
      cT.points.push_back({samples[i].thrustN, runs[r].held[i].thrustN});
      fM.points.push_back({samples[i].torqueNmm, runs[r].fitted[i].torqueNmm});
      cM.points.push_back({samples[i].torqueNmm, runs[r].held[i].torqueNmm});
    }
    panels[0].series.push_back(fT);
    panels[0].series.push_back(cT);
    panels[1].series.push_back(fM);
    panels[1].series.push_back(cM);
  }
  const std::string svg =
      ScatterSvg(panels, "predicted against measured: " + data.filename().string());
  std::filesystem::create_directories(outDir);
  const std::filesystem::path dir(outDir);
  WriteFilesAtomic({{(dir / "coefficients.json").string(), modelJson(runs[0], name)},
                    {(dir / "zheng.json").string(), modelJson(runs[1], name + "-zheng")},
                    {(dir / "folds.csv").string(), foldsCsv.str()},
                    {(dir / "predictions.csv").string(), predCsv.str()},
                    {(dir / "chart.svg").string(), svg}});
  std::cout << "\nwrote " << (dir / "coefficients.json").string() << ", zheng.json, folds.csv, "
            << "predictions.csv, chart.svg\n";
  return 0;
}

BM_REGISTER_COMMAND(calibrate, "fit cutting coefficients to measured forces (DATA.csv)",
                    CalibrateOptions, CalibrateCommand);

} // namespace bm::cli
