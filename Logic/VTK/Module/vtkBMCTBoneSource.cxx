// vtkBMCTBoneSource.cxx - see vtkBMCTBoneSource.h.
#include "vtkBMCTBoneSource.h"

#ifdef BM_WITH_IO
#include "bmCTVoxmap.h"
#include "bmImport.h"
#endif
#include "bmVTKImageVolume.h"
#include "bmVoxmap.h"

#include "vtkAlgorithmOutput.h"
#include "vtkDataArray.h"
#include "vtkDataSetReader.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTransform.h"
#include "vtkXMLImageDataReader.h"
#include "bmJson.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

class vtkBMCTBoneSource::vtkInternals {
public:
  std::string Error;
  std::string Specification;
  std::string Report;               ///< the last import's summary ("" when it failed)
  std::unique_ptr<bm::Voxmap> Bone; ///< the last import's voxmap (null when it failed)
  vtkTimeStamp ImportTime;          ///< when the last import ran
  const void* Input = nullptr;      ///< the input image of the last import (identity only)
  vtkMTimeType InputMTime = 0;      ///< its MTime then
  std::string CTCopy;               ///< MetaImage copy of an input image / VTK file ("" none)
  std::string CopyOf;               ///< what CTCopy holds (file name or input identity + MTime)
  ~vtkInternals() {
    std::error_code ec;
    if (!this->CTCopy.empty())
      std::filesystem::remove(this->CTCopy, ec);
  }
};

vtkStandardNewMacro(vtkBMCTBoneSource);

vtkBMCTBoneSource::vtkBMCTBoneSource() : Internals(new vtkInternals) {
  this->SetNumberOfInputPorts(1);
}

vtkBMCTBoneSource::~vtkBMCTBoneSource() {
  this->SetFileName(nullptr);
  delete this->Internals;
}

int vtkBMCTBoneSource::FillInputPortInformation(int, vtkInformation* info) {
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkBMCTBoneSource::RequestUpdateExtent(vtkInformation*, vtkInformationVector** inputVector,
                                           vtkInformationVector*) {
  // The whole input CT, whatever part of the voxmap image is asked for.
  if (inputVector[0]->GetNumberOfInformationObjects() > 0) {
    vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
    if (inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
      inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
                  inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
  }
  return 1;
}

const char* vtkBMCTBoneSource::GetLastError() {
  return this->Internals->Error.c_str();
}

const char* vtkBMCTBoneSource::GetImportReport() {
  return this->Internals->Report.c_str();
}

const char* vtkBMCTBoneSource::GetBoneSpecification() {
  std::string& spec = this->Internals->Specification;
  spec.clear();
  const bool viaCopy = this->GetNumberOfInputConnections(0) > 0 ||
                       (this->FileName && bm::IsVTKImageFile(this->FileName));
  if (viaCopy ? this->Internals->CTCopy.empty() : (!this->FileName || !*this->FileName))
    return spec.c_str();
  nlohmann::json j;
  try {
    j = bm::ParseJson(this->ImportOptionsJson(), "the CT bone's import options");
  } catch (const std::exception&) {
    return spec.c_str(); // invalid settings: no bone (Import names the problem)
  }
  j["ct"] = viaCopy ? this->Internals->CTCopy : std::filesystem::absolute(this->FileName).string();
  spec = j.dump();
  return spec.c_str();
}

std::string vtkBMCTBoneSource::ImportOptionsJson() const {
  nlohmann::json j;
  if (this->IntensityMode == IntensityRaw)
    j["rawThreshold"] = this->RawThreshold; // in the file's units: no HU threshold
  else
    j["threshold"] = this->ThresholdHU;
  if (this->IntensityMode == IntensityMapped)
    j["huMapping"] = {this->HUMapping[0], this->HUMapping[1]};
  if (this->ROI[3] > this->ROI[0] && this->ROI[4] > this->ROI[1] && this->ROI[5] > this->ROI[2])
    j["roi"] = {this->ROI[0], this->ROI[1], this->ROI[2], this->ROI[3], this->ROI[4], this->ROI[5]};
  if (this->UseSeed)
    j["seed"] = {this->Seed[0], this->Seed[1], this->Seed[2]};
  if (this->KeepAllBones)
    j["keepAllComponents"] = true;
  if (!this->ExcludePoints.empty()) {
    j["exclude"] = nlohmann::json::array();
    for (size_t i = 0; i + 2 < this->ExcludePoints.size(); i += 3)
      j["exclude"].push_back(
          {this->ExcludePoints[i], this->ExcludePoints[i + 1], this->ExcludePoints[i + 2]});
  }
  if (this->UseBox) {
    // The widget's box: world = centre + R (scale o p), p in the reference box, R = Rz Rx Ry.
    const double unit[6] = {0, 1, 0, 1, 0, 1};
    const double* ref = this->BoxUseReferenceBounds ? this->BoxReferenceBounds : unit;
    double refCentre[3], centre[3], half[3];
    for (int a = 0; a < 3; ++a) {
      if (!(ref[2 * a + 1] > ref[2 * a]))
        throw std::runtime_error("the box widget's reference bounds are empty along axis " +
                                 std::to_string(a) + " (give x0 < x1, y0 < y1, z0 < z1)");
      refCentre[a] = this->BoxHalfSizes[a] * 0.5 * (ref[2 * a] + ref[2 * a + 1]);
      half[a] = std::abs(this->BoxHalfSizes[a]) * 0.5 * (ref[2 * a + 1] - ref[2 * a]);
    }
    vtkNew<vtkTransform> rotation;
    rotation->RotateZ(this->BoxRotation[2]);
    rotation->RotateX(this->BoxRotation[0]);
    rotation->RotateY(this->BoxRotation[1]);
    rotation->TransformVector(refCentre, centre);
    j["box"] = {
        {"centre",
         {this->BoxCentre[0] + centre[0], this->BoxCentre[1] + centre[1],
          this->BoxCentre[2] + centre[2]}},
        {"halfSizes", {half[0], half[1], half[2]}},
        {"rotation", {this->BoxRotation[0], this->BoxRotation[1], this->BoxRotation[2]}}};
  }
  return j.dump();
}

void vtkBMCTBoneSource::AddExcludePoint(double x, double y, double z) {
  this->ExcludePoints.insert(this->ExcludePoints.end(), {x, y, z});
  this->Modified();
}

void vtkBMCTBoneSource::RemoveAllExcludePoints() {
  if (this->ExcludePoints.empty())
    return;
  this->ExcludePoints.clear();
  this->Modified();
}

int vtkBMCTBoneSource::GetNumberOfExcludePoints() const {
  return int(this->ExcludePoints.size() / 3);
}

int vtkBMCTBoneSource::RequestInformation(vtkInformation*, vtkInformationVector**,
                                          vtkInformationVector* outputVector) {
  // The import runs here (once per change of the settings): image consumers need the extent,
  // origin and spacing before they request data.
  vtkInternals& in = *this->Internals;
  vtkImageData* input = nullptr;
  if (this->GetNumberOfInputConnections(0) > 0) {
    // The input CT is imported here, so it must be current before its data is requested.
    vtkAlgorithmOutput* connection = this->GetInputConnection(0, 0);
    vtkAlgorithm* producer = connection->GetProducer();
    producer->UpdateWholeExtent();
    input = vtkImageData::SafeDownCast(producer->GetOutputDataObject(connection->GetIndex()));
  }
  if (this->GetMTime() > in.ImportTime.GetMTime() || input != in.Input ||
      (input && input->GetMTime() != in.InputMTime)) {
    in.Input = input;
    in.InputMTime = input ? input->GetMTime() : 0;
    this->Import(input);
    in.ImportTime.Modified();
  }
  vtkInformation* info = outputVector->GetInformationObject(0);
  int extent[6] = {0, -1, 0, -1, 0, -1};
  double origin[3] = {0, 0, 0}, spacing[3] = {1, 1, 1};
  if (in.Bone) {
    for (int a = 0; a < 3; ++a) {
      extent[2 * a + 1] = in.Bone->Dims()[a] - 1;
      origin[a] = in.Bone->Origin()[a];
      spacing[a] = in.Bone->Spacing();
    }
  }
  info->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  info->Set(vtkDataObject::ORIGIN(), origin, 3);
  info->Set(vtkDataObject::SPACING(), spacing, 3);
  info->Set(CAN_PRODUCE_SUB_EXTENT(), 0);
  return 1;
}

void vtkBMCTBoneSource::Import(vtkImageData* input) {
  vtkInternals& in = *this->Internals;
  in.Error.clear();
  in.Report.clear();
  in.Bone.reset();
  this->BoneVoxels = 0;
  this->BoneVolumeMm3 = 0;
  for (double& b : this->BoneBounds)
    b = 0;
  try {
    if (!input && (!this->FileName || !*this->FileName))
      throw std::runtime_error(
          "no CT chosen: connect a CT image or set a DICOM folder or a CT file");
    const bool anyRoi = this->ROI[0] != 0 || this->ROI[1] != 0 || this->ROI[2] != 0 ||
                        this->ROI[3] != 0 || this->ROI[4] != 0 || this->ROI[5] != 0;
    const bool validRoi =
        this->ROI[3] > this->ROI[0] && this->ROI[4] > this->ROI[1] && this->ROI[5] > this->ROI[2];
    if (anyRoi && !validRoi)
      throw std::runtime_error("the region of interest is inverted or empty: give x0, y0, z0, "
                               "x1, y1, z1 (mm) with each x1 above its x0");
    const double axisNorm =
        std::sqrt(this->Axis[0] * this->Axis[0] + this->Axis[1] * this->Axis[1] +
                  this->Axis[2] * this->Axis[2]);
    if (!(axisNorm > 0))
      throw std::runtime_error("the axis is zero: give the direction the tool comes in along");
    (void)this->ImportOptionsJson(); // the settings' own errors (the box reference), named
#ifdef BM_WITH_IO
    auto progress = [this](double f, const std::string&) {
      this->UpdateProgress(f);
      return !this->GetAbortExecute();
    };
    // A VTK image file is read by VTK's readers, then imported as an input image.
    vtkSmartPointer<vtkImageData> fromFile;
    std::string source = "the input image";
    if (!input && bm::IsVTKImageFile(this->FileName)) {
      source = this->FileName;
      fromFile = bm::ReadVTKImageFile(this->FileName);
      input = fromFile;
    }
    if (input) {
      bm::VTKImageVolume volume;
      bm::VolumeFromVTKImage(input, source, volume);
      const bm::CTVolumeView& view = volume.view;
      const nlohmann::json options =
          bm::ParseJson(this->ImportOptionsJson(), "the CT bone's import options");
      in.Bone = std::make_unique<bm::Voxmap>(
          bm::MakeCTVoxmapFromVolume(view, options, this->Resolution, progress, &in.Report));
      // The CT as a file a session can import at its own resolution (once per CT).
      const std::string copyOf = fromFile ? std::string(this->FileName)
                                          : std::to_string(reinterpret_cast<uintptr_t>(in.Input)) +
                                                "@" + std::to_string(in.InputMTime);
      if (in.CTCopy.empty() || in.CopyOf != copyOf) {
        if (in.CTCopy.empty())
          in.CTCopy = (std::filesystem::temp_directory_path() /
                       ("bm-ct-bone-" + std::to_string(::getpid()) + "-" +
                        std::to_string(reinterpret_cast<uintptr_t>(this)) + ".mha"))
                          .string();
        bm::SaveCTVolume(view, in.CTCopy);
        in.CopyOf = copyOf;
      }
    } else {
      const nlohmann::json spec =
          bm::ParseJson(this->GetBoneSpecification(), "the CT bone's specification");
      bm::ImportOptions options = bm::ImportOptionsFromJson(spec);
      options.resolution = this->Resolution;
      bm::ImportResult r =
          bm::ImportVoxmap(spec.at("ct").get<std::string>(), options, bm::Progress(progress));
      in.Report = r.Report();
      in.Bone = std::make_unique<bm::Voxmap>(std::move(r.voxmap));
    }
#else
    throw std::runtime_error("CT import needs the IO library, which this build leaves out");
#endif
    const bm::Voxmap& v = *in.Bone;
    const double h = v.Spacing();
    this->BoneVoxels = v.CountBone();
    this->BoneVolumeMm3 = v.BoneVolume();
    const bm::Box3 box = v.Bounds();
    for (int a = 0; a < 3; ++a) {
      this->BoneBounds[2 * a] = box.lo[a];
      this->BoneBounds[2 * a + 1] = box.hi[a];
    }
    // Entry: march along -axis from outside the box through its centre; first voxel >= 0.5.
    std::array<double, 3> centre, u;
    double halfDiagonal = 0;
    for (int a = 0; a < 3; ++a) {
      centre[a] = 0.5 * (box.lo[a] + box.hi[a]);
      u[a] = this->Axis[a] / axisNorm;
      halfDiagonal += 0.25 * (box.hi[a] - box.lo[a]) * (box.hi[a] - box.lo[a]);
    }
    halfDiagonal = std::sqrt(halfDiagonal);
    for (int a = 0; a < 3; ++a)
      this->SuggestedEntry[a] = centre[a];
    const int steps = int(std::ceil(4 * halfDiagonal / h));
    for (int step = 0; step <= steps; ++step) {
      const double t = halfDiagonal - step * 0.5 * h;
      const std::array<double, 3> p{centre[0] + t * u[0], centre[1] + t * u[1],
                                    centre[2] + t * u[2]};
      std::array<int, 3> ijk;
      if (v.VoxelAt(p, ijk) && v.Fraction(v.Index(ijk[0], ijk[1], ijk[2])) >= 0.5) {
        for (int a = 0; a < 3; ++a)
          this->SuggestedEntry[a] = p[a];
        break;
      }
    }
  } catch (const std::exception& e) {
    in.Error = e.what();
    if (in.Error.find("--raw-threshold") != std::string::npos)
      in.Error += " (in the panel and the filter's properties: Intensity mode 'Raw values' with "
                  "Raw threshold, or 'Map values to HU' with HU mapping)";
    in.Report.clear();
    in.Bone.reset();
    this->BoneVoxels = 0;
    this->BoneVolumeMm3 = 0;
  }
}

int vtkBMCTBoneSource::RequestData(vtkInformation*, vtkInformationVector**,
                                   vtkInformationVector* outputVector) {
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  output->Initialize();
  vtkInternals& in = *this->Internals;
  if (!in.Bone) {
    vtkErrorMacro(<< "cannot import the CT bone: " << in.Error);
    return 0;
  }
  const bm::Voxmap& v = *in.Bone;
  const std::array<int, 3>& d = v.Dims();
  const double h = v.Spacing();
  output->SetExtent(0, d[0] - 1, 0, d[1] - 1, 0, d[2] - 1);
  output->SetSpacing(h, h, h);
  output->SetOrigin(v.Origin()[0], v.Origin()[1], v.Origin()[2]);
  vtkNew<vtkFloatArray> fraction;
  fraction->SetName("BoneFraction");
  fraction->SetNumberOfTuples(v.NumVoxels());
  int64_t out = 0; // the image's rows are dense, the voxmap's padded (Voxmap::Pitch)
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
        fraction->SetValue(out++, float(v.Fraction(v.Index(i, j, k))));
  output->GetPointData()->SetScalars(fraction);
  return 1;
}

void vtkBMCTBoneSource::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "ThresholdHU: " << this->ThresholdHU << "\n";
  os << indent << "IntensityMode: " << this->IntensityMode << " (raw threshold "
     << this->RawThreshold << ", HU mapping " << this->HUMapping[0] << " x value + "
     << this->HUMapping[1] << ")\n";
  os << indent << "ROI: " << this->ROI[0] << " " << this->ROI[1] << " " << this->ROI[2] << " "
     << this->ROI[3] << " " << this->ROI[4] << " " << this->ROI[5] << " mm\n";
  os << indent << "Resolution: " << this->Resolution << "\n";
  os << indent << "BoneVoxels: " << this->BoneVoxels << ", " << this->BoneVolumeMm3 << " mm^3\n";
}
