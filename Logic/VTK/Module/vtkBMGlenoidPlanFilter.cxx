// vtkBMGlenoidPlanFilter.cxx - see vtkBMGlenoidPlanFilter.h.
#include "vtkBMGlenoidPlanFilter.h"

#include "bmGlenoidLandmarks.h"
#include "bmGlenoidMeasurements.h"
#include "bmGlenoidPlan.h"
#include "bmPlanFiles.h"
#include "bmGlenoidPictures.h"
#include "bmPlanGlyphs.h"
#include "bmPlanResult.h"
#include "bmToolModel.h"
#ifdef BM_WITH_IO
#include "bmVoxmapFile.h"
#endif
#ifdef BM_WITH_DCMTK
#include "bmDicomSource.h"
#include "bmPlanDicomResults.h"
#endif
#include "bmJson.h"
#include "bmExcludedHead.h"
#include "bmJoinedHeadCut.h"
#include "bmSegmentedBone.h"
#include "bmVoxmap.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <memory>
#include <optional>
#include <stdexcept>
#include <sstream>
#include <string>

namespace {

/// The image's bone fractions as a voxmap (world mm). Throws std::runtime_error naming what is
/// wrong with the image.
bm::Voxmap VoxmapFromImage(vtkImageData* image) {
  int ext[6];
  image->GetExtent(ext);
  const std::array<int, 3> dims{ext[1] - ext[0] + 1, ext[3] - ext[2] + 1, ext[5] - ext[4] + 1};
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2)
    throw std::runtime_error("the input image is empty or flat (" + std::to_string(dims[0]) +
                             " x " + std::to_string(dims[1]) + " x " + std::to_string(dims[2]) +
                             " voxels)");
  const double* s = image->GetSpacing();
  const double h = s[0];
  if (!(h > 0) || std::abs(s[1] - h) > 1e-6 * h || std::abs(s[2] - h) > 1e-6 * h)
    throw std::runtime_error("the input image's spacing (" + std::to_string(s[0]) + ", " +
                             std::to_string(s[1]) + ", " + std::to_string(s[2]) +
                             " mm) is not isotropic: give a voxmap (BM CT Bone, bmsim import)");
  const vtkMatrix3x3* d = image->GetDirectionMatrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (std::abs(d->GetElement(r, c) - (r == c ? 1.0 : 0.0)) > 1e-9)
        throw std::runtime_error("the input image is not axis-aligned (its direction matrix is "
                                 "not the identity): give a voxmap (BM CT Bone, bmsim import)");
  vtkDataArray* fraction = image->GetPointData()->GetArray("BoneFraction");
  if (!fraction)
    fraction = image->GetPointData()->GetScalars();
  if (!fraction)
    throw std::runtime_error("the input image has no BoneFraction array and no point scalars");
  const double* o = image->GetOrigin();
  bm::Voxmap v(dims, h, {o[0] + ext[0] * h, o[1] + ext[2] * h, o[2] + ext[4] * h});
  vtkIdType n = 0;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i, ++n) {
        const double f = fraction->GetComponent(n, 0);
        if (std::isfinite(f) && f > 0)
          v.SetFill(v.Index(i, j, k),
                    bm::Voxmap::Fill(std::lround(std::min(f, 1.0) * double(bm::Voxmap::kFull))));
      }
  return v;
}

bm::Vec3 ToVec3(const double p[3]) {
  return {p[0], p[1], p[2]};
}

void Copy3(const bm::Vec3& v, double out[3]) {
  out[0] = v[0], out[1] = v[1], out[2] = v[2];
}

} // namespace

class vtkBMGlenoidPlanFilter::vtkInternals {
public:
  std::string Error, Warnings, PlanScene, PinScene, ReamScene;
  // Segmentation cache: one input identity and modification time.
  const void* Input = nullptr;
  vtkMTimeType InputMTime = 0;
  std::unique_ptr<bm::Voxmap> Voxmap;
  std::unique_ptr<bm::SegmentedBone> Bone;
  /// A humeral head joined to the glenoid, cut off (Bone is then the cut's): its steps leave it
  /// out.
  std::optional<bm::HeadCut> Cut;
  std::vector<bm::Vec3> RimPoints;
  // Detection cache: the landmarks for one set of glenoid overrides (centre, normal, face point,
  // rim points; none = detected), keyed by their JSON.
  bool HaveLandmarks = false;
  std::string LandmarksKey;
  bm::GlenoidLandmarks Landmarks;
  std::optional<bm::Vec3> DetectedNormal; ///< the face normal detected without overrides
  // The last plan, for WriteReport(): its landmarks, measurements and plan (or why it failed) and
  // its scenes.
  std::optional<bm::GlenoidLandmarks> LastLandmarks;
  bm::GlenoidMeasurements LastMeasurements;
  bm::GlenoidPlan LastPlan;
  std::optional<bm::PlanScenes> LastScenes;
  std::string LastFailure;
  /// A plan, or a failure to report, exists.
  bool Planned() const { return LastLandmarks || !LastFailure.empty(); }
  std::string ReportError, ReportFiles;
};

vtkStandardNewMacro(vtkBMGlenoidPlanFilter);

vtkBMGlenoidPlanFilter::vtkBMGlenoidPlanFilter() : Internals(new vtkInternals) {
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
}

vtkBMGlenoidPlanFilter::~vtkBMGlenoidPlanFilter() {
  this->SetCTFileName(nullptr);
  this->SetCTBoneSpecification(nullptr);
  this->SetReportDirectory(nullptr);
  this->SetResultBeforeBone(nullptr);
  this->SetResultAfterBone(nullptr);
  this->SetResultSteps(nullptr);
  delete this->Internals;
}

int vtkBMGlenoidPlanFilter::FillInputPortInformation(int, vtkInformation* info) {
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

const char* vtkBMGlenoidPlanFilter::GetWarnings() {
  return this->Internals->Warnings.c_str();
}

const char* vtkBMGlenoidPlanFilter::GetLastError() {
  return this->Internals->Error.c_str();
}

const char* vtkBMGlenoidPlanFilter::GetPlanScene() {
  return this->Internals->PlanScene.c_str();
}

const char* vtkBMGlenoidPlanFilter::GetPinStepScene() {
  return this->Internals->PinScene.c_str();
}

const char* vtkBMGlenoidPlanFilter::GetReamStepScene() {
  return this->Internals->ReamScene.c_str();
}

void vtkBMGlenoidPlanFilter::AddRimPoint(double x, double y, double z) {
  this->Internals->RimPoints.push_back({x, y, z});
  this->Modified();
}

void vtkBMGlenoidPlanFilter::RemoveAllRimPoints() {
  if (this->Internals->RimPoints.empty())
    return;
  this->Internals->RimPoints.clear();
  this->Modified();
}

int vtkBMGlenoidPlanFilter::GetNumberOfRimPoints() const {
  return int(this->Internals->RimPoints.size());
}

const char* vtkBMGlenoidPlanFilter::GetReportError() {
  return this->Internals->ReportError.c_str();
}

const char* vtkBMGlenoidPlanFilter::GetReportFiles() {
  return this->Internals->ReportFiles.c_str();
}

bool vtkBMGlenoidPlanFilter::WriteReport() {
  vtkInternals& in = *this->Internals;
  in.ReportError.clear();
  in.ReportFiles.clear();
  try {
    if (!this->ReportDirectory || !*this->ReportDirectory)
      throw std::runtime_error("no report folder given");
    if (!in.Planned())
      throw std::runtime_error("no plan yet: plan first");
    bm::PlanReportInput rep;
    const bool specified = this->CTBoneSpecification && *this->CTBoneSpecification;
    std::string ct = this->CTFileName ? this->CTFileName : "";
    if (specified) {
      const nlohmann::json spec =
          bm::ParseJson(std::string(this->CTBoneSpecification), "the CT bone's specification");
      ct = spec.value("ct", ct);
      rep.importSummary = "CT bone settings (BM CT Bone): " + spec.dump();
    } else {
      rep.importSummary = "bone from the image planned on (the CT's default import settings)";
    }
    if (in.Cut)
      rep.importSummary += "\n" + bm::HeadCutSummary(*in.Cut);
    rep.source = ct.empty() ? std::string("an image open in the viewer (no CT file named)") : ct;
    if (in.LastLandmarks) {
      rep.landmarks = &*in.LastLandmarks;
      rep.measurements = &in.LastMeasurements;
      rep.plan = &in.LastPlan;
    } else {
      rep.failure = in.LastFailure;
    }
    const std::vector<std::string> names =
        bm::WritePlanFiles(this->ReportDirectory, rep, in.LastScenes ? &*in.LastScenes : nullptr);
    for (const std::string& n : names)
      in.ReportFiles += (in.ReportFiles.empty() ? "" : "\n") + n;
    return true;
  } catch (const std::exception& e) {
    in.ReportError = e.what();
    vtkErrorMacro(<< "glenoid plan report: " << in.ReportError);
    return false;
  }
}

bool vtkBMGlenoidPlanFilter::WriteResult() {
  vtkInternals& in = *this->Internals;
  in.ReportError.clear();
  in.ReportFiles.clear();
  try {
    if (!this->ReportDirectory || !*this->ReportDirectory)
      throw std::runtime_error("no folder given for the plan's result");
    if (!in.LastLandmarks || !in.LastScenes)
      throw std::runtime_error("no plan with steps: plan on a named CT first");
    for (const char* f : {this->ResultBeforeBone, this->ResultAfterBone})
      if (!f || !*f || !std::filesystem::is_regular_file(f))
        throw std::runtime_error(std::string("the bone ") + (f && *f ? f : "(none)") +
                                 " is missing: run the plan's guide pin, then its reaming");
#ifdef BM_WITH_IO
    const bm::Voxmap before = bm::LoadVoxmap(this->ResultBeforeBone);
    const bm::Voxmap after = bm::LoadVoxmap(this->ResultAfterBone);
#else
    throw std::runtime_error("reading voxmaps needs the IO library, which this build leaves out");
    const bm::Voxmap before({1, 1, 1}, 1.0, {0, 0, 0}), after = before;
#endif
    nlohmann::json steps = this->ResultSteps && *this->ResultSteps
                               ? bm::ParseJson(std::string(this->ResultSteps), "the plan's steps")
                               : nlohmann::json::array();
    if (!steps.is_array())
      throw std::runtime_error("the plan's steps must be a JSON array");
    // A step is complete when it reached its scene's depth (within 0.1 mm); a session stopped
    // short says so.
    bool completed = !steps.empty();
    for (auto& step : steps) {
      const nlohmann::json& scene =
          step.value("tool", "") == "reamer" ? in.LastScenes->ream : in.LastScenes->pin;
      const double planned = scene.at("trial").value("depth_mm", 0.0);
      nlohmann::json& summary = step["summary"];
      const double reached = summary.is_object() && summary.contains("reached_depth_mm") &&
                                     summary["reached_depth_mm"].is_number()
                                 ? summary["reached_depth_mm"].get<double>()
                                 : -1e9;
      if (reached < planned - 0.1) {
        completed = false;
        std::ostringstream w;
        w.precision(2);
        w << std::fixed << "stopped at " << reached << " mm of the planned " << planned << " mm";
        summary["warnings"].push_back(w.str());
      }
    }
    const nlohmann::json& scene = in.LastScenes->plan;
    // The CT's DICOM series, checked before anything is written.
    std::string dicomFolder, dicomSeries;
    if (this->ResultAsDicom) {
      const nlohmann::json ct =
          scene.value("bone", nlohmann::json::object()).value("ct", nlohmann::json::object());
      dicomFolder = ct.value("ct", std::string());
      dicomSeries = ct.value("series", std::string());
      if (dicomFolder.empty() || !std::filesystem::is_directory(dicomFolder))
        throw std::runtime_error("the plan's CT" +
                                 (dicomFolder.empty() ? std::string() : " '" + dicomFolder + "'") +
                                 " is not a DICOM series: results as DICOM belong beside it");
#ifdef BM_WITH_DCMTK
      bm::ReadDicomSource(dicomFolder, dicomSeries);
#else
      throw std::runtime_error("results as DICOM need DCMTK, which this build leaves out");
#endif
    }
    bm::PlanResultInput result;
    result.planName = scene.value("name", "glenoid plan");
    result.planning = scene.value("planning", nlohmann::json());
    result.steps = steps;
    result.completed = completed;
    result.before = &before;
    result.after = &after;
    // The reaming step: the plan's reamer, to the depth its session reached.
    const nlohmann::json& ream = in.LastScenes->ream;
    const std::unique_ptr<bm::ToolModel> reamer = bm::MakeTool(ream.at("tool"));
    for (const auto& step : steps)
      if (step.value("tool", "") == "reamer" && step.contains("summary"))
        result.reamReachedMm = step["summary"].value("reached_depth_mm", 0.0);
    result.reamer = reamer.get();
    const nlohmann::json summary =
        bm::WritePlanResult(this->ReportDirectory, result,
                            [](const std::string& dir, const bm::Voxmap& b, const bm::Voxmap& a,
                               const nlohmann::json& planning) {
                              const bm::GlenoidPictureFiles files =
                                  bm::WriteGlenoidPictures(dir, b, a, planning);
                              return std::make_pair(files.before, files.after);
                            });
    in.ReportFiles = "summary.json\nplan_result.md\nplan_result.html";
    if (summary.contains("pictures"))
      in.ReportFiles += "\nglenoid_before.png\nglenoid_after.png";
#ifdef BM_WITH_DCMTK
    if (this->ResultAsDicom) {
      const bm::PlanDicomFiles files = bm::WritePlanDicomResults(
          (std::filesystem::path(this->ReportDirectory) / "dicom").string(), dicomFolder,
          dicomSeries, before, after, summary, "BoneMachining plugin", this->ReportDirectory);
      in.ReportFiles += "\ndicom/reamed-bone.seg.dcm\ndicom/plan.sr.dcm";
      for (const std::string& sc : files.pictures)
        in.ReportFiles += "\ndicom/" + std::filesystem::path(sc).filename().string();
    }
#endif
    return true;
  } catch (const std::exception& e) {
    in.ReportError = e.what();
    vtkErrorMacro(<< "glenoid plan result: " << in.ReportError);
    return false;
  }
}

int vtkBMGlenoidPlanFilter::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                        vtkInformationVector* outputVector) {
  vtkImageData* input = vtkImageData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  output->Initialize();
  vtkInternals& in = *this->Internals;
  in.Error.clear();
  in.Warnings.clear();
  in.PlanScene.clear();
  in.PinScene.clear();
  in.ReamScene.clear();
  in.LastLandmarks.reset();
  in.LastScenes.reset();
  in.LastFailure.clear();
  std::fill(std::begin(this->PlanCamera), std::end(this->PlanCamera), 0.0);
  this->FriedmanVersion = this->Version3D = this->Inclination = 0;
  this->GlenoidHeight = this->GlenoidWidth = this->FaceRadius = this->Correction = 0;
  this->ReamerFits = this->Implausible = 0;
  std::fill(std::begin(this->GlenoidLine), std::end(this->GlenoidLine), 0.0);
  for (double* p : {this->UsedGlenoidCentre, this->UsedTrigonum, this->UsedInferiorAngle,
                    this->UsedFaceNormal, this->PlanEntry, this->PlanAxis})
    p[0] = p[1] = p[2] = 0;
  try {
    if (!input)
      throw std::runtime_error("no input image");
    // 1. Segmentation, once per input.
    if (!in.Bone || in.Input != input || in.InputMTime != input->GetMTime()) {
      in.Bone.reset();
      in.Cut.reset();
      in.HaveLandmarks = false;
      in.DetectedNormal.reset();
      this->UpdateProgress(0.05);
      in.Voxmap = std::make_unique<bm::Voxmap>(VoxmapFromImage(input));
      in.Bone = std::make_unique<bm::SegmentedBone>(*in.Voxmap);
      in.Input = input;
      in.InputMTime = input->GetMTime();
    }
    // 2. Detection, once per set of glenoid overrides. A given centre keeps the detected face
    // normal (no joint search); the trigonum and inferior angle are replaced afterwards.
    std::optional<bm::Vec3> centre;
    if (this->UseGlenoidCentre)
      centre = ToVec3(this->GlenoidCentre);
    std::optional<bm::Vec3> givenNormal;
    if (this->UseFaceNormal) {
      const bm::Vec3 n = ToVec3(this->FaceNormal);
      const double len = bm::Norm(n);
      if (!(len > 0) || !std::isfinite(len))
        throw std::runtime_error("the face normal (" + std::to_string(n[0]) + ", " +
                                 std::to_string(n[1]) + ", " + std::to_string(n[2]) +
                                 ") is zero or not finite");
      givenNormal = bm::Scale(n, 1.0 / len);
    }
    bm::LandmarkOverrides base;
    base.glenoidCentre = centre;
    if (givenNormal)
      base.faceNormal = givenNormal;
    else if (centre && in.DetectedNormal)
      base.faceNormal = in.DetectedNormal;
    if (this->UseFacePoint && !centre && !givenNormal)
      base.facePoint = ToVec3(this->FacePoint);
    if (!centre && !givenNormal && !base.facePoint && in.RimPoints.size() >= 3)
      base.rimPoints = in.RimPoints;
    nlohmann::json key = nlohmann::json::object();
    if (base.glenoidCentre)
      key["c"] = *base.glenoidCentre;
    if (base.faceNormal)
      key["n"] = *base.faceNormal;
    if (base.facePoint)
      key["f"] = *base.facePoint;
    if (!base.rimPoints.empty())
      key["r"] = base.rimPoints;
    bm::LandmarkOverrides all = base;
    if (!givenNormal && centre)
      all.faceNormal.reset(); // a detected normal is not the user's
    if (this->UseTrigonum)
      all.trigonum = ToVec3(this->Trigonum);
    if (this->UseInferiorAngle)
      all.inferiorAngle = ToVec3(this->InferiorAngle);
    bm::GlenoidLandmarks L;
    if (in.HaveLandmarks && in.LandmarksKey == key.dump()) {
      L = in.Landmarks;
    } else {
      this->UpdateProgress(0.3);
      try {
        if (base.Empty() && !in.Cut) {
          // The plan's detection, as bmsim plan's: a joined humeral head is cut off first.
          bm::LandmarksOnCut found =
              bm::DetectCuttingAJoinedHead(*in.Voxmap, *in.Bone, [&](const bm::SegmentedBone& b) {
                return bm::DetectLandmarks(b, base);
              });
          L = std::move(found.landmarks);
          if (found.cut) {
            in.Bone = std::make_unique<bm::SegmentedBone>(std::move(*found.bone));
            in.Cut = std::move(found.cut);
          }
        } else {
          L = bm::DetectLandmarks(*in.Bone, base);
        }
        ++this->DetectionCount;
        if (base.faceNormal && !givenNormal)
          L.normalSource = "detected";
        in.Landmarks = L;
        in.LandmarksKey = key.dump();
        in.HaveLandmarks = true;
        if (base.Empty())
          in.DetectedNormal = L.faceNormal;
      } catch (const bm::NoGlenoidFound&) {
        // A scapular landmark the detection could not find may be one the user gave.
        if (!all.trigonum && !all.inferiorAngle)
          throw;
        if (base.faceNormal)
          all.faceNormal = base.faceNormal;
        L = bm::DetectLandmarks(*in.Bone, all);
        ++this->DetectionCount;
      }
    }
    if (all.trigonum) {
      L.trigonum = *all.trigonum;
      L.trigonumSource = "user";
      L.trigonumMissing.clear();
    }
    if (all.inferiorAngle) {
      L.inferiorAngle = *all.inferiorAngle;
      L.inferiorSource = "user";
      L.inferiorMissing.clear();
    }
    // 3. Measurements and plan.
    this->UpdateProgress(0.8);
    const bm::GlenoidMeasurements m = bm::MeasureGlenoid(L);
    bm::PlanOptions po;
    po.targetVersionDeg = this->TargetVersion;
    po.targetInclinationDeg = this->TargetInclination;
    po.reamDepthMm = this->ReamDepth;
    po.reamerDiameterMm = this->ReamerDiameter;
    po.pinRadiusMm = this->PinRadius;
    po.pinDepthMm = this->PinDepth;
    const bm::GlenoidPlan plan = bm::MakeGlenoidPlan(L, m, po);
    // A tool that would start inside bone: no step scenes, and the warning says why.
    std::string blocked;
    try {
      bm::CheckToolStartsOutsideBone(*in.Bone, L, plan);
    } catch (const bm::PlanBlocked& e) {
      blocked = e.what();
    }

    this->FriedmanVersion = m.friedmanVersionDeg;
    this->Version3D = m.version3DDeg;
    this->Inclination = m.inclinationDeg;
    this->GlenoidHeight = m.heightMm;
    this->GlenoidWidth = m.widthMm;
    this->FaceRadius = m.faceRadiusMm;
    this->Correction = plan.correctionDeg;
    this->ReamerFits = plan.reamerFits ? 1 : 0;
    this->Implausible = plan.implausible.empty() ? 0 : 1;
    Copy3(L.glenoidCentre, this->UsedGlenoidCentre);
    Copy3(L.trigonum, this->UsedTrigonum);
    Copy3(L.inferiorAngle, this->UsedInferiorAngle);
    Copy3(L.faceNormal, this->UsedFaceNormal);
    Copy3(m.anteriorRim, this->GlenoidLine);
    Copy3(m.posteriorRim, this->GlenoidLine + 3);
    Copy3(plan.entry, this->PlanEntry);
    Copy3(plan.axis, this->PlanAxis);
    for (const std::string& w : plan.warnings)
      in.Warnings += (in.Warnings.empty() ? "" : "\n") + w;
    if (!blocked.empty())
      in.Warnings += (in.Warnings.empty() ? "" : "\n") + blocked + " (the steps are not offered)";
    const bool specified = this->CTBoneSpecification && *this->CTBoneSpecification;
    if (blocked.empty() && (specified || (this->CTFileName && *this->CTFileName))) {
      nlohmann::json settings =
          specified
              ? bm::ParseJson(std::string(this->CTBoneSpecification), "the CT bone's specification")
              : nlohmann::json{{"ct", std::filesystem::absolute(this->CTFileName).string()}};
      if (in.Cut) // the steps' bone leaves the cut-off head out
        settings["exclude_heads"].push_back(bm::ExcludedHeadToJson(in.Cut->head));
      const bm::PlanScenes scenes = bm::MakePlanScenes(L, m, plan, settings);
      in.LastScenes = scenes;
      in.PlanScene = scenes.plan.dump(2);
      in.PinScene = scenes.pin.dump(2);
      in.ReamScene = scenes.ream.dump(2);
    }

    in.LastLandmarks = L;
    in.LastMeasurements = m;
    in.LastPlan = plan;

    // 4. The picture: the plan's glyphs, and its camera.
    const nlohmann::json planning = bm::PlanningJson(L, m, plan);
    output->ShallowCopy(bm::MakePlanGlyphs(planning));
    const bm::SurfaceView view = bm::PlanView(planning);
    for (int a = 0; a < 3; ++a) {
      this->PlanCamera[a] = view.focalMm[size_t(a)];
      this->PlanCamera[3 + a] = view.toCamera[size_t(a)];
      this->PlanCamera[6 + a] = view.viewUp[size_t(a)];
    }
    this->PlanCamera[9] = view.halfHeightMm;
  } catch (const bm::NoGlenoidFound& e) {
    // The detection's hint names the plan file's keys; here the landmarks are the filter's.
    std::string what = e.what();
    what = what.substr(0, what.find("; place the landmarks"));
    in.Error = what + "; place the glenoid: Click the face (or Click the rim, three or more "
                      "points) and click on the bone in the 3D view, or give the centre and "
                      "face normal; Use Trigonum or Use Inferior Angle for one not found";
    in.LastFailure = in.Error;
    output->Initialize();
    // An answer, not a fault: the dock shows it and asks for the glenoid to be placed
    // (LastErrorInfo). An error or warning would also open ParaView's Output Messages over the
    // view the surgeon is to click in.
    vtkDebugMacro(<< "glenoid plan: " << in.Error);
    return 1;
  } catch (const std::exception& e) {
    in.Error = e.what();
    output->Initialize();
    vtkErrorMacro(<< "glenoid plan: " << in.Error);
    return 0;
  }
  return 1;
}

void vtkBMGlenoidPlanFilter::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "UseGlenoidCentre: " << this->UseGlenoidCentre << " (" << this->GlenoidCentre[0]
     << ", " << this->GlenoidCentre[1] << ", " << this->GlenoidCentre[2] << ") mm\n";
  os << indent << "UseFaceNormal: " << this->UseFaceNormal << " (" << this->FaceNormal[0] << ", "
     << this->FaceNormal[1] << ", " << this->FaceNormal[2] << ")\n";
  os << indent << "UseTrigonum: " << this->UseTrigonum << " (" << this->Trigonum[0] << ", "
     << this->Trigonum[1] << ", " << this->Trigonum[2] << ") mm\n";
  os << indent << "UseInferiorAngle: " << this->UseInferiorAngle << " (" << this->InferiorAngle[0]
     << ", " << this->InferiorAngle[1] << ", " << this->InferiorAngle[2] << ") mm\n";
  os << indent << "Targets: version " << this->TargetVersion << " deg, inclination "
     << this->TargetInclination << " deg\n";
  os << indent << "ReamDepth: " << this->ReamDepth << " mm, ReamerDiameter " << this->ReamerDiameter
     << " mm, PinRadius " << this->PinRadius << " mm, PinDepth " << this->PinDepth << " mm\n";
  os << indent << "CTFileName: " << (this->CTFileName ? this->CTFileName : "(none)") << "\n";
  os << indent << "CTBoneSpecification: "
     << (this->CTBoneSpecification ? this->CTBoneSpecification : "(none)") << "\n";
  os << indent << "Measured: Friedman version " << this->FriedmanVersion << " deg, 3D version "
     << this->Version3D << " deg, inclination " << this->Inclination << " deg\n";
}
