// BMBenchCells - the cells of `bmsim bench` (bm::RunBenchCellIsolated, one forked child per cell)
// without the chart, for builds without ParaView's VTK (bmsim bench needs BMCharts there). Writes
// bench.csv, table1.md and table2.md exactly as bmsim bench does; `bmsim bench --replot` merges
// the CSV with other runs and draws the chart on a full build.
//
// usage: BMBenchCells [--methods lazar,zheng] [--shells 128,...] [--voxmaps 128,...]
//                     [--threads N] [--frames N] [--warmup N] [--out DIR]
// Backend: cpu. Frame times in ms.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bmBenchmark.h"

namespace {

std::vector<int> Ints(const std::string& s) {
  std::vector<int> out;
  for (const auto& v : bm::SplitCommaList(s))
    out.push_back(std::stoi(v));
  return out;
}

} // namespace

int main(int argc, char** argv) {
  bm::BenchOptions o;
  o.backends = {"cpu"};
  std::string out = "out/bench-cells";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--methods") {
      o.methods.clear();
      for (const auto& m : bm::SplitCommaList(v))
        o.methods.push_back(bm::MethodFromString(m));
    } else if (k == "--shells")
      o.shells = Ints(v);
    else if (k == "--voxmaps")
      o.voxmaps = Ints(v);
    else if (k == "--threads")
      o.threads = std::stoi(v);
    else if (k == "--frames")
      o.frames = std::stoi(v);
    else if (k == "--warmup")
      o.warmup = std::stoi(v);
    else if (k == "--out")
      out = v;
    else {
      std::cerr << "unknown option " << k << "\n";
      return 2;
    }
  }
  std::vector<bm::BenchCell> cells;
  for (auto m : o.methods)
    for (int s : o.shells)
      for (int v : o.voxmaps) {
        std::cout << bm::ToString(m) << " cpu shell " << s << " voxmap " << v << " threads "
                  << o.threads << ": " << std::flush;
        const bm::BenchCell c = bm::RunBenchCellIsolated(m, "cpu", s, v, o);
        if (c.status == "ok")
          std::cout << "median " << c.medianMs << " ms, p99 " << c.p99Ms << " ms, max " << c.maxMs
                    << " ms, error " << 100 * c.forceError << " %, engaged " << c.engagedCutting
                    << ", elements " << c.elements << "\n";
        else
          std::cout << c.status << "\n";
        cells.push_back(c);
      }
  std::filesystem::create_directories(out);
  std::ostringstream note;
  note << "\n"
       << o.frames << " timed frames per cell after " << o.warmup << " warm-up frames; CPU backend "
       << o.threads << " threads; " << std::thread::hardware_concurrency() << " logical cores.\n";
  std::ofstream(out + "/bench.csv") << bm::BenchCsv(cells);
  std::ofstream(out + "/table1.md")
      << bm::BenchTable(cells, bm::Method::Lazar, "Ours (VPS, Lazar forces): frame time", o.shells,
                        o.voxmaps) +
             note.str();
  std::ofstream(out + "/table2.md")
      << bm::BenchTable(cells, bm::Method::Zheng,
                        "Zheng et al. (octree, buffer + reduction): frame time", o.shells,
                        o.voxmaps) +
             note.str();
  return 0;
}
