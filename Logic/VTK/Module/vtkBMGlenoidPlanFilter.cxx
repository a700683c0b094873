// vtkBMGlenoidPlanFilter.cxx - see vtkBMGlenoidPlanFilter.h.
#include "vtkBMGlenoidPlanFilter.h"

#include "bmGlenoidLandmarks.h"
#include "bmGlenoidMeasurements.h"
#include "bmGlenoidPlan.h"
#include "bmJson.h"
#include "bmSegmentedBone.h"
#include "bmVoxmap.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <memory>
#include <optional>
#include <stdexcept>
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
  std::unique_ptr<bm::SegmentedBone> Bone;
  // Detection cache: the landmarks for one glenoid-centre override (none = detected).
  bool HaveLandmarks = false;
  std::optional<bm::Vec3> LandmarksCentre, LandmarksNormal;
  bm::GlenoidLandmarks Landmarks;
  std::optional<bm::Vec3> DetectedNormal; ///< the face normal detected without overrides
};

vtkStandardNewMacro(vtkBMGlenoidPlanFilter);

vtkBMGlenoidPlanFilter::vtkBMGlenoidPlanFilter() : Internals(new vtkInternals) {
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
}

vtkBMGlenoidPlanFilter::~vtkBMGlenoidPlanFilter() {
  this->SetCTFileName(nullptr);
  this->SetCTBoneSpecification(nullptr);
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
  this->FriedmanVersion = this->Version3D = this->Inclination = 0;
  this->GlenoidHeight = this->GlenoidWidth = this->FaceRadius = this->Correction = 0;
  this->ReamerFits = 0;
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
      in.HaveLandmarks = false;
      in.DetectedNormal.reset();
      this->UpdateProgress(0.05);
      in.Bone = std::make_unique<bm::SegmentedBone>(VoxmapFromImage(input));
      in.Input = input;
      in.InputMTime = input->GetMTime();
    }
    // 2. Detection, once per glenoid-centre override. A given centre keeps the detected face
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
    bm::LandmarkOverrides all;
    all.glenoidCentre = centre;
    if (this->UseTrigonum)
      all.trigonum = ToVec3(this->Trigonum);
    if (this->UseInferiorAngle)
      all.inferiorAngle = ToVec3(this->InferiorAngle);
    bm::GlenoidLandmarks L;
    if (in.HaveLandmarks && in.LandmarksCentre == centre && in.LandmarksNormal == givenNormal) {
      L = in.Landmarks;
    } else {
      this->UpdateProgress(0.3);
      bm::LandmarkOverrides base;
      base.glenoidCentre = centre;
      if (givenNormal)
        base.faceNormal = givenNormal;
      else if (centre && in.DetectedNormal)
        base.faceNormal = in.DetectedNormal;
      try {
        L = bm::DetectLandmarks(*in.Bone, base);
        ++this->DetectionCount;
        if (base.faceNormal && !givenNormal)
          L.normalSource = "detected";
        in.Landmarks = L;
        in.LandmarksCentre = centre;
        in.LandmarksNormal = givenNormal;
        in.HaveLandmarks = true;
        if (!centre && !givenNormal)
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
      const nlohmann::json settings =
          specified
              ? bm::ParseJson(std::string(this->CTBoneSpecification), "the CT bone's specification")
              : nlohmann::json{{"ct", std::filesystem::absolute(this->CTFileName).string()}};
      const bm::PlanScenes scenes = bm::MakePlanScenes(L, m, plan, settings);
      in.PlanScene = scenes.plan.dump(2);
      in.PinScene = scenes.pin.dump(2);
      in.ReamScene = scenes.ream.dump(2);
    }

    // 4. The picture: landmarks, rim, axis, face normal.
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> verts, lines;
    vtkNew<vtkStringArray> names;
    names->SetName("Landmark");
    vtkNew<vtkIntArray> part;
    part->SetName("Part");
    const std::pair<const char*, bm::Vec3> marks[] = {{"glenoid centre", L.glenoidCentre},
                                                      {"trigonum", L.trigonum},
                                                      {"inferior angle", L.inferiorAngle}};
    for (const auto& [name, p] : marks) {
      const vtkIdType id = points->InsertNextPoint(p.data());
      names->InsertNextValue(name);
      verts->InsertNextCell(1, &id);
    }
    auto addPoint = [&](const bm::Vec3& p) {
      names->InsertNextValue("");
      return points->InsertNextPoint(p.data());
    };
    if (!L.rim.empty()) {
      lines->InsertNextCell(int(L.rim.size() + 1));
      const vtkIdType first = addPoint(L.rim[0]);
      lines->InsertCellPoint(first);
      for (size_t i = 1; i < L.rim.size(); ++i)
        lines->InsertCellPoint(addPoint(L.rim[i]));
      lines->InsertCellPoint(first);
    }
    const vtkIdType axis[2] = {addPoint(plan.entry),
                               addPoint(bm::AddScaled(plan.entry, plan.axis, 40.0))};
    lines->InsertNextCell(2, axis);
    const vtkIdType normal[2] = {addPoint(L.glenoidCentre),
                                 addPoint(bm::AddScaled(L.glenoidCentre, L.faceNormal, 30.0))};
    lines->InsertNextCell(2, normal);
    const vtkIdType glenoidLine[2] = {addPoint(m.anteriorRim), addPoint(m.posteriorRim)};
    lines->InsertNextCell(2, glenoidLine);
    for (int i = 0; i < 3; ++i)
      part->InsertNextValue(0);
    if (!L.rim.empty())
      part->InsertNextValue(1);
    part->InsertNextValue(2);
    part->InsertNextValue(3);
    part->InsertNextValue(4);
    output->SetPoints(points);
    output->SetVerts(verts);
    output->SetLines(lines);
    output->GetPointData()->AddArray(names);
    output->GetCellData()->AddArray(part);
  } catch (const bm::NoGlenoidFound& e) {
    // The detection's hint names the plan file's keys; here the landmarks are the filter's.
    std::string what = e.what();
    what = what.substr(0, what.find("; place the landmarks"));
    in.Error = what + "; place the landmarks: turn on Use Glenoid Centre and Use Face Normal and "
                      "give them (drag the centre's handle onto the glenoid face in the 3D "
                      "view), and Use Trigonum or Use Inferior Angle for one not found";
    output->Initialize();
    vtkErrorMacro(<< "glenoid plan: " << in.Error);
    return 0;
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
