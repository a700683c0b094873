// bmsimRunSteps.cxx - see bmsimRunSteps.h.
#include "bmsimRunSteps.h"

#include <cctype>
#include <filesystem>
#include <iostream>
#include <optional>

#include "bmAtomicFile.h"
#include "bmFeedTrial.h"
#include "bmMachiningSetup.h"
#include "bmPlanRunReport.h"
#include "bmReamingOutcome.h"
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

Vec3 ToVec3(const nlohmann::json& j, const Eigen::Vector3d& def) {
  if (j.is_array() && j.size() == 3)
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
  return {def(0), def(1), def(2)};
}

double PlanValue(const nlohmann::json& plan, const char* key, double def) {
  return plan.is_object() && plan.contains(key) && plan.at(key).is_number()
             ? plan.at(key).get<double>()
             : def;
}

} // namespace

int RunSceneSteps(const bm::Scene& scene, const ParsedArgs& args, const std::string& outDir) {
  [[maybe_unused]] const bool report = !args.Has("no-report");
  CheckWritableOutput("output folder", outDir, true);
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

  nlohmann::json summary = {{"plan", scene.name}, {"steps", steps}, {"completed", !blocked}};
  if (!scene.planning.is_null())
    summary["planning"] = scene.planning;
  if (reamStep) {
    const bm::TrialSpec& t = scene.Step(*reamStep).trial;
    ReamingOutcomeOptions o;
    const nlohmann::json& p = scene.planning;
    o.baseplateDiameterMm = PlanValue(p, "baseplate_diameter_mm", o.baseplateDiameterMm);
    o.backRadiusMm = PlanValue(p, "baseplate_back_radius_mm", o.backRadiusMm);
    o.gapMm = PlanValue(p, "seating_gap_mm", o.gapMm);
    o.pegLengthMm = PlanValue(p, "peg_length_mm", o.pegLengthMm);
    o.pegRadiusMm = PlanValue(p, "peg_radius_mm", o.pegRadiusMm);
    o.pinRadiusMm = PlanValue(p, "pin_radius_mm", o.pinRadiusMm);
    o.pinDepthMm = PlanValue(p, "pin_depth_mm", o.pinDepthMm);
    const Vec3 entry =
        ToVec3(p.is_object() ? p.value("entry_mm", nlohmann::json()) : nullptr, t.entry);
    const Vec3 axis =
        Normalized(ToVec3(p.is_object() ? p.value("axis", nlohmann::json()) : nullptr, t.axis));
    const ReamingOutcome outcome =
        MeasureReamingOutcome(before, bone, entry, axis, *reamer, reamReached, o);
    summary["outcome"] = outcome.ToJson();
    summary["outcome"]["options"] = {{"baseplate_diameter_mm", o.baseplateDiameterMm},
                                     {"baseplate_back_radius_mm", o.backRadiusMm},
                                     {"seating_gap_mm", o.gapMm},
                                     {"peg_length_mm", o.pegLengthMm},
                                     {"peg_radius_mm", o.pegRadiusMm}};
    std::cout << "  outcome: removed " << outcome.removedMm3 << " mm^3 (cortical "
              << outcome.removedCorticalMm3 << ", cancellous " << outcome.removedCancellousMm3
              << "), reamed face " << outcome.faceAngleDeg << " deg from the axis, medialisation "
              << outcome.medialisationMm << " mm, seating " << 100 * outcome.seating << " % within "
              << o.gapMm << " mm, bone beyond the peg " << outcome.boneBeyondPegMm << " mm\n";
    for (const std::string& w : outcome.warnings)
      std::cout << "  warning: " << w << "\n";
  }

  // The glenoid before and after, with the planned axis, face normal, rim and face plane drawn.
#ifdef BM_WITH_REPORT
  if (report && scene.planning.is_object() && scene.planning.contains("entry_mm") &&
      scene.planning.contains("axis")) {
    const GlenoidPictureFiles files =
        WriteGlenoidPictures(stagePath.string(), before, bone, scene.planning);
    summary["pictures"] = {{"before", files.before}, {"after", files.after}};
  }
#endif

  // Everything was written: the step folders, pictures and results move into place together,
  // the summary last (it says the set is complete).
  summary = WithFaceAngles(std::move(summary));
  WriteFilesAtomic({{(stagePath / "summary.json").string(), summary.dump(2) + "\n"},
                    {(stagePath / "plan_result.md").string(), PlanRunMarkdown(summary)},
                    {(stagePath / "plan_result.html").string(), PlanRunHtml(summary)}});
  staged.Commit("summary.json");
  std::cout << "wrote " << outDir << "/summary.json, plan_result.md/.html and " << folders.size()
            << " step folders\n";
  if (blocked)
    std::cerr << "bmsim run: the plan did not complete: a guide met solid bone (see the "
                 "warnings)\n";
  return blocked ? 1 : 0;
}

} // namespace bm::cli
