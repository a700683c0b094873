// bmTrialReport.cxx - see bmTrialReport.h.
#include "bmTrialReport.h"
#include "bmHtmlEscape.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>

#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLWriter.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLPolyDataWriter.h>

#include "bmAtomicFile.h"
#include "bmBoneSurface.h"
#include "bmEdgeQuadrature.h"
#include "bmReportCharts.h"

namespace bm {
namespace {

namespace fs = std::filesystem;

std::string CutName(const ToolModel& tool) {
  if (tool.Kind() == "reamer")
    return "reamed";
  if (tool.Kind() == "drill")
    return "drilled";
  return "cut";
}

/// World position of the tool frame's origin when the foremost cutting point is `depth` below
/// the entry point (as FeedTrial places it).
Eigen::Vector3d ToolPosition(MachiningSetup& setup, double depthMm) {
  const TrialSpec& t = setup.GetScene().trial;
  return t.entry - t.axis.normalized() * depthMm -
         setup.ToolRotation() * Eigen::Vector3d(0, 0, ForemostCuttingZ(setup.Tool()));
}

template <class Writer> void WriteVtk(const std::string& path, vtkPolyData* surface) {
  const std::string tmp = TemporarySibling(path);
  vtkNew<Writer> writer;
  writer->SetFileName(tmp.c_str());
  writer->SetInputData(surface);
  const int ok = writer->Write();
  std::error_code ec;
  if (!ok || writer->GetErrorCode() != 0 || !fs::exists(tmp)) {
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot write " + path);
  }
  fs::rename(tmp, path);
}

std::string Fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

} // namespace

vtkSmartPointer<vtkPolyData> CutBoneSurface(MachiningSetup& setup, const FeedTrial& trial) {
  BoneSurface extractor;
  extractor.Update(setup.Bone());
  vtkSmartPointer<vtkPolyData> surface = vtkSmartPointer<vtkPolyData>::New();
  surface->ShallowCopy(extractor.GetOutput());

  // A point is on the cut when it lies (within one voxel) on or above the cutting part of the
  // tool's outline at its final pose: everything the feed swept down to there is gone.
  const ToolModel& tool = setup.Tool();
  const Eigen::Matrix3d rot = setup.ToolRotation();
  const Eigen::Vector3d pos = ToolPosition(setup, trial.FinalDepthMm());
  double cutLo = tool.OuterRadius(), cutHi = 0;
  for (EdgeKind kind : {EdgeKind::Lip, EdgeKind::Chisel}) {
    const auto r = tool.EdgeRange(kind);
    if (r[1] > r[0]) {
      cutLo = std::min(cutLo, r[0]);
      cutHi = std::max(cutHi, r[1]);
    }
  }
  const double tol = setup.Bone().Spacing();
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  const vtkIdType n = surface->GetNumberOfPoints();
  colors->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i) {
    double p[3];
    surface->GetPoint(i, p);
    const Eigen::Vector3d local = rot.transpose() * (Eigen::Vector3d(p[0], p[1], p[2]) - pos);
    const double rho = std::hypot(local.x(), local.y());
    double zLo = 0, zHi = 0;
    bool cut = false;
    if (rho >= cutLo - tol && rho <= cutHi + tol) {
      const double r = std::clamp(rho, cutLo, cutHi);
      if (tool.ZRange(r, zLo, zHi))
        cut = local.z() >= zLo - tol;
    }
    const unsigned char bone[3] = {237, 227, 199}, reamed[3] = {92, 152, 214};
    const unsigned char* c = cut ? reamed : bone;
    colors->SetTypedTuple(i, c);
  }
  surface->GetPointData()->AddArray(colors);
  return surface;
}

SurfaceView TrialView(MachiningSetup& setup, int sizePx) {
  const TrialSpec& t = setup.GetScene().trial;
  const Eigen::Vector3d axis = t.axis.normalized();
  // Up: the world axis least aligned with the trial axis, made perpendicular to it.
  int best = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(axis[a]) <= std::abs(axis[best]))
      best = a;
  Eigen::Vector3d up = Eigen::Vector3d::Unit(best);
  up = (up - up.dot(axis) * axis).normalized();
  const double tilt = 20.0 * 3.14159265358979323846 / 180.0;
  const Eigen::Vector3d toCamera = (std::cos(tilt) * axis - std::sin(tilt) * up).normalized();
  const Box3 b = setup.Bone().Bounds();
  double extent = 0;
  for (int a = 0; a < 3; ++a)
    extent = std::max(extent, b.hi[a] - b.lo[a]);
  SurfaceView view;
  view.focalMm = {t.entry.x(), t.entry.y(), t.entry.z()};
  view.toCamera = {toCamera.x(), toCamera.y(), toCamera.z()};
  view.viewUp = {up.x(), up.y(), up.z()};
  view.halfHeightMm = 0.6 * extent;
  view.widthPx = view.heightPx = sizePx;
  return view;
}

TrialReportFiles WriteTrialReport(const std::string& dirName, MachiningSetup& setup,
                                  const FeedTrial& trial) {
  const fs::path dir(dirName);
  fs::create_directories(dir);
  const Scene& scene = setup.GetScene();
  const ToolModel& tool = setup.Tool();
  const std::string cut = CutName(tool);
  const nlohmann::json s = trial.Summary();
  TrialReportFiles files;

  // Surface and picture.
  vtkSmartPointer<vtkPolyData> surface = CutBoneSurface(setup, trial);
  files.surfaceVtp = (dir / (cut + ".vtp")).string();
  files.surfaceStl = (dir / (cut + ".stl")).string();
  files.image = (dir / (cut + ".png")).string();
  WriteVtk<vtkXMLPolyDataWriter>(files.surfaceVtp, surface);
  WriteVtk<vtkSTLWriter>(files.surfaceStl, surface);
  WriteSurfacePng(files.image, surface, TrialView(setup));

  // Charts over time.
  const auto& frames = trial.Frames();
  if (frames.empty())
    throw std::runtime_error("the trial has no frames to report");
  LineChart base;
  base.xLabel = "time (s)";
  for (const auto& f : frames)
    base.x.push_back(f.timeS);
  auto series = [&](const std::string& name, auto get, std::array<unsigned char, 3> rgb) {
    LineSeries c;
    c.name = name;
    c.rgb = rgb;
    for (const auto& f : frames)
      c.y.push_back(get(f));
    return c;
  };
  double removed = 0;
  std::vector<double> cumulative;
  for (const auto& f : frames)
    cumulative.push_back(removed += f.removedVolumeMm3);
  struct Chart {
    std::string file, title, yLabel;
    LineSeries data;
  };
  const Chart charts[] = {
      {"thrust.png", "Thrust (along the tool axis, resisting the feed)", "thrust (N)",
       series("thrust", [](const TrialFrame& f) { return f.thrustN; }, {214, 39, 40})},
      {"torque.png", "Torque (resisting the spindle)", "torque (N mm)",
       series("torque", [](const TrialFrame& f) { return f.torqueNmm; }, {31, 119, 180})},
      {"frame_time.png", "Engine time per haptic frame", "frame time (ms)",
       series("frame time", [](const TrialFrame& f) { return f.frameMs; }, {44, 160, 44})},
      {"removed_volume.png", "Removed bone volume", "removed volume (mm^3)",
       LineSeries{"removed volume", cumulative, {148, 103, 189}}},
  };
  for (const Chart& c : charts) {
    LineChart chart = base;
    chart.title = c.title;
    chart.yLabel = c.yLabel;
    chart.series = {c.data};
    const std::string path = (dir / c.file).string();
    WriteLineChartPng(path, chart);
    files.charts.push_back(path);
  }

  // Numbers.
  double peakThrust = 0, peakTorque = 0;
  for (const auto& f : frames) {
    peakThrust = std::max(peakThrust, f.thrustN);
    peakTorque = std::max(peakTorque, f.torqueNmm);
  }
  const double feedVelocity = scene.trial.feedMmPerRev * scene.trial.speedRpm / 60.0;
  const std::string phase = s["statistics_phase"] == "full_engagement"
                                ? "mean over full engagement"
                                : "mean over the last fifth of the travel";
  const Eigen::Vector3d& e = scene.trial.entry;
  const Eigen::Vector3d a = scene.trial.axis.normalized();
  std::vector<std::pair<std::string, std::string>> rows = {
      {"Removed bone volume", Fixed(s["removed_volume_mm3"].get<double>(), 1) + " mm^3"},
      {"Depth (foremost cutting point below the entry point)",
       Fixed(trial.FinalDepthMm(), 2) + " mm"},
      {"Entry point, axis (world)", "(" + Fixed(e.x(), 1) + ", " + Fixed(e.y(), 1) + ", " +
                                        Fixed(e.z(), 1) + ") mm, (" + Fixed(a.x(), 3) + ", " +
                                        Fixed(a.y(), 3) + ", " + Fixed(a.z(), 3) + ")"},
      {"Tool", tool.Kind() + ", " + std::to_string(tool.NumLips()) + " lips, diameter " +
                   Fixed(2 * tool.OuterRadius(), 2) + " mm"},
      {"Feed, spindle speed", Fixed(scene.trial.feedMmPerRev, 3) + " mm/rev at " +
                                  Fixed(scene.trial.speedRpm, 0) + " rpm (" +
                                  Fixed(feedVelocity, 3) + " mm/s)"},
      {"Thrust (" + phase + ")",
       Fixed(s["thrust_N"].get<double>(), 1) + " N (peak " + Fixed(peakThrust, 1) + " N)"},
      {"Torque (" + phase + ")",
       Fixed(s["torque_Nmm"].get<double>(), 0) + " N mm (peak " + Fixed(peakTorque, 0) + " N mm)"},
      {"Frame time p50 / p99 / max", Fixed(s["frame_ms_p50"].get<double>(), 3) + " / " +
                                         Fixed(s["frame_ms_p99"].get<double>(), 3) + " / " +
                                         Fixed(s["frame_ms_max"].get<double>(), 3) +
                                         " ms (period " + Fixed(scene.trial.frameS * 1000.0, 3) +
                                         " ms)"},
      {"Coefficients",
       setup.Model().Provenance().name +
           (setup.Model().Provenance().calibrated ? " (calibrated: fitted to measured forces)"
                                                  : " (not calibrated: an assumption)") +
           ": " + setup.Model().Provenance().source},
      {"Frames", std::to_string(frames.size())},
      {"Engine",
       s["engine"].get<std::string>() + ", " + std::to_string(scene.threads) + " threads"},
      {"Voxmap", "resolution " + std::to_string(scene.voxmapResolution) + ", voxel " +
                     Fixed(setup.Bone().Spacing(), 4) + " mm"},
      {"Point shell", "resolution " + std::to_string(scene.shellResolution) + ", spacing " +
                          Fixed(setup.Shell().Spacing(), 4) + " mm, " +
                          std::to_string(setup.Shell().Size()) + " elements"},
      {"Cut surface", std::to_string(surface->GetNumberOfCells()) + " triangles"},
  };
  const std::string title = "BoneMachining report: scene " + scene.name;
  const std::string note =
      "Forces use the coefficient set named above (Docs/Calibration.md says what each rests on); "
      "the phantom's cancellous bone is scaled by its material. Thrust and torque are the "
      "time-averaged "
      "values the haptic engine computes per frame. Depth is measured along the trial axis from "
      "the "
      "entry point to the tool's foremost cutting point. The surface is the voxmap's 0.5 fill "
      "fraction, so it is accurate to about half a voxel.";
  const std::string fileNames[] = {cut + ".vtp", cut + ".stl", "forces.csv", "summary.json"};

  std::ostringstream md;
  md << "# " << title << "\n\n";
  md << "| Quantity | Value |\n|---|---|\n";
  for (const auto& [k, v] : rows)
    md << "| " << k << " | " << v << " |\n";
  md << "\n" << note << "\n\n## The cut bone\n\n![" << cut << " bone](" << cut << ".png)\n\n";
  md << "## Over time\n\n";
  for (const Chart& c : charts)
    md << "![" << c.title << "](" << c.file << ")\n\n";
  md << "## Files\n\n";
  for (const auto& f : fileNames)
    md << "- [" << f << "](" << f << ")\n";
  files.markdown = (dir / "report.md").string();
  WriteFileAtomic(files.markdown, md.str());

  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << HtmlEscape(title)
       << "</title>\n<style>body{font-family:sans-serif;max-width:960px;margin:2em auto}"
          "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:4px "
          "8px;text-align:left}"
          "img{max-width:100%}</style></head><body>\n";
  html << "<h1>" << HtmlEscape(title)
       << "</h1>\n<table>\n<tr><th>Quantity</th><th>Value</th></tr>\n";
  for (const auto& [k, v] : rows)
    html << "<tr><td>" << HtmlEscape(k) << "</td><td>" << HtmlEscape(v) << "</td></tr>\n";
  html << "</table>\n<p>" << HtmlEscape(note) << "</p>\n<h2>The cut bone</h2>\n<img src=\"" << cut
       << ".png\" alt=\"" << cut << " bone\">\n<h2>Over time</h2>\n";
  for (const Chart& c : charts)
    html << "<img src=\"" << c.file << "\" alt=\"" << HtmlEscape(c.title) << "\">\n";
  html << "<h2>Files</h2>\n<ul>\n";
  for (const auto& f : fileNames)
    html << "<li><a href=\"" << f << "\">" << f << "</a></li>\n";
  html << "</ul>\n</body></html>\n";
  files.html = (dir / "report.html").string();
  WriteFileAtomic(files.html, html.str());
  return files;
}

} // namespace bm
