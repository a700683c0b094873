// bmPanelLogic.cxx - see bmPanelLogic.h.
#include "bmPanelLogic.h"

#include "bmRegularFile.h"

#include "bmBenchmark.h"
#include "bmCTFileTypes.h"
#include "bmHapticSession.h"
#include "bmScene.h"
#include "bmSessionBenchTable.h"
#include "bmSessionGrid.h"
#include "bmVTKImageVolume.h"
#include "bmVirtualCoupling.h"
#include "vtkBMSessionSource.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

namespace bm::PanelLogic {

namespace {
std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}
} // namespace

std::string ParameterLabel(const std::string& key) {
  static const std::pair<const char*, const char*> units[] = {
      {"_mm", "mm"}, {"_deg", "deg"}, {"_rpm", "rpm"}, {"_n", "N"}};
  std::string words = key, unit;
  for (const auto& [suffix, name] : units) {
    const std::string s = suffix;
    if (words.size() > s.size() && words.compare(words.size() - s.size(), s.size(), s) == 0) {
      words.resize(words.size() - s.size());
      unit = name;
      break;
    }
  }
  std::replace(words.begin(), words.end(), '_', ' ');
  if (!words.empty())
    words[0] = char(std::toupper(static_cast<unsigned char>(words[0])));
  return unit.empty() ? words : words + " (" + unit + ")";
}

std::string ParameterToolTip(const std::string& key) {
  static const std::map<std::string, const char*> tips = {
      {"alpha_deg", "Angle of the reamer's lips to the face, deg"},
      {"arc_centre_offset_mm", "Distance of the lip arc's centre from the axis, mm"},
      {"arc_radius_mm", "Radius of the lips' arc, mm"},
      {"chisel_angle_deg", "Drill chisel edge angle, deg"},
      {"flute_length_mm", "Length of the drill's flutes, mm"},
      {"head_thickness_mm", "Axial thickness of the reamer head behind its rim, mm"},
      {"helix_angle_deg", "Drill helix angle, deg"},
      {"lips", "Number of cutting lips (flutes)"},
      {"nipple_length_mm", "How far the guide nipple reaches beyond the face, mm (0 = no nipple)"},
      {"nipple_radius_mm", "Radius of the central guide nipple, mm (0 = none)"},
      {"outer_radius_mm", "Outer radius where the lips end, mm (half the diameter)"},
      {"point_angle_deg", "Drill point angle, deg"},
      {"radius_mm", "Burr radius, mm"},
      {"rake_deg", "Normal rake angle of the lips, deg"},
      {"shaft_length_mm", "Modelled length of the shaft behind the head, mm"},
      {"shaft_radius_mm", "Radius of the shaft, mm"},
      {"web_half_width_mm", "Half the drill's web thickness at the point, mm"}};
  const auto it = tips.find(key);
  return it != tips.end() ? it->second : "Tool parameter: " + ParameterLabel(key);
}

std::string CTFileFilter() {
  std::string patterns;
  for (const auto* list : {&CTFileExtensions(), &VTKImageExtensions()})
    for (const std::string& ext : *list)
      patterns += (patterns.empty() ? "*" : " *") + ext;
  return "CT volumes (" + patterns + ");;All files (*)";
}

std::string WithVoxmapExtension(const std::string& path, const std::string& defaultSuffix) {
  // Only a name with no extension at all gets one: another extension is the user's choice, and
  // the save refuses it naming the formats.
  if (path.empty() || std::filesystem::path(path).has_extension())
    return path;
  return path + "." + defaultSuffix;
}

std::string ParsePoints(const std::string& text, std::vector<double>& xyz) {
  xyz.clear();
  std::vector<double> points;
  std::istringstream list(text);
  std::string point;
  for (int index = 1; std::getline(list, point, ';'); ++index) {
    std::string blanks = point;
    std::replace(blanks.begin(), blanks.end(), ',', ' ');
    if (blanks.find_first_not_of(" \t\r\n") == std::string::npos) {
      if (text.find_first_not_of(" \t\r\n;") == std::string::npos)
        continue; // no points at all
      return "point " + std::to_string(index) + " is empty: give three numbers x y z (mm)";
    }
    std::istringstream numbers(blanks);
    double v[3];
    std::string extra;
    if (!(numbers >> v[0] >> v[1] >> v[2]) || (numbers >> extra) || !std::isfinite(v[0]) ||
        !std::isfinite(v[1]) || !std::isfinite(v[2]))
      return "point " + std::to_string(index) + " ('" + point + "'): give three numbers x y z (mm)";
    points.insert(points.end(), v, v + 3);
  }
  xyz = std::move(points);
  return "";
}

std::string StateText(SessionState state, const std::string& pauseReason) {
  switch (state) {
  case SessionState::Running:
    return "running";
  case SessionState::Paused:
    return pauseReason.empty() ? "paused" : "paused: " + pauseReason;
  case SessionState::Stopped:
    return "stopped";
  case SessionState::Idle:
    break;
  }
  return "";
}

bool IsPaused(SessionState state) {
  return state == SessionState::Paused;
}

bool IsActive(SessionState state) {
  return state == SessionState::Running || state == SessionState::Paused;
}

double MinForceScale() {
  return 1e-3;
}
double MaxForceScale() {
  return kMaxForceScale;
}
double DefaultForceScale() {
  return 0.0;
}

std::string ForceScaleError(double scale) {
  if (scale == 0)
    return ""; // the tool's
  try {
    CheckForceScale(scale);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

ExpectedCost::ExpectedCost() {
  try {
    this->Table_ = BenchmarkTable::Load(BenchmarkTable::DefaultPath());
  } catch (const std::exception& e) {
    this->Error_ = e.what();
  }
  const std::string sessions = DefaultSessionBenchPath();
  if (NotARegularFile(sessions) != "missing or unreadable") {
    try {
      // A FIFO, /dev/zero or a /proc file as the table would block the panel or never end.
      this->Sessions_ = ParseSessionBenchCsv(
          ReadRegularFile(sessions, uint64_t(64) << 20, "the session table"), sessions);
    } catch (const std::exception& e) {
      this->Error_ = e.what(); // a damaged table is named, not ignored
      this->Table_.reset();
    }
  }
  // Without the accuracy table (missing or damaged) the line leaves the accuracy out.
  this->Accuracy_ = LoadDefaultSessionAccuracy();
}

ExpectedCost::~ExpectedCost() = default;
ExpectedCost::ExpectedCost(ExpectedCost&&) noexcept = default;
ExpectedCost& ExpectedCost::operator=(ExpectedCost&&) noexcept = default;

ExpectedCost::ExpectedCost(BenchmarkTable table, std::vector<SessionBenchRow> sessions,
                           std::vector<SessionAccuracyRow> accuracy)
    : Table_(std::move(table)), Sessions_(std::move(sessions)), Accuracy_(std::move(accuracy)) {}

std::string ExpectedCost::Line(const std::string& sceneName, int voxmap, int shell, int method,
                               double periodMs) const {
  if (!this->Table_)
    return "No measured costs: " + this->Error_;
  Scene scene;
  try {
    const auto builtin = Scene::BuiltinNames();
    scene = std::find(builtin.begin(), builtin.end(), sceneName) != builtin.end()
                ? Scene::Builtin(sceneName)
                : Scene::Load(sceneName);
    // The resolutions a session runs at (vtkBMSessionSource: a voxmap set alone scales the
    // scene's shell alike).
    if (voxmap > 0 && shell <= 0)
      scene = scene.WithVoxmapResolution(voxmap);
  } catch (const std::exception& e) {
    return std::string("Expected cost unknown: ") + e.what();
  }
  // Neither set: the resolutions and threads the session chooses (bmSessionGrid.h) from the
  // measurements with the live view, else those without; a CT bone's spacing may lower them.
  int threads = 0;
  std::string chosen;
  if (voxmap <= 0 && shell <= 0)
    for (bool view : {true, false}) {
      const SessionGridPlan plan =
          PlanSessionGrid(scene, this->Sessions_, view, 1000.0 / periodMs, this->Accuracy_);
      if (plan.limit) {
        scene = plan.scene;
        threads = plan.scene.threads;
        chosen = ", chosen for the session (" + std::to_string(threads) + " engine thread" +
                 (threads == 1 ? "" : "s") + "; a CT bone's spacing may lower it)";
        break;
      }
    }
  const int v = voxmap > 0 ? voxmap : scene.voxmapResolution;
  const int s = shell > 0 ? shell : scene.shellResolution;
  const std::string name = method == vtkBMSessionSource::LAZAR   ? "lazar"
                           : method == vtkBMSessionSource::ZHENG ? "zheng"
                                                                 : ToString(scene.method);
  const BenchCell* cell = this->Table_->Nearest(name, scene.backend, s, v);
  if (!cell)
    return "Expected cost unknown: no " + name + " / " + scene.backend + " cell was measured";
  // The panel's session refreshes the live view: its measurements first, else those without.
  bool withView = true;
  auto session = name == ToString(scene.method)
                     ? NearestSessionCell(this->Sessions_, scene.name, v, s, withView,
                                          "incremental", 1.5, threads)
                     : std::nullopt;
  if (!session && name == ToString(scene.method)) {
    withView = false;
    session = NearestSessionCell(this->Sessions_, scene.name, v, s, withView, "incremental", 1.5,
                                 threads);
  }
  if (session) {
    // What the voxmap buys: the offline reaming trial at it against the converged reference.
    const std::string bought = AccuracyBought(this->Accuracy_, scene.name, v);
    const bool overruns = session->p99Ms > periodMs || session->overrunPauses > 0;
    return "Expected (" + scene.name + " session, shell " + std::to_string(s) + " / voxmap " +
           std::to_string(v) + chosen + ", nearest measured: " + std::to_string(session->shell) +
           " / " + std::to_string(session->voxmap) + ", hand-like trial" +
           (withView ? " with the live view" : " without the view") + " on " + session->machine +
           ", " + session->date + "): frame " + Format("%.3g", session->p50Ms) + " ms median, " +
           Format("%.3g", session->p99Ms) + " ms p99, " + Format("%.3g", session->maxMs) +
           " ms max; " + std::to_string(session->overrunPauses) + " overrun pauses in " +
           Format("%g", session->seconds) + " s; force error " +
           Format("%.2g", cell->forceError * 100.0) + " %" + (bought.empty() ? "" : "; " + bought) +
           (overruns ? "; over the " + Format("%g", periodMs) +
                           " ms period: expect overrun pauses, choose coarser resolutions"
                     : "");
  }
  return "Expected (" + name + ", shell " + std::to_string(s) + " / voxmap " + std::to_string(v) +
         ", nearest measured: " + std::to_string(cell->shell) + " / " +
         std::to_string(cell->voxmap) + "): frame " + Format("%.3g", cell->medianMs) +
         " ms median, " + Format("%.3g", cell->p99Ms) + " ms p99; force error " +
         Format("%.2g", cell->forceError * 100.0) + " %" +
         (cell->p99Ms > periodMs
              ? "; over the " + Format("%g", periodMs) +
                    " ms period: expect overrun pauses, choose coarser resolutions"
              : "");
}

} // namespace bm::PanelLogic
