// bmsim run - run a scene: built-in (drilling) or a scene file, and write its outputs.
#include <filesystem>
#include <iostream>

#include "bmFeedTrial.h"
#include "bmMachiningSetup.h"
#ifdef BM_WITH_REPORT
#include "bmTrialReport.h"
#endif
#include "bmScene.h"
#include "bmSceneOverrides.h"
#include "bmsimArgs.h"
#include "bmsimCommand.h"
#include "bmsimProgressBar.h"
#include "bmsimRunSession.h"
#include "bmsimRunSteps.h"
#include "bmsimStagedOutput.h"

namespace {

void RunOptions(bm::cli::ParsedArgs& p) {
  p.Words("SCENE", "built-in scene (drilling, glenoid, skull, ...) or a scene file (.json)")
      .Value("out", "DIR", "output folder (default out/<scene>); gets forces.csv, summary.json")
      .Real("feed", 1e-5, 1.0, "MM_PER_REV", "feed per revolution, mm/rev (default: the scene's)")
      .Real("speed", 1.0, 100000.0, "RPM", "spindle speed, rpm (default: the scene's)")
      .Int("voxmap-resolution", 8, 4096,
           "cells along the bone's longest side (default: the scene's; a session run chooses "
           "its own when none of the resolutions or threads is given: no finer than the CT's "
           "spacing and this machine's measured limit); alone, it scales the scene's shell "
           "alike (the grids keep their ratio)")
      .Int("shell-resolution", 8, 4096,
           "cells along the tool's longest side (default: the scene's, or a session's choice)")
      .Choice("method", {"lazar", "zheng"}, "force model and pipeline (default: the scene's)")
      .Int("threads", 1, 64, "CPU threads (default: the scene's, or a session's choice)")
      .Choice("backend", {"cpu", "opencl"}, "compute backend (default cpu)")
      .Value("cl-device", "D",
             "with --backend opencl: the OpenCL device, its number or part of its name (bmsim "
             "devices)")
      .Choice("lips", {"averaged", "instantaneous"}, "lip model (default averaged)")
      .Flag("no-report", "skip the report (report.md/.html, cut surface .vtp/.stl, PNG charts and "
                         "picture; rendering starts a private Xvfb when DISPLAY is unset)")
      .Flag("dicom", "a plan whose CT is a DICOM series: also DIR/dicom/reamed-bone.seg.dcm (the "
                     "bone removed and remaining, a Segmentation) and DIR/dicom/plan.sr.dcm (the "
                     "measurements and outcome, a Structured Report), in the series' patient, "
                     "study and frame of reference");
  bm::cli::SessionRunOptions(p);
  p.Footer("Without --device the scene runs as an offline feed trial (forces.csv, summary.json, "
           "report). With --device scripted|touch (or --mode) it runs through a haptic session "
           "(session.csv, summary.json; Docs/Session.md). A scene with steps (a plan from bmsim "
           "plan) runs its steps in order on one bone.");
}

int RunCommand(const bm::cli::ParsedArgs& p) {
  using bm::cli::UsageError;
  if (p.Positional().size() != 1)
    throw UsageError("needs exactly one SCENE");
  const std::string name = p.Positional()[0];
  bm::Scene scene;
  try {
    bm::SceneOverrides o;
    o.feedMmPerRev = p.GetDouble("feed", 1e-5, 1.0);
    o.speedRpm = p.GetDouble("speed", 1.0, 100000.0);
    o.voxmapResolution = int(p.GetInt("voxmap-resolution", 8, 4096).value_or(0));
    o.shellResolution = int(p.GetInt("shell-resolution", 8, 4096).value_or(0));
    o.method = p.Get("method", "");
    if (auto v = p.GetInt("threads", 1, 64))
      o.threads = int(*v);
    o.backend = p.Get("backend", "");
    o.lips = p.Get("lips", "");
    scene = bm::ApplyOverrides(bm::ResolveScene(name), o);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  const std::string out = p.Get("out", "out/" + scene.name);
  if (p.Has("dicom") && scene.steps.empty())
    throw UsageError("--dicom: scene '" + scene.name +
                     "' is not a plan; DICOM results are written for a plan's steps");
  if (!scene.steps.empty()) { // a plan: its steps in order on one bone (bmsimRunSteps.h)
    if (bm::cli::WantsSession(p))
      throw UsageError("scene '" + scene.name +
                       "' is a plan of steps, which run scripted; a session runs one scene");
    return bm::cli::RunSceneSteps(scene, p, out);
  }
  if (bm::cli::WantsSession(p))
    return bm::cli::RunSessionScene(scene, p, out);
  bm::cli::CheckWritableOutput("--out", out, true); // before the trial, not after it
  bm::cli::CheckRunOutputs(scene, p, out, {"forces.csv", "summary.json"});
  bm::MachiningSetup setup(scene, bm::cli::SceneBone(scene), p.Get("cl-device", ""));
  bm::FeedTrial trial(setup);
  {
    bm::cli::ProgressBar bar("run " + scene.name);
    trial.Run([&](double f) { return bar.Update(f); });
  }
  bm::cli::StagedOutput staged(out); // the outputs appear together (bmsimStagedOutput.h)
  trial.WriteOutputs(staged.Path());
  const auto s = trial.Summary();
  std::cout << "scene " << scene.name << " (" << s["engine"].get<std::string>() << ", voxmap "
            << scene.voxmapResolution << ", shell " << scene.shellResolution << ", "
            << scene.threads << " threads)\n"
            << "  thrust " << s["thrust_N"].get<double>() << " N (reference "
            << s["reference_thrust_N"].get<double>() << ", ripple "
            << s["thrust_ripple"].get<double>() << ")\n"
            << "  torque " << s["torque_Nmm"].get<double>() << " N mm (reference "
            << s["reference_torque_Nmm"].get<double>() << ")\n"
            << "  frame  p50 " << s["frame_ms_p50"].get<double>() << " ms, p99 "
            << s["frame_ms_p99"].get<double>() << " ms\n"
            << "  removed " << s["removed_volume_mm3"].get<double>() << " mm^3\n"
            << "wrote " << out << "/forces.csv and " << out << "/summary.json\n";
#ifdef BM_WITH_REPORT
  if (!p.Has("no-report")) {
    const bm::TrialReportFiles report = bm::WriteTrialReport(staged.Path(), setup, trial);
    const auto inOut = [&](const std::string& f) {
      return (std::filesystem::path(out) / std::filesystem::path(f).filename()).string();
    };
    std::cout << "report " << inOut(report.html) << " (and " << inOut(report.markdown) << ")\n";
  }
#endif
  staged.Commit();
  for (const std::string& w : trial.Warnings())
    std::cerr << "bmsim run: warning: " << w << "\n";
  return trial.GuideBlocked() ? 1 : 0; // the feed stopped short of its depth
}

} // namespace

BM_REGISTER_COMMAND(run, "run a scene (drilling or FILE.json) and write forces.csv, summary.json",
                    RunOptions, RunCommand);
