// TestGlenoidReaming - the glenoid reaming scene end to end: phantom DICOM -> voxmap -> reaming ->
// surface and report, checked against geometry computed without the voxmap.
//
// usage: TestGlenoidReaming WORK_DIR BASELINE_PNG VOXMAP_RESOLUTION SHELL_RESOLUTION
//
// 1. The glenoid phantom is written as a DICOM series and imported through the scene's CT path
//    (bm::MakeCTVoxmap), then the built-in glenoid scene (Resources/Scenes/glenoid.json: reamer fed
//    along the face axis to 2 mm below the face centre) runs as a feed trial, and the report is
//    written (bm::WriteTrialReport) into WORK_DIR/report.
// 2. Removed volume: the voxmap's removed volume must match the volume of the phantom's analytic
//    bone (bm::PhantomIsBone) inside the reamer's swept envelope at the final depth (every point
//    over the cutting face: rho within the lips' radial range and z above bm::ToolModel::ZRange's
//    lower end, in the tool frame), integrated by a midpoint grid of 0.05 mm, to within
//        tolerance = 0.5 voxel x pi R^2   (R the reamer's outer radius),
//    i.e. the cut's boundary placed within half a voxel over the reamer's face area. Sources of
//    the difference: CT sampling (0.5 mm, partial volume), segmentation, resampling into the
//    voxmap and removal at voxel resolution. The voxmap's bone inside the envelope before the cut
//    is checked against the same geometry and tolerance, so a failure says whether the import or
//    the removal is off. The removal needs the shell and voxmap grids about 2:1 (CTest runs
//    voxmap 96 / shell 170: 0.430 / 0.215 mm); with unaligned grids (e.g. 96 / 192) elements
//    straddling voxel columns leave partial voxels behind and ~14 % of the envelope stays.
// 3. Forces: every frame's thrust and torque finite, both positive in every frame that removed
//    bone, the mean over the statistics phase positive.
// 4. Picture: the cut bone rendered from outside along the axis (400 x 400) against BASELINE_PNG
//    with VTK's regression test (vtkTesting, threshold 0.15 as vtkRegressionTestImage). When the
//    baseline file does not exist the test writes it and fails, so a new baseline is a deliberate
//    commit.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkTesting.h>

#include "bmCTVoxmap.h"
#include "bmEdgeQuadrature.h"
#include "bmFeedTrial.h"
#include "bmGlenoidPhantomGeometry.h"
#include "bmMachiningSetup.h"
#include "bmScene.h"
#include "bmSurfaceImage.h"
#include "bmTrialReport.h"

namespace fs = std::filesystem;

namespace {

int failures = 0;

void Check(bool ok, const std::string& what) {
  std::cout << (ok ? "ok   " : "FAIL ") << what << "\n";
  if (!ok)
    ++failures;
}

/// The reamer's swept envelope at the final pose: tool pose and the lips' radial range.
struct Envelope {
  Eigen::Matrix3d rot;
  Eigen::Vector3d pos;
  double cutLo, cutHi;
  const bm::ToolModel* tool;
  /// True when world point p (mm) lies over the cutting face (swept by the feed).
  bool Contains(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d l = rot.transpose() * (p - pos);
    const double rho = std::hypot(l.x(), l.y());
    double zLo = 0, zHi = 0;
    return rho >= cutLo && rho <= cutHi && tool->ZRange(rho, zLo, zHi) && l.z() >= zLo;
  }
};

Envelope MakeEnvelope(bm::MachiningSetup& setup, double finalDepthMm) {
  const bm::ToolModel& tool = setup.Tool();
  const bm::TrialSpec& t = setup.GetScene().trial;
  Envelope e;
  e.tool = &tool;
  e.rot = setup.ToolRotation();
  e.pos = t.entry - t.axis.normalized() * finalDepthMm -
          e.rot * Eigen::Vector3d(0, 0, bm::ForemostCuttingZ(tool));
  e.cutLo = tool.OuterRadius();
  e.cutHi = 0;
  for (bm::EdgeKind kind : {bm::EdgeKind::Lip, bm::EdgeKind::Chisel}) {
    const auto r = tool.EdgeRange(kind);
    if (r[1] > r[0]) {
      e.cutLo = std::min(e.cutLo, r[0]);
      e.cutHi = std::max(e.cutHi, r[1]);
    }
  }
  return e;
}

/// Bone volume (mm^3) of a voxmap whose voxel centres lie in the envelope (diagnostics).
double VoxmapVolumeIn(const bm::Voxmap& bone, const Envelope& e) {
  double v = 0;
  const auto& d = bone.Dims();
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i) {
        const int64_t idx = bone.Index(i, j, k);
        if (bone.GetFill(idx) <= 0)
          continue;
        const auto w = bone.GridToWorld({double(i), double(j), double(k)});
        if (e.Contains({w[0], w[1], w[2]}))
          v += bone.Fraction(idx);
      }
  return v * bone.VoxelVolume();
}

/// Volume (mm^3) of the analytic phantom bone inside the envelope, by a midpoint grid of step h
/// (mm) in the tool frame. The voxmap is not used.
double IndependentRemovedVolume(const Envelope& e, double finalDepthMm, double h) {
  const bm::ToolModel& tool = *e.tool;
  const Eigen::Matrix3d& rot = e.rot;
  const Eigen::Vector3d& pos = e.pos;
  const double cutLo = e.cutLo, cutHi = e.cutHi;
  // Highest bone above the entry point along the axis: 10 mm covers the glenoid rim (6.3 mm).
  const double zTop = bm::ForemostCuttingZ(tool) + finalDepthMm + 10.0;
  const int n = int(std::ceil(cutHi / h));
  int64_t inside = 0;
  for (int ix = -n; ix < n; ++ix) {
    const double x = (ix + 0.5) * h;
    for (int iy = -n; iy < n; ++iy) {
      const double y = (iy + 0.5) * h;
      const double rho = std::hypot(x, y);
      double zLo = 0, zHi = 0;
      if (rho < cutLo || rho > cutHi || !tool.ZRange(rho, zLo, zHi))
        continue;
      for (double z = zLo + 0.5 * h; z < zTop; z += h) {
        const Eigen::Vector3d p = pos + rot * Eigen::Vector3d(x, y, z);
        inside += bmtest::GlenoidIsBone({p.x(), p.y(), p.z()});
      }
    }
  }
  return double(inside) * h * h * h;
}

} // namespace

int main(int argc, char* argv[]) {
  if (argc != 5) {
    std::cerr
        << "usage: TestGlenoidReaming WORK_DIR BASELINE_PNG VOXMAP_RESOLUTION SHELL_RESOLUTION\n";
    return 2;
  }
  const fs::path work = argv[1];
  const std::string baseline =
      fs::absolute(argv[2]).string(); // vtkTesting reads -V from its data root unless absolute
  const int voxmapResolution = std::stoi(argv[3]), shellResolution = std::stoi(argv[4]);
  std::error_code ec;
  fs::remove_all(work, ec);
  fs::create_directories(work);

  // Phantom DICOM -> the scene's CT path -> voxmap.
  const std::string dicom = (work / "dicom").string();
  bmtest::WriteGlenoidDicom(dicom);
  nlohmann::json j = bm::Scene::Builtin("glenoid").ToJson();
  j["bone"]["ct"] = {{"ct", dicom}};
  j["voxmap_resolution"] = voxmapResolution;
  j["shell_resolution"] = shellResolution;
  const bm::Scene scene = bm::Scene::FromJson(j);
  std::array<double, 3> centre, axisOut;
  bmtest::GlenoidFace(centre, axisOut);
  Check((scene.trial.entry - Eigen::Vector3d(centre[0], centre[1], centre[2])).norm() < 1e-9 &&
            (scene.trial.axis.normalized() - Eigen::Vector3d(axisOut[0], axisOut[1], axisOut[2]))
                    .norm() < 1e-9,
        "the glenoid scene reams at the phantom's face centre along its outward axis");
  bm::Voxmap bone = bm::MakeCTVoxmap(scene.bone.ct, "", scene.voxmapResolution);
  const double voxel = bone.Spacing();

  // Reaming -> outputs and report.
  const bm::Voxmap initial = bone;
  bm::MachiningSetup setup(scene, std::move(bone));
  bm::FeedTrial trial(setup);
  Check(trial.Run(), "the trial ran to its final depth");
  const std::string out = (work / "report").string();
  trial.WriteOutputs(out);
  const bm::TrialReportFiles files = bm::WriteTrialReport(out, setup, trial);
  const nlohmann::json s = trial.Summary();

  // Removed volume against the geometry; the voxmap's bone in the envelope before and after the
  // cut tells the import's share of a difference from the removal's.
  const Envelope envelope = MakeEnvelope(setup, trial.FinalDepthMm());
  const double removed = s["removed_volume_mm3"].get<double>();
  const double independent = IndependentRemovedVolume(envelope, trial.FinalDepthMm(), 0.05);
  const double R = setup.Tool().OuterRadius();
  const double tolerance = 0.5 * voxel * 3.14159265358979323846 * R * R;
  const double before = VoxmapVolumeIn(initial, envelope),
               after = VoxmapVolumeIn(setup.Bone(), envelope);
  std::cout << "voxmap bone in the envelope (voxel centres): " << before << " mm^3 before the cut, "
            << after << " mm^3 after; the engine's swept volume "
            << s["swept_volume_mm3"].get<double>() << " mm^3\n";
  Check(std::abs(before - independent) <= tolerance,
        "imported bone in the envelope " + std::to_string(before) + " mm^3 vs geometry " +
            std::to_string(independent) + " mm^3 (tolerance " + std::to_string(tolerance) +
            " mm^3)");
  std::ostringstream what;
  what << "removed volume " << removed << " mm^3 vs geometry " << independent
       << " mm^3 (difference " << removed - independent
       << " mm^3 = " << 100.0 * (removed - independent) / independent << " %, tolerance "
       << tolerance << " mm^3 at voxel " << voxel << " mm)";
  Check(independent > 0 && std::abs(removed - independent) <= tolerance, what.str());

  // Forces.
  bool finite = true, positive = true;
  int cutting = 0;
  for (const auto& f : trial.Frames()) {
    finite = finite && std::isfinite(f.thrustN) && std::isfinite(f.torqueNmm);
    if (f.removedVolumeMm3 > 0) {
      ++cutting;
      positive = positive && f.thrustN > 0 && f.torqueNmm > 0;
    }
  }
  Check(finite, "every frame's thrust and torque are finite");
  Check(cutting > 0 && positive, "thrust and torque positive in all " + std::to_string(cutting) +
                                     " frames that removed bone");
  Check(s["thrust_N"].get<double>() > 0 && s["torque_Nmm"].get<double>() > 0,
        "mean thrust " + std::to_string(s["thrust_N"].get<double>()) + " N and torque " +
            std::to_string(s["torque_Nmm"].get<double>()) + " N mm positive");

  // The reamer never engages every lip element here: the summary compares no partly engaged
  // mean with the fully engaged reference, and says so; it names the coefficient set.
  Check(s["statistics_phase"] == "last_fifth_of_travel" && s["error_reference"] == "none" &&
            s["thrust_error"].is_null() && s["torque_error"].is_null(),
        "partial engagement on a CT bone: no thrust_error against the fully engaged reference "
        "(thrust is " +
            std::to_string(s["thrust_fraction_of_full_engagement"].get<double>()) +
            " of the fully engaged)");
  Check(s["coefficients"]["name"] == setup.Model().Provenance().name &&
            s["coefficients"]["calibrated"].is_boolean(),
        "the summary names the coefficient set " + setup.Model().Provenance().name);

  // Report files.
  for (const std::string& f :
       {files.markdown, files.html, files.surfaceVtp, files.surfaceStl, files.image})
    Check(fs::exists(f) && fs::file_size(f) > 0, "wrote " + f);
  for (const std::string& f : files.charts)
    Check(fs::exists(f) && fs::file_size(f) > 0, "wrote " + f);
  std::ifstream md(files.markdown);
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  Check(text.find("Removed bone volume") != std::string::npos &&
            text.find("reamed.png") != std::string::npos,
        "report.md lists the removed volume and shows the picture");
  Check(text.find(setup.Model().Provenance().name + " (not calibrated") != std::string::npos,
        "report.md names the coefficient set and that it is not calibrated");

  // Picture against the baseline.
  vtkSmartPointer<vtkPolyData> surface = bm::CutBoneSurface(setup, trial);
  Check(surface->GetNumberOfCells() > 0,
        "the cut surface has " + std::to_string(surface->GetNumberOfCells()) + " triangles");
  const std::string picture = (work / "GlenoidReamed.png").string();
  bm::WritePng(picture, bm::RenderSurface(surface, bm::TrialView(setup, 400)));
  if (!fs::exists(baseline)) {
    fs::create_directories(fs::path(baseline).parent_path());
    fs::copy_file(picture, baseline);
    Check(false, "no baseline: wrote " + baseline + " (check it and commit it)");
  } else {
    vtkNew<vtkTesting> testing;
    testing->AddArgument("-V");
    testing->AddArgument(baseline.c_str());
    testing->AddArgument("-T");
    testing->AddArgument(work.string().c_str());
    const int result = testing->RegressionTest(picture, 0.15);
    Check(result == vtkTesting::PASSED, "the rendered reamed glenoid matches " + baseline);
  }
  std::cout << (failures ? "FAILED" : "OK") << "\n";
  return failures ? 1 : 0;
}
