// bmSessionGrid.cxx - see bmSessionGrid.h.
#include "bmSessionGrid.h"

#include "bmRegularFile.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

namespace bm {

std::optional<SessionLimit> MeasuredSessionLimit(const std::vector<SessionBenchRow>& rows,
                                                 const std::string& sceneName, bool view,
                                                 double periodMs) {
  // Worst p99 per (voxmap, threads).
  std::map<std::pair<int, int>, const SessionBenchRow*> worst;
  for (const SessionBenchRow& r : rows) {
    if (r.scene != sceneName || r.path != "incremental" || r.view != view)
      continue;
    const SessionBenchRow*& w = worst[{r.voxmap, r.threads}];
    if (!w || r.p99Ms > w->p99Ms)
      w = &r;
  }
  if (worst.empty())
    return std::nullopt;
  // Per voxmap, the threads with the lowest worst p99.
  std::map<int, const SessionBenchRow*> best;
  for (const auto& [key, row] : worst) {
    const SessionBenchRow*& b = best[key.first];
    if (!b || row->p99Ms < b->p99Ms)
      b = row;
  }
  const SessionBenchRow* pick = nullptr;
  for (const auto& [voxmap, row] : best) // ascending voxmap: the finest that holds wins
    if (row->p99Ms <= periodMs)
      pick = row;
  SessionLimit l;
  l.holds = pick != nullptr;
  if (!pick)
    pick = best.begin()->second; // none holds: the coarsest measured
  l.voxmap = pick->voxmap;
  l.threads = pick->threads;
  l.p99Ms = pick->p99Ms;
  l.machine = pick->machine;
  l.date = pick->date;
  return l;
}

/// Largest session table read (bytes): the shipped one is a few KiB.
constexpr uint64_t kMaxSessionTableBytes = uint64_t(64) << 20;

std::vector<SessionBenchRow> LoadDefaultSessionTable(std::string* error) {
  // A FIFO, a device or /proc file as the table would block or never end: refused, named.
  return LoadOptionalTable<std::vector<SessionBenchRow>>(DefaultSessionBenchPath(),
                                                         kMaxSessionTableBytes, "session table",
                                                         ParseSessionBenchCsv, error);
}

SessionGridPlan PlanSessionGrid(const Scene& scene, const std::vector<SessionBenchRow>& table,
                                bool view, double rateHz,
                                const std::vector<SessionAccuracyRow>& accuracy) {
  SessionGridPlan p;
  p.scene = scene;
  const double periodMs = 1000.0 / rateHz;
  p.limit = MeasuredSessionLimit(table, scene.name, view, periodMs);
  std::ostringstream why;
  if (!p.limit) {
    why << "no session measurements of scene '" << scene.name << "'"
        << (view ? " with the live view" : "") << " on this machine: the scene's voxmap "
        << scene.voxmapResolution;
    p.reason = why.str();
    return p;
  }
  const SessionLimit& l = *p.limit;
  if (l.voxmap < scene.voxmapResolution)
    p.scene = scene.WithVoxmapResolution(l.voxmap);
  p.scene.threads = l.threads;
  why << "measured on " << l.machine << " (" << l.date << "): voxmap " << l.voxmap << " with "
      << l.threads << " engine thread" << (l.threads == 1 ? "" : "s") << " has frame p99 "
      << std::setprecision(3) << l.p99Ms << " ms" << (view ? " with the live view" : "")
      << (l.holds ? ", within " : ", over ") << periodMs << " ms";
  if (!l.holds)
    why << " (no measured voxmap holds the rate: expect overrun pauses)";
  if (const std::string bought = AccuracyBought(accuracy, scene.name, p.scene.voxmapResolution);
      !bought.empty())
    why << "; " << bought;
  p.reason = why.str();
  return p;
}

double ToolVoxelMm(double toolRadiusMm) {
  return 2.0 * toolRadiusMm / kVoxelsAcrossTool;
}

} // namespace bm
