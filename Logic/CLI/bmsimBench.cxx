// bmsim bench - frame time against force error over the paper's resolution grid
// (Docs/Performance.md); with --view, the live view of the cut bone during a reaming session;
// with --session, a haptic session's frame time. Builds without ParaView's VTK (a Logic-only build
// for a GPU machine) have the grid and the session bench, without the chart and the view.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <thread>

#include <time.h>

#include <ctime>

#ifdef BM_WITH_REPORT
#include <vtkNew.h>
#include <vtkPolyData.h>
#endif

#include "bmAnalyticGlenoid.h"
#include "bmAtomicFile.h"
#include "bmBenchmark.h"
#ifdef BM_WITH_REPORT
#include "bmBoneSurface.h"
#endif
#include "bmCpuEngine.h"
#include "bmEdgeQuadrature.h"
#include "bmFeedTrial.h"
#include "bmHapticSession.h"
#include "bmScriptedDevice.h"
#include "bmTimingStats.h"
#include "bmMachiningSetup.h"
#include "bmScene.h"
#include "bmSceneOverrides.h"
#include "bmSessionBenchTable.h"
#include "bmSessionBuilder.h"
#ifdef BM_WITH_CHARTS
#include "bmSpeedAccuracyChart.h"
#endif
#include "bmsimArgs.h"
#include "bmsimCommand.h"
#include "bmsimSessionAccuracy.h"
#ifdef BM_WITH_IO
#include "bmCTVoxmap.h"
#endif
#ifdef BM_WITH_OPENCL
#include "bmOpenCLDevice.h"
#endif

namespace {

std::vector<int> Resolutions(const bm::cli::ParsedArgs& p, const std::string& name,
                             std::vector<int> def) {
  const auto v = p.Get(name);
  if (!v)
    return def;
  std::vector<int> out;
  for (const auto& s : bm::SplitCommaList(*v)) {
    size_t used = 0;
    int r = 0;
    try {
      r = std::stoi(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != s.size() || r < 8 || r > 4096)
      throw bm::cli::UsageError("--" + name + ": '" + s + "' is not a resolution in 8..4096");
    out.push_back(r);
  }
  if (out.empty())
    throw bm::cli::UsageError("--" + name + " is empty");
  return out;
}

std::string MachineName() {
  std::ifstream in("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  return model + ", " + std::to_string(std::thread::hardware_concurrency()) + " logical cores";
}

/// The OpenCL device `choice` picks, with its platform, or why there is none. Call it only after
/// the grid's cells ran: they fork, and a parent that opened OpenCL must not.
std::string OpenCLDeviceName(const std::string& choice) {
#ifdef BM_WITH_OPENCL
  try {
    bm::OpenCLDeviceInfo info;
    bm::ChooseOpenCLDevice(choice, &info);
    return info.name + " (" + info.platform + ", " + info.version + ")";
  } catch (const std::exception& e) {
    return std::string("none: ") + e.what();
  }
#else
  (void)choice;
  return "none (this build has no OpenCL)";
#endif
}

using Clock = std::chrono::steady_clock;

#ifdef BM_WITH_REPORT
/// CPU time of the calling thread, ms.
double ThreadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}
#endif

#ifndef BM_WITH_IO
/// The glenoid phantom's bone (bmAnalyticGlenoid.h's shape, placed as bmPhantom.h places it: face
/// centre (-60, 20, 40) mm, outward axis -x, elliptic face 40 x 29 mm, concave face of radius 35
/// mm, vault 25 mm deep, pilot hole r 4.0 mm x 10 mm) sampled straight into a voxmap, for builds
/// without BMIO (no ITK: no CT import). Box: the bone's bounds plus 0.625 mm, `resolution` voxels
/// along its longest side; fill = 0.5 + (signed distance to the surface) / spacing, clamped
/// (partial volume, as the CT import's resampling gives), all cortical. Units: mm.
bm::Voxmap AnalyticGlenoid(int resolution) {
  const double a = bm::glenoid::kA, b = bm::glenoid::kB, Rc = bm::glenoid::kRc, H = bm::glenoid::kH,
               rp = bm::glenoid::kRp, Dp = bm::glenoid::kDp, margin = 0.625;
  const double wTop = Rc - std::sqrt(Rc * Rc - a * a);
  // World x = -60 - w, y = 20 + v, z = 40 + u.
  const std::array<double, 3> lo{-60 - wTop - margin, 20 - b - margin, 40 - a - margin};
  const std::array<double, 3> hi{-60 + H + margin, 20 + b + margin, 40 + a + margin};
  double longest = 0;
  for (int q = 0; q < 3; ++q)
    longest = std::max(longest, hi[q] - lo[q]);
  const double h = longest / resolution;
  std::array<int, 3> dims;
  for (int q = 0; q < 3; ++q)
    dims[q] = int(std::ceil((hi[q] - lo[q]) / h));
  bm::Voxmap v(dims, h, {lo[0] + 0.5 * h, lo[1] + 0.5 * h, lo[2] + 0.5 * h});
  bm::Voxmap::Fill* fill = v.MutableFill();
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const auto p = v.GridToWorld({double(i), double(j), double(k)});
        const double w = -60 - p[0], vv = p[1] - 20, u = p[2] - 40;
        const double r = std::hypot(u, vv);
        // Signed distances (> 0 inside): elliptic wall (first order), vault floor, concave face
        // (a sphere of radius Rc centred Rc above the face centre), pilot hole.
        const double q = std::hypot(u / a, vv / b);
        const double g = q > 1e-9 ? std::hypot(u / (a * a), vv / (b * b)) / q : 1 / b;
        const double wall = (1 - q) / g;
        const double floor = w + H;
        const double face = std::sqrt(r * r + (w - Rc) * (w - Rc)) - Rc;
        const double hole = std::max(r - rp, -Dp - w);
        const double d = std::min({wall, floor, face, hole});
        fill[v.Index(i, j, k)] =
            bm::Voxmap::Fill(std::clamp(0.5 + d / h, 0.0, 1.0) * bm::Voxmap::kFull);
      }
  v.RebuildOccupancy();
  return v;
}
#endif

/// The scene's bone (bm::MakeSceneBone; without BMIO, the glenoid phantom's analytic bone).
bm::Voxmap SceneBone(const bm::Scene& scene) {
#ifndef BM_WITH_IO
  if (scene.bone.type != "block" && scene.bone.ct.value("phantom", "") == "glenoid")
    return AnalyticGlenoid(scene.voxmapResolution);
#endif
  return bm::MakeSceneBone(scene);
}

#ifdef BM_WITH_REPORT
/// One scripted session of the scene, with or without the live view refreshing.
struct ViewRun {
  std::vector<double> refreshMs;   ///< refreshes while bone was cut
  std::vector<int> bricks;         ///< bricks re-extracted by those refreshes
  std::vector<double> patched;     ///< of those, bricks whose triangles stayed (patched in place)
  std::vector<double> surfaceless; ///< of those, bricks with no triangles before or after
  std::vector<double> extractedTriangles;    ///< the triangles those bricks hold now
  std::vector<double> extractMs, assembleMs; ///< their parts (bm::BoneSurface::UpdateStats)
  std::vector<double> cpuMs;   ///< the view thread's CPU time in those refreshes (wall time less
                               ///< what other processes took of its core)
  std::vector<double> pending; ///< changed bricks each left for the next
  double firstMs = 0;          ///< the first refresh (the whole surface)
  int refreshes = 0;           ///< all refreshes after the first
  double cutS = 0;             ///< wall time from the first to the last cutting refresh
  bm::TimingStats haptic;      ///< the session's frame time
  double removedMm3 = 0;
  vtkIdType triangles = 0; ///< of the final surface
};

/// Runs the scene's scripted feed trial as vtkBMSessionSource runs it (position-source limits,
/// scripted feed, frames back to back unless realTime) and, when view, refreshes the surface
/// from the live bone every intervalMs on this thread (BoneSurface::Update then a shallow copy
/// into the port's polydata, the surface part of vtkBMSessionSource::RequestData). serialFrames >
/// 0: no second thread; the frames and the refreshes take turns on this one, a refresh after
/// every serialFrames frames (the view's own cost, the same bricks in every run).
ViewRun RunViewSession(const bm::Scene& scene, bool view, double intervalMs, bool realTime,
                       int64_t maxFrames, double budgetMs, int brick, int serialFrames) {
  bm::Voxmap bone = SceneBone(scene);
  bm::MachiningSetup setup(scene, std::move(bone));
  const bm::TrialSpec& t = scene.trial;
  const double depth = bm::TrialDepthMm(setup);
  const bm::FeedPath path(setup);
  int64_t frames = int64_t(std::ceil((depth + t.clearanceMm) / path.StepMm()));
  if (maxFrames > 0)
    frames = std::min(frames, maxFrames);

  // The haptic thread: the scene's scripted feed, one engine frame (collision, forces, removal)
  // per period, as the feed trial runs it; it never waits for the view.
  std::vector<double> frameMs;
  frameMs.reserve(size_t(frames));
  std::atomic<double> removedMm3{0};
  std::atomic<bool> finished{false};
  bm::Engine& engine = setup.GetEngine();
  double removedSoFar = 0; // the haptic thread's own sum
  auto hapticFrame = [&](int64_t k) {
    const bm::FrameInput in = path.Frame(-t.clearanceMm + path.StepMm() * double(k + 1), k);
    const auto t0 = Clock::now();
    removedSoFar += engine.Step(in).removedVolumeMm3;
    frameMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    removedMm3.store(removedSoFar, std::memory_order_relaxed);
  };

  bm::BoneSurface surface(brick);
  surface.SetTimeBudgetMs(budgetMs);
  vtkNew<vtkPolyData> port;
  ViewRun r;
  double lastRemoved = 0;
  bool first = true;
  Clock::time_point firstCut, lastCut;
  // One refresh of the view, as the BM Session source's RequestData makes it.
  auto refresh = [&] {
    const double removed = removedMm3.load(std::memory_order_relaxed);
    const double c0 = ThreadCpuMs();
    const auto t0 = Clock::now();
    const int n = surface.Update(setup.Bone());
    port->ShallowCopy(surface.GetOutput());
    const auto t1 = Clock::now();
    const double ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    const double cpu = ThreadCpuMs() - c0;
    if (first) {
      r.firstMs = ms;
      first = false;
    } else {
      ++r.refreshes;
      if (removed > lastRemoved) {
        if (r.refreshMs.empty())
          firstCut = t0;
        lastCut = t1;
        r.refreshMs.push_back(ms);
        r.cpuMs.push_back(cpu);
        r.bricks.push_back(n);
        r.patched.push_back(surface.LastUpdate().patched);
        r.surfaceless.push_back(surface.LastUpdate().surfaceless);
        r.extractedTriangles.push_back(double(surface.LastUpdate().extractedTriangles));
        r.extractMs.push_back(surface.LastUpdate().extractMs);
        r.assembleMs.push_back(surface.LastUpdate().assembleMs);
        r.pending.push_back(surface.LastUpdate().pending);
      }
    }
    lastRemoved = removed;
  };

  if (serialFrames > 0) {
    // One thread: serialFrames haptic frames, then a refresh, and so on: every run refreshes
    // after the same frames, so two builds re-extract the same bricks and nothing else competes.
    if (view)
      refresh();
    for (int64_t k = 0; k < frames; ++k) {
      hapticFrame(k);
      if (view && ((k + 1) % serialFrames == 0 || k + 1 == frames))
        refresh();
    }
  } else {
    std::thread haptic([&] {
      const auto start = Clock::now();
      for (int64_t k = 0; k < frames; ++k) {
        hapticFrame(k);
        if (realTime)
          std::this_thread::sleep_until(start +
                                        std::chrono::duration<double>(t.frameS * double(k + 1)));
      }
      finished.store(true);
    });
    const auto period = std::chrono::microseconds(int64_t(intervalMs * 1000));
    while (true) {
      const auto next = Clock::now() + period;
      const bool done = finished.load();
      if (view)
        refresh();
      if (done)
        break;
      std::this_thread::sleep_until(next);
    }
    haptic.join();
  }
  r.removedMm3 = removedMm3.load();
  std::sort(frameMs.begin(), frameMs.end());
  r.haptic.frames = int64_t(frameMs.size());
  r.haptic.p50Ms = bm::Percentile(frameMs, 50);
  r.haptic.p99Ms = bm::Percentile(frameMs, 99);
  r.haptic.maxMs = frameMs.empty() ? 0 : frameMs.back();
  for (double x : frameMs)
    r.haptic.meanMs += x / double(frameMs.size());
  if (view) {
    surface.Update(setup.Bone());
    r.triangles = surface.GetOutput()->GetNumberOfCells();
    r.cutS = std::chrono::duration<double>(lastCut - firstCut).count();
  }
  return r;
}

int ViewBench(const bm::cli::ParsedArgs& p) {
  using bm::cli::UsageError;
  const std::vector<int> voxmaps = Resolutions(p, "voxmaps", {192, 512});
  const int threads = int(p.GetInt("threads", 1, 64).value_or(1));
  const double interval = p.GetDouble("interval", 0, 10000).value_or(33.0);
  const int repeats = int(p.GetInt("repeats", 1, 100).value_or(1));
  const bool realTime = p.Has("real-time");
  const int64_t frames = p.GetInt("frames", 1, 100000000).value_or(0);
  const double budget = p.GetDouble("budget", 0, 10000).value_or(8.0);
  const int brick = int(p.GetInt("brick", 2, 256).value_or(bm::Voxmap::kBrick));
  const int serial = int(p.GetInt("serial", 0, 1000000).value_or(0));
  const std::string sceneName = p.Get("scene", "glenoid");
  const std::string out = p.Get("out", "out/bench-view");
  const bm::Scene base = bm::ResolveScene(sceneName);
  std::ostringstream csv;
  // 0: the scene's shell scaled with the voxmap (bm::Scene::WithVoxmapResolution).
  const std::vector<int> shells = Resolutions(p, "shells", {0});
  csv << "voxmap,shell,run,view,refresh_ms_median,refresh_ms_p99,refresh_cpu_ms_median,fps_median,"
         "fps_p99,refreshes_cutting,refreshes_per_s,bricks_median,bricks_patched_median,"
         "bricks_surfaceless_median,triangles_extracted_median,pending_median,pending_max,"
         "extract_ms_median,assemble_ms_median,first_extract_ms,triangles,haptic_ms_mean,"
         "haptic_ms_p50,haptic_ms_p99,haptic_ms_max,haptic_frames,removed_mm3\n";
  std::cout << std::fixed << std::setprecision(2);
  std::cout << "live view of scene " << base.name << ": engine threads " << threads << ", "
            << (realTime ? "real-time 1 kHz" : "frames back to back") << ", refresh "
            << (serial > 0 ? "after every " + std::to_string(serial) + " frames on one thread"
                           : "every " + std::to_string(interval) + " ms")
            << ", extraction budget " << budget << " ms, bricks of " << brick
            << " voxels; machine: " << MachineName() << "\n";
  for (int v : voxmaps)
    for (int shellAsked : shells) {
      bm::SceneOverrides o;
      o.voxmapResolution = v;
      o.shellResolution = shellAsked; // 0: the scene's shell scaled with the voxmap
      o.threads = threads;
      const bm::Scene scene = bm::ApplyOverrides(base, o);
      const int shell = scene.shellResolution;
      for (int run = 1; run <= repeats; ++run)
        for (bool view : {false, true}) {
          const ViewRun r =
              RunViewSession(scene, view, interval, realTime, frames, budget, brick, serial);
          const double med = bm::Percentile(r.refreshMs, 50), p99 = bm::Percentile(r.refreshMs, 99);
          std::vector<double> bricks(r.bricks.begin(), r.bricks.end());
          std::cout << "voxmap " << v << " shell " << shell << " run " << run
                    << (view ? " view on: " : " view off: ");
          if (view)
            std::cout << "refresh median " << med << " ms, p99 " << p99 << " ms ("
                      << (med > 0 ? 1000 / med : 0) << " / " << (p99 > 0 ? 1000 / p99 : 0)
                      << " FPS; view thread CPU median " << bm::Percentile(r.cpuMs, 50) << " ms), "
                      << r.refreshMs.size() << " refreshes while cutting ("
                      << (r.cutS > 0 ? double(r.refreshMs.size()) / r.cutS : 0.0)
                      << " per s), bricks median " << bm::Percentile(bricks, 50) << " ("
                      << bm::Percentile(r.extractedTriangles, 50)
                      << " triangles; patched in place median " << bm::Percentile(r.patched, 50)
                      << ", of them with no surface " << bm::Percentile(r.surfaceless, 50)
                      << "), left pending median " << bm::Percentile(r.pending, 50) << " max "
                      << bm::Percentile(r.pending, 100) << "; extract median "
                      << bm::Percentile(r.extractMs, 50) << " ms, assemble median "
                      << bm::Percentile(r.assembleMs, 50) << " ms; first " << r.firstMs << " ms, "
                      << r.triangles << " triangles; ";
          std::cout << "haptic mean " << r.haptic.meanMs << " ms, p50 " << r.haptic.p50Ms
                    << " ms, p99 " << r.haptic.p99Ms << " ms, max " << r.haptic.maxMs << " ms over "
                    << r.haptic.frames << " frames; removed " << r.removedMm3 << " mm^3\n"
                    << std::flush;
          csv << v << "," << shell << "," << run << "," << (view ? 1 : 0) << "," << med << ","
              << p99 << "," << bm::Percentile(r.cpuMs, 50) << "," << (med > 0 ? 1000 / med : 0)
              << "," << (p99 > 0 ? 1000 / p99 : 0) << "," << r.refreshMs.size() << ","
              << (r.cutS > 0 ? double(r.refreshMs.size()) / r.cutS : 0.0) << ","
              << bm::Percentile(bricks, 50) << "," << bm::Percentile(r.patched, 50) << ","
              << bm::Percentile(r.surfaceless, 50) << ","
              << bm::Percentile(r.extractedTriangles, 50) << "," << bm::Percentile(r.pending, 50)
              << "," << bm::Percentile(r.pending, 100) << "," << bm::Percentile(r.extractMs, 50)
              << "," << bm::Percentile(r.assembleMs, 50) << "," << r.firstMs << "," << r.triangles
              << "," << r.haptic.meanMs << "," << r.haptic.p50Ms << "," << r.haptic.p99Ms << ","
              << r.haptic.maxMs << "," << r.haptic.frames << "," << r.removedMm3 << "\n";
        }
    }
  std::filesystem::create_directories(out);
  bm::WriteFileAtomic(out + "/view.csv", csv.str());
  std::cout << "wrote " << out << "/view.csv\n";
  return 0;
}
#endif // BM_WITH_REPORT

/// One hand-like session trial's figures.
struct SessionRun {
  std::vector<double> frameMs, contactMs; ///< every frame; the frames touching bone
  int64_t over = 0;                       ///< frames over the period
  int64_t rulePauses = 0; ///< pauses the default overrun rule (> 5 of 100 frames) would make
  double removedMm3 = 0, sumThrustN = 0, sumProxyMm = 0, sumForceN = 0;
  Eigen::Vector3d lastProxy = Eigen::Vector3d::Zero();
  bm::Scene used;         ///< the scene at the resolutions and threads the session ran
  std::string gridReason; ///< how they were chosen ("" when given)
  std::string engine;     ///< the engine that ran it (bm::Engine::Name())
};

/// The scripted hand pushes pushN (N, at the device, scaled by the tool's force scale)
/// along -axis from the scene's clearance above its entry point; the session runs `seconds` (s)
/// of frames; candidates: the incremental path (the proxy's contact candidates and the engine's
/// incremental pass) or the full pass (every contact query scans the shell, the engine visits
/// every element of the blocks not culled); choose: the resolutions and threads a session chooses
/// (bmSessionGrid.h), else the scene's.
SessionRun RunHandSession(const bm::Scene& scene, bool choose, bool candidates, double pushN,
                          double tremorN, double seconds, bool realTime, double viewIntervalMs,
                          int64_t checksumFrames, const std::string& clDevice) {
  // A hand on a Touch pushing through the tool's force scale, counting its overruns.
  bm::SessionRequest req;
  req.mode = bm::ScriptMode::Hand;
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
                                          : bm::BuildSession(scene, SceneBone(scene), req);
  const std::shared_ptr<bm::Device>& device = built.device;
  bm::MachiningSetup& setup = *built.setup;
  bm::SessionOptions o = built.options;
  o.recordCapacity = size_t(o.maxFrames) + 16;
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
  return r;
}

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
  const std::string clName = std::find(backends.begin(), backends.end(), "opencl") != backends.end()
                                 ? OpenCLDeviceName(clDevice)
                                 : std::string();
  if (!clName.empty())
    std::cout << "OpenCL device: " << clName << "\n";
  char date[16] = "";
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
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
    bm::cli::WriteSessionAccuracy(scenes.front(), rows, views.back(), int(*reference), SceneBone,
                                  out, machine, date);
  return 0;
}

void BenchOptions(bm::cli::ParsedArgs& p) {
  p.Value("out", "DIR",
          "output folder (default out/bench; --view: out/bench-view; --session: "
          "out/bench-session, writing session.csv): bench.csv, table1.md (ours), table2.md "
          "(Zheng's), speed_vs_accuracy.png")
      .Flag("quick", "small subset, fewer frames (< 1 min): shells 128,256, voxmap 128, 200 "
                     "frames after 20 warm-up frames")
      .Value("methods", "LIST", "lazar,zheng (default both)")
      .Value("backends", "LIST", "cpu,opencl (default both; --session: cpu)")
      .Value("shells", "LIST",
             "point-shell resolutions, each in [8, 4096] (default 128,256,512,1024,2048; --view: "
             "the scene's shell scaled with each voxmap)")
      .Value("voxmaps", "LIST",
             "voxmap resolutions, each in [8, 4096] (default 128,256,512,1024; --view: 192,512; "
             "--session: those a session chooses; each given: the shell scaled alike)")
      .Int("frames", 1, 100000000,
           "timed frames per cell, at most 1000000 (default 1000); --view: stop after N haptic "
           "frames (default: the scene's whole trial)")
      .Int("warmup", 0, 1000000, "untimed frames first (default 100)")
      .Int("threads", 1, 64,
           "CPU backend threads (default 2; --view: engine threads, default 1; --session: "
           "default those a session chooses, else the scene's)")
      .Value("cl-device", "D", "the OpenCL device, its number or part of its name (bmsim devices)")
      .Flag("cl-host-bone",
            "OpenCL cells keep the host's copy of the cut bone current every frame, as a session "
            "does (default: the device alone holds it, as the paper measures the engine)")
      .Real("cell-limit", 1, 86400, "S", "stop a cell after S seconds (default 600)")
      .Value("replot", "CSV,...",
             "run nothing: merge saved bench.csv files (a later file's cell replaces an earlier "
             "one's) and write the tables and the chart from them")
      .Value("machine", "TEXT",
             "--replot: the machine the cells were measured on, for the tables' note (default: "
             "this one)")
      .Flag("view", "instead: the live view of the cut bone while a scene is reamed (below)")
      .Value("scene", "NAME|FILE",
             "--view: the scene (default glenoid; in builds without CT import, the glenoid "
             "phantom's analytic bone is sampled straight into the voxmap)")
      .Real("interval", 0, 10000, "MS", "--view: refresh period, ms (default 33; 0 = back to back)")
      .Int("repeats", 1, 100,
           "--view: runs per voxmap and mode (default 1); --session: runs of "
           "each path (default 2)")
      .Flag("real-time", "--view: the haptic thread at the scene's frame rate (1 kHz, sleeping "
                         "between frames) instead of back to back")
      .Real("budget", 0, 10000, "MS",
            "--view: the surface's extraction time budget per refresh, ms (default 8, as the BM "
            "Session source; 0 = every changed brick every refresh)")
      .Int("brick", 2, 256, "--view: the surface's brick edge, voxels (default 8)")
      .Int("serial", 0, 1000000,
           "--view: one thread, no contention: K haptic frames, then a refresh, in turn (default "
           "0: the haptic thread and the view run side by side)")
      .Int("accuracy", 8, 4096,
           "--session: also the offline reaming trial at each voxmap measured and at this voxmap "
           "(the converged reference), its outcome against the reference's: "
           "session_accuracy.csv and session_speed_vs_accuracy.png (a reaming scene)")
      .Value("session", "NAME|FILE",
             "instead: the haptic session's frame time on a scene in a hand-like trial (below)")
      .Real("seconds", 0.01, 3600, "S", "--session: seconds of session time (default 20)")
      .Real("full-seconds", 0.01, 3600, "S",
            "--session: seconds of session time of the full pass (default: --seconds)")
      .Real("push", 0.01, bm::DeviceLimits().maxForceN, "N",
            "--session: the hand's steady push at the device, N (default 2.5), rising over 0.5 "
            "s; the tool gets the tool's force scale times it")
      .Real("tremor", 0, bm::DeviceLimits().maxForceN, "N",
            "--session: lateral tremor, N (default 0.1)")
      .Flag("back-to-back", "--session: no sleeping between frames")
      .Flag("with-view", "--session: each run also with the live view refreshing the cut bone's "
                         "surface every 33 ms on its own thread, as the BM Session source does")
      .Footer(
          "Default: sweeps the drilling scene with the lips fully engaged (block pre-cut to the "
          "tool's envelope): method x backend x point-shell resolution x voxmap resolution. Per "
          "cell: frame time median, p99 and sd over the timed frames after warm-up, peak memory "
          "of the cell's process, thrust and torque error against the edge quadrature. Each cell "
          "runs in its own child process.\n"
          "--view: a haptic thread runs the scene's scripted feed through the engine, once "
          "without and once with the view (bm::BoneSurface, as the BM Session source refreshes "
          "it) refreshing every --interval ms; prints the refresh time median and p99, the "
          "bricks re-extracted and pending, the first extraction and the haptic frame time with "
          "and without the view; writes view.csv.\n"
          "--session: the scripted hand on the scene's trial axis from its clearance, at 1 kHz; "
          "runs alternate between the incremental path (contact candidates that follow the "
          "shell's changes, the engine's incremental pass) and the full pass; prints frame p50 "
          "/ p99 / max (ms), frames over the period, the pauses the overrun rule (more than 5 of "
          "100 frames) would have made, and a checksum of forces and path over the frames both "
          "ran, the same for both when exact. Without --voxmaps and --threads it runs the "
          "resolutions and threads a session chooses (Docs/RealTime.md).");
}

int BenchCommand(const bm::cli::ParsedArgs& p) {
  using bm::cli::UsageError;
  if (!p.Positional().empty())
    throw UsageError("takes no positional arguments");
  if (p.Has("view")) {
#ifdef BM_WITH_REPORT
    return ViewBench(p);
#else
    throw UsageError("--view needs a build with VTK (the live view's surface)");
#endif
  }
  if (p.Has("session"))
    return SessionBench(p);
  bm::BenchOptions o;
  const bool quick = p.Has("quick");
  if (quick) {
    o.shells = {128, 256};
    o.voxmaps = {128};
    o.frames = 200;
    o.warmup = 20;
  }
  if (auto v = p.Get("methods")) {
    o.methods.clear();
    for (const auto& m : bm::SplitCommaList(*v)) {
      try {
        o.methods.push_back(bm::MethodFromString(m));
      } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--methods: ") + e.what());
      }
    }
  }
  if (auto v = p.Get("backends")) {
    o.backends = bm::SplitCommaList(*v);
    for (const auto& b : o.backends)
      if (b != "cpu" && b != "opencl")
        throw UsageError("--backends: '" + b + "' is not cpu or opencl");
  }
  o.shells = Resolutions(p, "shells", o.shells);
  o.voxmaps = Resolutions(p, "voxmaps", o.voxmaps);
  if (auto v = p.GetInt("frames", 1, 1000000))
    o.frames = int(*v);
  if (auto v = p.GetInt("warmup", 0, 1000000))
    o.warmup = int(*v);
  if (auto v = p.GetInt("threads", 1, 64))
    o.threads = int(*v);
  if (auto v = p.GetDouble("cell-limit", 1, 86400))
    o.cellLimitS = *v;
  o.device = p.Get("cl-device", "");
  o.deviceHeldBone = !p.Has("cl-host-bone");
  if (o.methods.empty() || o.backends.empty())
    throw UsageError("--methods and --backends need an entry");
  const std::string out = p.Get("out", "out/bench");

  std::vector<bm::BenchCell> cells;
  std::string framesNote;
  if (auto files = p.Get("replot")) {
    for (const auto& f : bm::SplitCommaList(*files)) {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(f, ec)) // a FIFO would block the read
        throw UsageError("--replot: " + f + " is not a regular file");
      std::ifstream in(f);
      if (!in)
        throw UsageError("--replot: cannot read " + f);
      std::stringstream text;
      text << in.rdbuf();
      for (const auto& c : bm::ParseBenchCsv(text.str(), f)) {
        auto same = [&](const bm::BenchCell& o) {
          return o.method == c.method && o.backend == c.backend && o.shell == c.shell &&
                 o.voxmap == c.voxmap;
        };
        cells.erase(std::remove_if(cells.begin(), cells.end(), same), cells.end());
        cells.push_back(c);
      }
    }
    o.methods.clear();
    o.backends.clear();
    o.shells.clear();
    o.voxmaps.clear();
    for (const auto& c : cells) {
      if (std::find(o.methods.begin(), o.methods.end(), c.method) == o.methods.end())
        o.methods.push_back(c.method);
      if (std::find(o.backends.begin(), o.backends.end(), c.backend) == o.backends.end())
        o.backends.push_back(c.backend);
      if (std::find(o.shells.begin(), o.shells.end(), c.shell) == o.shells.end())
        o.shells.push_back(c.shell);
      if (std::find(o.voxmaps.begin(), o.voxmaps.end(), c.voxmap) == o.voxmaps.end())
        o.voxmaps.push_back(c.voxmap);
    }
    std::sort(o.shells.begin(), o.shells.end());
    std::sort(o.voxmaps.begin(), o.voxmaps.end());
    framesNote = "timed frames per cell: the frames column of bench.csv";
  } else {
    framesNote = std::to_string(o.frames) + " timed frames per cell after " +
                 std::to_string(o.warmup) + " warm-up frames";
  }
  const size_t total = o.methods.size() * o.backends.size() * o.shells.size() * o.voxmaps.size();
  if (!p.Has("replot"))
    std::filesystem::create_directories(out);
  for (auto m : o.methods)
    for (const auto& be : o.backends)
      for (int s : o.shells)
        for (int v : o.voxmaps) {
          if (p.Has("replot"))
            continue;
          std::cout << "[" << cells.size() + 1 << "/" << total << "] " << bm::ToString(m) << " "
                    << be << " shell " << s << " voxmap " << v << ": " << std::flush;
          bm::BenchCell c = bm::RunBenchCellIsolated(m, be, s, v, o);
          if (c.status == "ok" && be == "opencl" && c.engine.rfind("opencl", 0) != 0)
            c.status = "no OpenCL (ran on " + c.engine + ")";
          if (c.status == "ok")
            std::cout << "median " << c.medianMs << " ms, p99 " << c.p99Ms << " ms, error "
                      << 100 * c.forceError << " %, " << c.peakMemoryMb << " MiB\n";
          else
            std::cout << c.status << "\n";
          cells.push_back(c);
          // The cells so far, after each: a sweep stopped part-way keeps what it measured.
          bm::WriteFileAtomic(out + "/bench.csv", bm::BenchCsv(cells));
        }

  std::filesystem::create_directories(out);
  const std::string machine = MachineName();
  std::ostringstream note;
  // Replotted cells were measured elsewhere: the machine and threads as the user names them.
  note << "\nMachine: " << p.Get("machine", machine) << "; " << framesNote;
  if (!p.Has("replot") || p.Has("threads"))
    note << "; CPU backend " << o.threads << " threads";
  if (std::find(o.backends.begin(), o.backends.end(), "opencl") != o.backends.end() &&
      !p.Has("replot"))
    note << "; OpenCL device " << OpenCLDeviceName(o.device)
         << (o.deviceHeldBone ? ", the cut bone held on the device"
                              : ", the host's copy of the cut bone kept current every frame");
  note << ".\n";
  bm::WriteFileAtomic(out + "/bench.csv", bm::BenchCsv(cells));
  bm::WriteFileAtomic(out + "/table1.md",
                      bm::BenchTable(cells, bm::Method::Lazar,
                                     "Ours (VPS, Lazar forces): frame time", o.shells, o.voxmaps) +
                          note.str());
  bm::WriteFileAtomic(out + "/table2.md",
                      bm::BenchTable(cells, bm::Method::Zheng,
                                     "Zheng et al. (octree, buffer + reduction): frame time",
                                     o.shells, o.voxmaps) +
                          note.str());
#ifdef BM_WITH_CHARTS
  std::vector<bm::ChartSeries> series;
  for (auto m : o.methods)
    for (const auto& be : o.backends) {
      bm::ChartSeries s;
      s.name = bm::ToString(m) + " / " + be;
      for (const auto& c : cells)
        if (c.method == m && c.backend == be && c.status == "ok")
          s.points.push_back(
              {c.p99Ms, c.forceError, std::to_string(c.shell) + "/" + std::to_string(c.voxmap)});
      if (!s.points.empty())
        series.push_back(s);
    }
  bm::WriteSpeedAccuracyChart(
      out + "/speed_vs_accuracy.png",
      "Frame time (p99) against force error; labels: point shell / voxmap resolution", series);
  std::cout << "wrote " << out << "/bench.csv, table1.md, table2.md, speed_vs_accuracy.png\n";
#else
  std::cout << "wrote " << out
            << "/bench.csv, table1.md, table2.md (no chart: this build has no "
               "VTK; bmsim bench --replot draws it on a full build)\n";
#endif
  return 0;
}

} // namespace

BM_REGISTER_COMMAND(
    bench, "frame time against force error over the resolution grid (bench.csv, tables, chart)",
    BenchOptions, BenchCommand);
