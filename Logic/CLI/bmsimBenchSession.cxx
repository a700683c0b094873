// bmsimBenchSession.cxx - bmsim bench --session: a haptic session's frame time on a scene in a
// hand-like trial, the incremental path against the full pass; on a drill's scene, the scripted
// push through the plate, the proxy's fast paths against their reference (bmsimBenchSession.h).
#include "bmsimBenchSession.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <thread>

#ifdef BM_WITH_REPORT
#include <vtkNew.h>
#include <vtkPolyData.h>
#endif

#include "bmAtomicFile.h"
#include "bmBenchmark.h"
#include "bmBreakthrough.h"
#ifdef BM_WITH_REPORT
#include "bmBoneSurface.h"
#endif
#include "bmCpuEngine.h"
#include "bmFeedTrial.h"
#include "bmHapticSession.h"
#include "bmScriptedDevice.h"
#include "bmMachiningSetup.h"
#include "bmScene.h"
#include "bmSceneOverrides.h"
#include "bmSessionBenchTable.h"
#include "bmSessionBuilder.h"
#include "bmsimBenchSupport.h"
#include "bmsimCommand.h"
#include "bmsimSessionAccuracy.h"

namespace bm::cli {

namespace {

/// One hand-like session trial's figures.
struct SessionRun {
  std::vector<double> frameMs, contactMs; ///< every frame; the frames touching bone
  int64_t over = 0;                       ///< frames over the period
  int64_t rulePauses = 0; ///< pauses the default overrun rule (> 5 of 100 frames) would make
  double removedMm3 = 0, sumThrustN = 0, sumProxyMm = 0, sumForceN = 0;
  Eigen::Vector3d lastProxy = Eigen::Vector3d::Zero();
  std::vector<double> byFrame; ///< every frame's time, ms, in frame order
  double breakthroughS = -1;   ///< bm::MeasureBreakthrough's time, s (-1: none)
  bm::Scene used;              ///< the scene at the resolutions and threads the session ran
  std::string gridReason;      ///< how they were chosen ("" when given)
  std::string engine;          ///< the engine that ran it (bm::Engine::Name())
};

/// The scripted hand (mode Hand) or push (mode Force) pushes pushN (N, at the device, scaled by
/// the tool's force scale) along -axis from the scene's clearance above its entry point; the
/// session runs `seconds` (s) of frames; candidates: the incremental path (the proxy's contact
/// candidates and the engine's incremental pass) or the full pass (every contact query scans the
/// shell, the engine visits every element of the blocks not culled); fastPaths: the proxy's exact
/// fast paths (ProxyOptions::sweepFirstContact) or their reference; choose: the resolutions and
/// threads a session chooses (bmSessionGrid.h), else the scene's.
SessionRun RunHandSession(const bm::Scene& scene, bool choose, bool candidates, double pushN,
                          double tremorN, double seconds, bool realTime, double viewIntervalMs,
                          int64_t checksumFrames, const std::string& clDevice,
                          bm::ScriptMode mode = bm::ScriptMode::Hand, bool fastPaths = true) {
  // A hand on a Touch pushing through the tool's force scale, counting its overruns.
  bm::SessionRequest req;
  req.mode = mode;
  req.appliedForceN = pushN;
  req.handTremorN = tremorN;
  req.realTime = realTime;
  req.chooseGrid = choose && bm::CanImportSceneBones();
  req.liveView = viewIntervalMs > 0;
  req.overrunLimit = -1;
  req.rateHz = 1.0 / scene.trial.frameS;
  req.maxFrames = int64_t(std::llround(seconds / scene.trial.frameS));
  req.clDevice = clDevice;
  bm::BuiltSession built = req.chooseGrid ? bm::BuildSession(scene, req)
                                          : bm::BuildSession(scene, BenchSceneBone(scene), req);
  const std::shared_ptr<bm::Device>& device = built.device;
  bm::MachiningSetup& setup = *built.setup;
  bm::SessionOptions o = built.options;
  o.recordCapacity = size_t(o.maxFrames) + 16;
  o.proxy.sweepFirstContact = fastPaths;
  if (!candidates) { // the full pass: every contact query scans the shell, the engine visits all
    o.proxy.candidateRadiusVoxels = 0;
    if (auto* cpu = dynamic_cast<bm::CpuEngine*>(&setup.GetEngine()))
      cpu->SetIncremental(false);
  }
  bm::HapticSession session(setup, device, o);
  session.Start();
  // The live view, as the BM Session source refreshes it: the cut bone's surface re-extracted
  // from the live voxmap every viewIntervalMs (at most 8 ms per refresh) on its own thread.
  std::atomic<bool> viewDone{false};
  std::thread viewer;
#ifdef BM_WITH_REPORT
  if (viewIntervalMs > 0)
    viewer = std::thread([&] {
      bm::BoneSurface surface;
      surface.SetTimeBudgetMs(8.0);
      vtkNew<vtkPolyData> port;
      while (!viewDone.load()) {
        surface.Update(setup.Bone());
        port->ShallowCopy(surface.GetOutput());
        std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(viewIntervalMs));
      }
    });
#else
  if (viewIntervalMs > 0)
    throw bm::cli::UsageError("--with-view needs a build with VTK (the live view's surface)");
#endif
  const bool finished = session.WaitUntilPaused(seconds * 20 + 600);
  viewDone.store(true);
  if (viewer.joinable())
    viewer.join();
  if (!finished)
    throw std::runtime_error("session bench: the trial did not finish");
  session.Stop();
  std::vector<bm::FrameRecord> rec;
  session.DrainRecords(rec);
  SessionRun r;
  r.used = setup.GetScene();
  r.gridReason = built.gridReason;
  r.engine = setup.GetEngine().Name();
  const double periodMs = 1000.0 * scene.trial.frameS;
  std::vector<uint8_t> window(100, 0);
  int inWindow = 0;
  for (size_t k = 0; k < rec.size(); ++k) {
    const bm::FrameRecord& f = rec[k];
    r.frameMs.push_back(f.frameMs);
    r.byFrame.push_back(f.frameMs);
    if (f.thrustN != 0 || f.removedVoxels > 0 || f.deviceForce[0] != 0 || f.deviceForce[1] != 0 ||
        f.deviceForce[2] != 0)
      r.contactMs.push_back(f.frameMs);
    const bool over = f.frameMs > periodMs;
    r.over += over;
    uint8_t& slot = window[k % window.size()];
    inWindow += int(over) - int(slot);
    slot = over;
    if (inWindow > 5) { // the session would pause here; a resume starts an empty window
      ++r.rulePauses;
      std::fill(window.begin(), window.end(), uint8_t(0));
      inWindow = 0;
    }
    if (int64_t(k) >= checksumFrames)
      continue;
    r.removedMm3 += f.removedVolumeMm3;
    r.sumThrustN += f.thrustN;
    r.sumProxyMm += f.proxyPos[0] + f.proxyPos[1] + f.proxyPos[2];
    r.sumForceN += f.deviceForce[0] + f.deviceForce[1] + f.deviceForce[2];
    r.lastProxy = {f.proxyPos[0], f.proxyPos[1], f.proxyPos[2]};
  }
  std::sort(r.frameMs.begin(), r.frameMs.end());
  std::sort(r.contactMs.begin(), r.contactMs.end());
  const bm::Breakthrough b = bm::MeasureBreakthrough(rec, [&](const bm::FrameRecord& f) {
    return bm::ToolDepthMm(setup, Eigen::Vector3d(f.proxyPos[0], f.proxyPos[1], f.proxyPos[2]),
                           bm::ToolRotationFromQuaternion(f.deviceQuat));
  });
  if (b.found)
    r.breakthroughS = b.timeS;
  return r;
}

/// A drill's scene: the scripted push (force mode, as `bmsim run SCENE --device scripted --mode
/// force`) through the plate at the resolutions and threads a session chooses (or those given),
/// the proxy's fast paths and their reference in turn, `repeats` times; prints each run's frame
/// p50 / p99 / max and frames over the period, for the whole run and for three windows (before
/// breakthrough less 0.1 s: the cut; 0.1 s either side of it: the point leaving the plate; after),
/// and checks that both paths gave the same checksum. Writes DIR/session_force.csv.
int ForceSessionBench(const bm::cli::ParsedArgs& p, const std::string& sceneName, double seconds,
                      double push, int repeats, bool realTime, const std::string& out,
                      const std::string& machine, const std::string& date) {
  bm::SceneOverrides overrides;
  if (auto t = p.GetInt("threads", 1, 64))
    overrides.threads = int(*t);
  const bm::Scene base = bm::ApplyOverrides(bm::ResolveScene(sceneName), overrides);
  const bool choose = !p.Has("voxmaps") && !p.Has("threads");
  std::vector<bm::Scene> scenes;
  for (int v : Resolutions(p, "voxmaps", {0}))
    scenes.push_back(v > 0 ? base.WithVoxmapResolution(v) : base);
  std::string csv = "scene,voxmap,shell,threads,path,run,window,frames,p50_ms,p99_ms,max_ms,over,"
                    "breakthrough_s,machine,date\n";
  std::cout << std::fixed << std::setprecision(3);
  for (const bm::Scene& scene : scenes) {
    const double periodMs = 1000.0 * scene.trial.frameS;
    const int64_t frames = std::llround(seconds / scene.trial.frameS);
    std::cout << "session bench, scene " << scene.name << " (";
    if (choose)
      std::cout << "the resolutions a session chooses";
    else
      std::cout << "voxmap " << scene.voxmapResolution << ", shell " << scene.shellResolution
                << ", " << scene.threads << " engine threads";
    std::cout << "): scripted push of " << push
              << " N at the device (force mode, the tool's force scale), " << seconds << " s at "
              << 1.0 / scene.trial.frameS << " Hz" << (realTime ? "" : " (frames back to back)")
              << "; the proxy's fast paths against their reference; machine: " << machine << "\n";
    for (int run = 1; run <= repeats; ++run) {
      std::array<double, 2> checksum{0, 0};
      for (bool fast : {true, false}) {
        const SessionRun r = RunHandSession(scene, choose, true, push, 0.0, seconds, realTime, 0.0,
                                            frames, "", bm::ScriptMode::Force, fast);
        if (!r.gridReason.empty() && fast && run == 1)
          std::cout << "resolutions chosen: " << r.gridReason << "\n";
        const double b = r.breakthroughS;
        struct Window {
          const char* name;
          double from, to; // s
        };
        const double inf = std::numeric_limits<double>::infinity();
        std::vector<Window> windows{{"all", -inf, inf}};
        if (b >= 0) {
          windows.push_back({"cut", -inf, b - 0.1});
          windows.push_back({"breakthrough", b - 0.1, b + 0.1});
          windows.push_back({"after", b + 0.1, inf});
        }
        std::cout << "run " << run << (fast ? " fast path" : " reference") << ": breakthrough "
                  << (b >= 0 ? "at " + std::to_string(b).substr(0, 5) + " s" : "not found") << "\n";
        for (const Window& w : windows) {
          std::vector<double> v;
          for (size_t k = 0; k < r.byFrame.size(); ++k) {
            const double t = double(k) * scene.trial.frameS;
            if (t >= w.from && t < w.to)
              v.push_back(r.byFrame[k]);
          }
          std::sort(v.begin(), v.end());
          const int64_t over =
              std::count_if(v.begin(), v.end(), [&](double ms) { return ms > periodMs; });
          const double p50 = bm::Percentile(v, 50), p99 = bm::Percentile(v, 99);
          const double mx = v.empty() ? 0.0 : v.back();
          std::cout << "  " << std::left << std::setw(13) << w.name << std::right << v.size()
                    << " frames, p50 " << p50 << " ms, p99 " << p99 << " ms, max " << mx
                    << " ms, over " << periodMs << " ms: " << over << "\n";
          std::ostringstream row;
          row << std::setprecision(6) << "\"" << scene.name << "\"," << r.used.voxmapResolution
              << "," << r.used.shellResolution << "," << r.used.threads << ","
              << (fast ? "fast" : "reference") << "," << run << "," << w.name << "," << v.size()
              << "," << p50 << "," << p99 << "," << mx << "," << over << "," << b << ",\""
              << machine << "\"," << date << "\n";
          csv += row.str();
        }
        std::cout << std::setprecision(9) << "  checksum: removed " << r.removedMm3
                  << " mm^3, sum thrust " << r.sumThrustN << " N, sum proxy " << r.sumProxyMm
                  << " mm, sum device force " << r.sumForceN << " N\n"
                  << std::setprecision(3) << std::flush;
        const std::array<double, 2> sum{r.removedMm3 + r.sumThrustN, r.sumProxyMm + r.sumForceN};
        if (fast)
          checksum = sum;
        else if (sum != checksum)
          throw std::runtime_error("session bench: the fast paths and their reference gave "
                                   "different frames (checksums differ)");
        bm::WriteFileAtomic(out + "/session_force.csv", csv);
      }
    }
  }
  std::cout << "wrote " << out << "/session_force.csv\n";
  return 0;
}

} // namespace

int SessionBench(const bm::cli::ParsedArgs& p) {
  const std::string sceneName = p.Get("session", "glenoid");
  const double seconds = p.GetDouble("seconds", 0.01, 3600).value_or(20.0);
  const double push = p.GetDouble("push", 0.01, bm::DeviceLimits().maxForceN).value_or(2.5);
  const double fullSeconds = p.GetDouble("full-seconds", 0.01, 3600).value_or(seconds);
  const double tremor = p.GetDouble("tremor", 0, bm::DeviceLimits().maxForceN).value_or(0.1);
  const int repeats = int(p.GetInt("repeats", 1, 100).value_or(2));
  const bool realTime = !p.Has("back-to-back");
  const std::string out = p.Get("out", "out/bench-session");
  // Without the view, and with it when asked (--with-view): the panel's session refreshes it.
  const std::vector<bool> views =
      p.Has("with-view") ? std::vector<bool>{false, true} : std::vector<bool>{false};
  const std::string clDevice = p.Get("cl-device", "");
  // The CPU backend unless --backends names others: each cell runs on each backend in turn.
  const std::vector<std::string> backends = p.Has("backends")
                                                ? bm::SplitCommaList(p.Get("backends", ""))
                                                : std::vector<std::string>{"cpu"};
  for (const auto& b : backends)
    if (b != "cpu" && b != "opencl")
      throw bm::cli::UsageError("--backends: '" + b + "' is not cpu or opencl");
  // The scene's own resolutions, or each voxmap asked for with the shell scaled alike (as the
  // BM Session source does for a voxmap set alone).
  std::vector<bm::Scene> scenes;
  // Without --voxmaps (or --threads): the resolutions and threads a session chooses (on the CPU
  // backend: the session table measures it).
  const bool choose = !p.Has("voxmaps") && !p.Has("threads");
  if (p.Has("accuracy") && bm::ResolveScene(sceneName).tool.value("type", "") != "reamer")
    throw bm::cli::UsageError("--accuracy: scene '" + sceneName + "' cuts with a " +
                              bm::ResolveScene(sceneName).tool.value("type", "?") +
                              "; the accuracy is measured on a reaming's outcome (a reamer scene)");
  for (const auto& backend : backends) {
    bm::SceneOverrides overrides;
    if (auto t = p.GetInt("threads", 1, 64))
      overrides.threads = int(*t);
    overrides.backend = backend;
    const bm::Scene base = bm::ApplyOverrides(bm::ResolveScene(sceneName), overrides);
    for (int v : Resolutions(p, "voxmaps", {0}))
      scenes.push_back(v > 0 ? base.WithVoxmapResolution(v) : base);
  }
  std::filesystem::create_directories(out);
  const std::string machine = MachineName();
  char date[16] = "";
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
  // A drill's scene: the push through the plate (force mode, 2 s unless --seconds), the proxy's
  // fast paths against their reference.
  if (bm::ResolveScene(sceneName).tool.value("type", "") == "drill") {
    if (p.Has("accuracy") || p.Has("with-view") || p.Has("backends"))
      throw bm::cli::UsageError("--session " + sceneName +
                                ": a drill's scene runs the push through the plate on the CPU "
                                "backend, without --accuracy, --with-view or --backends");
    return ForceSessionBench(p, sceneName, p.GetDouble("seconds", 0.01, 3600).value_or(2.0), push,
                             int(p.GetInt("repeats", 1, 100).value_or(1)), realTime, out, machine,
                             date);
  }
  const std::string clName = std::find(backends.begin(), backends.end(), "opencl") != backends.end()
                                 ? OpenCLDeviceName(clDevice)
                                 : std::string();
  if (!clName.empty())
    std::cout << "OpenCL device: " << clName << "\n";
  std::string csv = bm::SessionBenchCsvHeader() + "\n";
  std::vector<bm::SessionBenchRow> rows;
  std::cout << std::fixed << std::setprecision(3);
  auto figures = [](const std::vector<double>& v) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(3) << "p50 " << bm::Percentile(v, 50) << " ms, p99 "
      << bm::Percentile(v, 99) << " ms, max " << (v.empty() ? 0.0 : v.back()) << " ms";
    return s.str();
  };
  for (const bm::Scene& scene : scenes) {
    const int64_t checksumFrames =
        std::llround(std::min(seconds, fullSeconds) / scene.trial.frameS);
    std::cout << "session bench, scene " << scene.name << ", backend " << scene.backend << " (";
    if (choose)
      std::cout << "the resolutions a session chooses";
    else
      std::cout << "voxmap " << scene.voxmapResolution << ", shell " << scene.shellResolution
                << ", " << scene.threads << " engine threads";
    std::cout << "): scripted hand pushing " << push << " N (force scale "
              << "the tool's, bm::SessionForceScale) with " << tremor << " N of lateral tremor, "
              << seconds << " s at " << 1.0 / scene.trial.frameS << " Hz"
              << (realTime ? "" : " (frames back to back)") << "; machine: " << machine << "\n";
    for (int run = 1; run <= repeats; ++run)
      for (bool view : views)
        for (bool incremental : {true, false}) {
          const SessionRun r =
              RunHandSession(scene, choose && scene.backend == "cpu", incremental, push, tremor,
                             incremental ? seconds : fullSeconds, realTime, view ? 33.0 : 0.0,
                             checksumFrames, clDevice);
          if (!r.gridReason.empty() && incremental)
            std::cout << "resolutions chosen: " << r.gridReason << "\n";
          if (run == 1 && !view && incremental)
            std::cout << "engine: " << r.engine << "\n";
          if (scene.backend != "cpu" && r.engine.rfind(scene.backend, 0) != 0)
            throw std::runtime_error("session bench: the " + scene.backend +
                                     " backend did not start (ran on " + r.engine + ")");
          std::cout << "run " << run << (incremental ? " incremental" : " full pass  ")
                    << (view ? ", view on " : ", view off") << ": " << r.frameMs.size()
                    << " frames " << figures(r.frameMs) << "; " << r.contactMs.size()
                    << " touching bone " << figures(r.contactMs) << "; over "
                    << 1000.0 * scene.trial.frameS << " ms: " << r.over << ", overrun pauses "
                    << r.rulePauses << "\n"
                    << std::setprecision(9) << "  checksum of the first " << checksumFrames
                    << " frames: removed " << r.removedMm3 << " mm^3, sum thrust " << r.sumThrustN
                    << " N, sum proxy " << r.sumProxyMm << " mm, sum device force " << r.sumForceN
                    << " N, last proxy (" << r.lastProxy(0) << ", " << r.lastProxy(1) << ", "
                    << r.lastProxy(2) << ") mm\n"
                    << std::setprecision(3) << std::flush;
          bm::SessionBenchRow row;
          row.scene = scene.name;
          row.voxmap = r.used.voxmapResolution;
          row.shell = r.used.shellResolution;
          row.threads = r.used.threads;
          row.path = incremental ? "incremental" : "full";
          row.view = view;
          row.run = run;
          row.frames = (long long)r.frameMs.size();
          row.p50Ms = bm::Percentile(r.frameMs, 50);
          row.p99Ms = bm::Percentile(r.frameMs, 99);
          row.maxMs = r.frameMs.empty() ? 0.0 : r.frameMs.back();
          row.over = r.over;
          row.overrunPauses = r.rulePauses;
          row.seconds = double(r.frameMs.size()) * scene.trial.frameS;
          row.machine = scene.backend == "opencl" ? machine + "; OpenCL " + clName : machine;
          row.date = date;
          row.backend = scene.backend;
          csv += bm::SessionBenchCsvRecord(row) + "\n";
          rows.push_back(row);
          // The rows so far, after each run: a bench stopped part-way keeps what it measured.
          bm::WriteFileAtomic(out + "/session.csv", csv);
        }
  }
  bm::WriteFileAtomic(out + "/session.csv", csv);
  std::cout << "wrote " << out << "/session.csv\n";
  if (const auto reference = p.GetInt("accuracy", 8, 4096))
    bm::cli::WriteSessionAccuracy(scenes.front(), rows, views.back(), int(*reference),
                                  BenchSceneBone, out, machine, date);
  return 0;
}

} // namespace bm::cli
