// bmsimBenchView.cxx - bmsim bench --view: the live view of the cut bone while a scene is reamed
// (bmsimBenchView.h). Builds without VTK have no view, and this file is empty in them.
#ifdef BM_WITH_REPORT
#include "bmsimBenchView.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <thread>

#include <time.h>

#include <vtkNew.h>
#include <vtkPolyData.h>

#include "bmAtomicFile.h"
#include "bmBoneSurface.h"
#include "bmFeedTrial.h"
#include "bmTimingStats.h"
#include "bmMachiningSetup.h"
#include "bmScene.h"
#include "bmSceneOverrides.h"
#include "bmSessionBuilder.h"
#include "bmsimBenchSupport.h"
#include "bmsimCommand.h"

namespace bm::cli {

namespace {

using Clock = std::chrono::steady_clock;

/// CPU time of the calling thread, ms.
double ThreadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

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
  bm::Voxmap bone = BenchSceneBone(scene);
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

} // namespace

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

} // namespace bm::cli

#endif // BM_WITH_REPORT
