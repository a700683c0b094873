// bmsimSessionAccuracy.cxx - see bmsimSessionAccuracy.h.
#include "bmsimSessionAccuracy.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "bmAtomicFile.h"
#include "bmSessionAccuracyTable.h"
#include "bmReamingAccuracy.h"
#ifdef BM_WITH_CHARTS
#include "bmSpeedAccuracyChart.h"
#endif

namespace bm::cli {

void WriteSessionAccuracy(const Scene& scene, const std::vector<SessionBenchRow>& rows, bool view,
                          int referenceVoxmap, const std::function<Voxmap(const Scene&)>& bone,
                          const std::string& out, const std::string& machine,
                          const std::string& date) {
  // Each voxmap's worst p99 on the incremental path, as the session table judges a cell.
  std::map<int, double> p99;
  for (const SessionBenchRow& r : rows)
    if (r.scene == scene.name && r.path == "incremental" && r.view == view)
      p99[r.voxmap] = std::max(p99[r.voxmap], r.p99Ms);
  if (p99.empty())
    throw std::runtime_error("--accuracy: no incremental-path cell of scene '" + scene.name +
                             "' was measured");
  // The glenoid phantom's bone has its guide-pin hole: the face's fit leaves it out.
  const ReamingOutcomeOptions options =
      scene.bone.type == "ct" && scene.bone.ct.value("phantom", "") == "glenoid"
          ? GlenoidPhantomOutcomeOptions()
          : ReamingOutcomeOptions();
  auto trial = [&](int v) {
    const Scene s = scene.WithVoxmapResolution(v);
    std::cout << "accuracy: the offline trial at voxmap " << v << ", shell " << s.shellResolution
              << "..." << std::flush;
    ReamingTrialOutcome t = RunReamingTrial(s, bone(s), options);
    std::cout << " " << std::fixed << std::setprecision(1) << t.seconds << " s\n";
    return t;
  };
  const ReamingTrialOutcome reference = trial(referenceVoxmap);
  std::string csv = SessionAccuracyCsvHeader() + "\n";
#ifdef BM_WITH_CHARTS
  // x: the frame p99 (ms), y: the relative removed-volume error, labelled with every error.
  ChartSeries series;
  series.name = scene.name + " session" + (view ? ", view on" : "");
#endif
  auto row = [&](const ReamingTrialOutcome& t, double p99Ms) {
    const ReamingAccuracy a = CompareReamingOutcomes(t.outcome, reference.outcome);
    SessionAccuracyRow r;
    r.scene = scene.name;
    r.voxmap = t.voxmap;
    r.shell = t.shell;
    r.voxelMm = t.voxelMm;
    r.view = view;
    r.p99Ms = p99Ms;
    r.removedMm3 = t.outcome.removedMm3;
    r.faceDepthMm = t.outcome.faceDepthMm;
    r.faceAngleDeg = t.outcome.faceAngleDeg;
    r.seating = t.outcome.seating;
    r.removedErrorPct = a.removedErrorPct;
    r.faceDepthErrorMm = a.depthErrorMm;
    r.faceErrorDeg = a.faceErrorDeg;
    r.seatingErrorPct = a.seatingErrorPct;
    r.referenceVoxmap = referenceVoxmap;
    r.referenceShell = reference.shell;
    r.trialS = t.seconds;
    r.machine = machine;
    r.date = date;
    csv += SessionAccuracyCsvRecord(r) + "\n";
    std::ostringstream line;
    line << std::fixed << std::setprecision(2) << t.voxmap << "/" << t.shell << " (" << t.voxelMm
         << " mm): removed " << std::showpos << a.removedErrorPct << " %, depth " << a.depthErrorMm
         << " mm, seating " << a.seatingErrorPct << " pp" << std::noshowpos << ", face "
         << a.faceErrorDeg << " deg";
    std::cout << "accuracy " << line.str();
    if (p99Ms > 0)
      std::cout << "; frame p99 " << std::setprecision(3) << p99Ms << " ms";
    std::cout << "\n";
#ifdef BM_WITH_CHARTS
    if (p99Ms > 0)
      series.points.push_back({p99Ms, std::abs(a.removedErrorPct) / 100.0, line.str()});
#endif
  };
  for (const auto& [v, ms] : p99)
    row(v == referenceVoxmap ? reference : trial(v), ms);
  if (p99.count(referenceVoxmap) == 0)
    row(reference, 0.0);
  WriteFileAtomic(out + "/session_accuracy.csv", csv);
  std::cout << "wrote " << out << "/session_accuracy.csv\n";
#ifdef BM_WITH_CHARTS
  WriteSpeedAccuracyChart(
      out + "/session_speed_vs_accuracy.png",
      "Session frame time (p99) against the result's accuracy; reference: voxmap " +
          std::to_string(referenceVoxmap) + "; labels: voxmap/shell (voxel): errors",
      {series}, 1000.0 * scene.trial.frameS, 1400, 900,
      "removed-volume error against the converged reference, relative (log)");
  std::cout << "wrote " << out << "/session_speed_vs_accuracy.png\n";
#endif
}

} // namespace bm::cli
