// bmsim bench - frame time against force error over the paper's resolution grid
// (Docs/Performance.md); with --view, the live view of the cut bone during a reaming session;
// with --session, a haptic session's frame time. Builds without ParaView's VTK (a Logic-only build
// for a GPU machine) have the grid and the session bench, without the chart and the view.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "bmAtomicFile.h"
#include "bmBenchmark.h"
#include "bmDevice.h"
#ifdef BM_WITH_CHARTS
#include "bmSpeedAccuracyChart.h"
#endif
#include "bmsimArgs.h"
#include "bmsimBenchSession.h"
#include "bmsimBenchSupport.h"
#include "bmsimBenchView.h"
#include "bmsimCommand.h"

namespace {

using bm::cli::MachineName;
using bm::cli::OpenCLDeviceName;
using bm::cli::Resolutions;
using bm::cli::SessionBench;
#ifdef BM_WITH_REPORT
using bm::cli::ViewBench;
#endif

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
      .Real("seconds", 0.01, 3600, "S",
            "--session: seconds of session time (default 20; a drill's scene 2)")
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
          "resolutions and threads a session chooses (Docs/RealTime.md). A drill's scene "
          "(--session drilling) instead pushes the drill through the plate in force mode (2 s "
          "unless --seconds) with the proxy's fast paths and their reference in turn; prints "
          "p50 / p99 / max and frames over the period for the whole run, the cut, 0.1 s either "
          "side of breakthrough and after; stops if their checksums differ; writes "
          "session_force.csv.");
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
