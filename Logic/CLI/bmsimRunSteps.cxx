// bmsimRunSteps.cxx - see bmsimRunSteps.h.
#include "bmsimRunSteps.h"

#include <cctype>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>

#include "bmAtomicFile.h"
#include "bmFeedTrial.h"
#include "bmMachiningSetup.h"
#include "bmPlanResult.h"
#ifdef BM_WITH_DCMTK
#include "bmDicomSource.h"
#include "bmPlanDicomResults.h"
#endif
#ifdef BM_WITH_REPORT
#include "bmGlenoidPictures.h"
#include "bmTrialReport.h"
#endif
#include "bmsimProgressBar.h"
#include "bmsimRunSession.h"
#include "bmsimStagedOutput.h"

namespace bm::cli {
namespace {

namespace fs = std::filesystem;

// "1-guide-pin": the step's number and its name in lower case, letters and digits only.
std::string StepFolder(size_t i, const std::string& name) {
  std::string slug;
  for (char c : name) {
    if (std::isalnum(static_cast<unsigned char>(c)))
      slug += char(std::tolower(static_cast<unsigned char>(c)));
    else if (!slug.empty() && slug.back() != '-')
      slug += '-';
  }
  while (!slug.empty() && slug.back() == '-')
    slug.pop_back();
  return std::to_string(i + 1) + "-" + (slug.empty() ? "step" : slug);
}

} // namespace

int RunSceneSteps(const bm::Scene& scene, const ParsedArgs& args, const std::string& outDir) {
  [[maybe_unused]] const bool report = !args.Has("no-report");
  CheckWritableOutput("output folder", outDir, true);
  // DICOM results need the series the CT came from: checked before any step runs.
  std::string dicomFolder, dicomSeries;
  if (args.Has("dicom")) {
#ifdef BM_WITH_DCMTK
    const nlohmann::json& ct = scene.bone.ct;
    const std::string path = scene.bone.type == "ct" ? ct.value("ct", std::string()) : "";
    const fs::path folder = path.empty() || fs::path(path).is_absolute()
                                ? fs::path(path)
                                : fs::path(scene.baseDir) / path;
    if (path.empty() || !fs::is_directory(folder))
      throw UsageError("--dicom: the plan's CT" + (path.empty() ? "" : " '" + path + "'") +
                       " is not a DICOM series (a folder); DICOM results belong to the series "
                       "they came from");
    dicomFolder = folder.string();
    dicomSeries = ct.value("series", std::string());
    bm::ReadDicomSource(dicomFolder, dicomSeries); // refuses a folder without that series now
#else
    throw UsageError("--dicom: this build has no DCMTK (BM_WITH_DCMTK)");
#endif
  }
  StagedOutput staged(outDir); // a failed step leaves nothing behind (bmsimStagedOutput.h)
  const fs::path stagePath(staged.Path());

  Voxmap bone = SceneBone(scene);
  const Voxmap before = bone;
  nlohmann::json steps = nlohmann::json::array();
  std::vector<std::string> folders;
  bool blocked = false;
  std::optional<size_t> reamStep;
  double reamReached = 0;
  std::unique_ptr<ToolModel> reamer;
  std::cout << "plan " << scene.name << ": " << scene.steps.size() << " steps on one bone\n";
  for (size_t i = 0; i < scene.steps.size(); ++i) {
    const bm::Scene step = scene.Step(i);
    const std::string folder = StepFolder(i, scene.steps[i].name);
    bm::MachiningSetup setup(step, bone, args.Get("cl-device", ""));
    bm::FeedTrial trial(setup);
    {
      ProgressBar bar(folder);
      trial.Run([&](double f) { return bar.Update(f); });
    }
    const fs::path dir = stagePath / folder;
    trial.WriteOutputs(dir.string());
    nlohmann::json s = trial.Summary();
    std::cout << "  step " << i + 1 << " (" << scene.steps[i].name << ", " << setup.Tool().Kind()
              << "): reached " << s["reached_depth_mm"].get<double>() << " mm, removed "
              << s["removed_volume_mm3"].get<double>() << " mm^3, thrust "
              << s["thrust_N"].get<double>() << " N, torque " << s["torque_Nmm"].get<double>()
              << " N mm\n";
    for (const std::string& w : trial.Warnings())
      std::cout << "  warning: " << w << "\n";
#ifdef BM_WITH_REPORT
    if (report)
      bm::WriteTrialReport(dir.string(), setup, trial);
#endif
    if (setup.Tool().Kind() == "reamer") {
      reamStep = i;
      reamReached = s["reached_depth_mm"].get<double>();
      reamer = setup.Tool().Clone();
    }
    steps.push_back({{"step", i + 1},
                     {"name", scene.steps[i].name},
                     {"description", scene.steps[i].description},
                     {"folder", folder},
                     {"tool", setup.Tool().Kind()},
                     {"summary", s}});
    folders.push_back(folder);
    blocked = blocked || trial.GuideBlocked();
    bone = setup.Bone(); // the cut bone goes on to the next step
  }

  // The outcome, the glenoid before and after with the plan drawn, and the report: written
  // together, the summary last (it says the set is complete).
  PlanResultInput result;
  result.planName = scene.name;
  result.planning = scene.planning;
  result.steps = steps;
  result.completed = !blocked;
  result.before = &before;
  result.after = &bone;
  if (reamStep) {
    const bm::TrialSpec& t = scene.Step(*reamStep).trial;
    result.reamer = reamer.get();
    result.reamReachedMm = reamReached;
    result.trialEntry = {t.entry(0), t.entry(1), t.entry(2)};
    result.trialAxis = {t.axis(0), t.axis(1), t.axis(2)};
  }
  PlanPictureWriter pictures;
#ifdef BM_WITH_REPORT
  if (report)
    pictures = [](const std::string& dir, const Voxmap& b, const Voxmap& a,
                  const nlohmann::json& planning) {
      const GlenoidPictureFiles files = WriteGlenoidPictures(dir, b, a, planning);
      return std::make_pair(files.before, files.after);
    };
#endif
  const nlohmann::json summary = WritePlanResult(stagePath.string(), result, pictures);
  if (summary.contains("outcome")) {
    const nlohmann::json& o = summary["outcome"];
    // NaN (null in JSON) where the outcome could not be measured.
    const auto num = [](const nlohmann::json& j, const char* key) {
      return j.contains(key) && j[key].is_number() ? j[key].get<double>()
                                                   : std::numeric_limits<double>::quiet_NaN();
    };
    std::cout << "  outcome: removed " << num(o, "removed_volume_mm3") << " mm^3 (cortical "
              << num(o, "removed_cortical_mm3") << ", cancellous "
              << num(o, "removed_cancellous_mm3") << "), reamed face "
              << num(o, "reamed_face_angle_to_axis_deg") << " deg from the axis, medialisation "
              << num(o, "medialisation_mm") << " mm, seating " << 100 * num(o, "seating_fraction")
              << " % within " << num(o["options"], "seating_gap_mm") << " mm, bone beyond the peg "
              << num(o, "bone_beyond_peg_mm") << " mm\n";
    for (const auto& w : o.value("warnings", nlohmann::json::array()))
      std::cout << "  warning: " << w.get<std::string>() << "\n";
  }
#ifdef BM_WITH_DCMTK
  if (!dicomFolder.empty()) {
    const bm::PlanDicomFiles files =
        bm::WritePlanDicomResults((stagePath / "dicom").string(), dicomFolder, dicomSeries, before,
                                  bone, summary, BM_VERSION, stagePath.string());
    std::cout << "  DICOM: dicom/" << fs::path(files.segmentation).filename().string()
              << " and dicom/" << fs::path(files.report).filename().string();
    for (const std::string& sc : files.pictures)
      std::cout << ", dicom/" << fs::path(sc).filename().string();
    std::cout << " for series " << (dicomSeries.empty() ? "(the folder's only one)" : dicomSeries)
              << "\n";
  }
#endif
  staged.Commit("summary.json");
  std::cout << "wrote " << outDir << "/summary.json, plan_result.md/.html and " << folders.size()
            << " step folders\n";
  if (blocked)
    std::cerr << "bmsim run: the plan did not complete: a guide met solid bone (see the "
                 "warnings)\n";
  return blocked ? 1 : 0;
}

} // namespace bm::cli
