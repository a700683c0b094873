// bmsim bench - frame time against force error over the paper's resolution grid (issue 3).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include "bmAtomicFile.h"
#include "bmBenchmark.h"
#include "bmSpeedAccuracyChart.h"
#include "bmsimArgs.h"
#include "bmsimCommand.h"

namespace {

const char* kUsage = R"(usage: bmsim bench [options]
  Sweeps the drilling scene with the lips fully engaged (block pre-cut to the tool's envelope):
  method x backend x point-shell resolution x voxmap resolution. Per cell: frame time median,
  p99 and sd over the timed frames after warm-up, peak memory of the cell's process, thrust and
  torque error against the edge quadrature. Each cell runs in its own child process.
  --out DIR              output folder (default out/bench): bench.csv, table1.md (ours),
                         table2.md (Zheng's), speed_vs_accuracy.png
  --quick                small subset, fewer frames (< 1 min): shells 128,256, voxmap 128,
                         200 frames after 20 warm-up frames
  --methods LIST         lazar,zheng (default both)
  --backends LIST        cpu,opencl (default both)
  --shells LIST          point-shell resolutions (default 128,256,512,1024,2048)
  --voxmaps LIST         voxmap resolutions (default 128,256,512,1024)
  --frames N             timed frames per cell (default 1000)
  --warmup N             untimed frames first (default 100)
  --threads N            CPU backend threads (default 2)
  --device D             OpenCL device (bmsim devices)
  --cell-limit S         stop a cell after S seconds (default 600)
  --replot CSV,...       run nothing: merge saved bench.csv files (a later file's cell replaces
                         an earlier one's) and write the tables and the chart from them
)";

std::vector<std::string> Split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty())
      out.push_back(item);
  return out;
}

std::vector<int> Resolutions(const bm::cli::ParsedArgs& p, const std::string& name,
                             std::vector<int> def) {
  const auto v = p.Get(name);
  if (!v)
    return def;
  std::vector<int> out;
  for (const auto& s : Split(*v)) {
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

int BenchCommand(const bm::cli::Args& args) {
  using bm::cli::UsageError;
  bm::cli::ParsedArgs p(args,
                        {"out", "methods", "backends", "shells", "voxmaps", "frames", "warmup",
                         "threads", "device", "cell-limit", "replot"},
                        {"quick", "help"});
  if (p.Has("help")) {
    std::cout << kUsage;
    return 0;
  }
  if (!p.Positional().empty())
    throw UsageError(std::string("takes no positional arguments\n") + kUsage);
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
    for (const auto& m : Split(*v)) {
      try {
        o.methods.push_back(bm::MethodFromString(m));
      } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--methods: ") + e.what());
      }
    }
  }
  if (auto v = p.Get("backends")) {
    o.backends = Split(*v);
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
  o.device = p.Get("device", "");
  if (o.methods.empty() || o.backends.empty())
    throw UsageError("--methods and --backends need an entry");
  const std::string out = p.Get("out", "out/bench");

  std::vector<bm::BenchCell> cells;
  std::string framesNote;
  if (auto files = p.Get("replot")) {
    for (const auto& f : Split(*files)) {
      std::ifstream in(f);
      if (!in)
        throw UsageError("--replot: cannot read " + f);
      std::stringstream text;
      text << in.rdbuf();
      for (const auto& c : bm::ParseBenchCsv(text.str())) {
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
        }

  std::filesystem::create_directories(out);
  const std::string machine = MachineName();
  std::ostringstream note;
  note << "\nMachine: " << machine << "; " << framesNote << "; CPU backend " << o.threads
       << " threads.\n";
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
  return 0;
}

} // namespace

BM_REGISTER_COMMAND(
    bench, "frame time against force error over the resolution grid (bench.csv, tables, chart)",
    BenchCommand);
