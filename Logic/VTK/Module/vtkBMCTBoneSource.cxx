// vtkBMCTBoneSource.cxx - see vtkBMCTBoneSource.h.
#include "vtkBMCTBoneSource.h"

#ifdef BM_WITH_IO
#include "bmCTVoxmap.h"
#endif
#include "bmVoxmap.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <exception>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

class vtkBMCTBoneSource::vtkInternals {
public:
  std::string Error;
  std::string Specification;
  std::unique_ptr<bm::Voxmap> Bone; ///< the last import's voxmap (null when it failed)
  vtkMTimeType ImportTime = 0;      ///< this source's MTime at the last import
};

vtkStandardNewMacro(vtkBMCTBoneSource);

vtkBMCTBoneSource::vtkBMCTBoneSource() : Internals(new vtkInternals) {
  this->SetNumberOfInputPorts(0);
}

vtkBMCTBoneSource::~vtkBMCTBoneSource() {
  this->SetFileName(nullptr);
  delete this->Internals;
}

const char* vtkBMCTBoneSource::GetLastError() {
  return this->Internals->Error.c_str();
}

const char* vtkBMCTBoneSource::GetBoneSpecification() {
  std::string& spec = this->Internals->Specification;
  spec.clear();
  if (!this->FileName || !*this->FileName)
    return spec.c_str();
  nlohmann::json j;
  j["ct"] = std::filesystem::absolute(this->FileName).string();
  j["threshold"] = this->ThresholdHU;
  if (this->ROI[1] > this->ROI[0] && this->ROI[3] > this->ROI[2] && this->ROI[5] > this->ROI[4])
    j["roi"] = {this->ROI[0], this->ROI[2], this->ROI[4], this->ROI[1], this->ROI[3], this->ROI[5]};
  spec = j.dump();
  return spec.c_str();
}

int vtkBMCTBoneSource::RequestInformation(vtkInformation*, vtkInformationVector**,
                                          vtkInformationVector* outputVector) {
  // The import runs here (once per change of the settings): image consumers need the extent,
  // origin and spacing before they request data.
  vtkInternals& in = *this->Internals;
  if (this->GetMTime() > in.ImportTime) {
    in.ImportTime = this->GetMTime();
    this->Import();
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

void vtkBMCTBoneSource::Import() {
  vtkInternals& in = *this->Internals;
  in.Error.clear();
  in.Bone.reset();
  this->BoneVoxels = 0;
  this->BoneVolumeMm3 = 0;
  for (double& b : this->BoneBounds)
    b = 0;
  try {
    if (!this->FileName || !*this->FileName)
      throw std::runtime_error("no CT chosen: set a DICOM folder or a CT file");
    const bool anyRoi = this->ROI[0] != 0 || this->ROI[1] != 0 || this->ROI[2] != 0 ||
                        this->ROI[3] != 0 || this->ROI[4] != 0 || this->ROI[5] != 0;
    const bool validRoi =
        this->ROI[1] > this->ROI[0] && this->ROI[3] > this->ROI[2] && this->ROI[5] > this->ROI[4];
    if (anyRoi && !validRoi)
      throw std::runtime_error("the region of interest is empty: each max must exceed its min");
    const double axisNorm =
        std::sqrt(this->Axis[0] * this->Axis[0] + this->Axis[1] * this->Axis[1] +
                  this->Axis[2] * this->Axis[2]);
    if (!(axisNorm > 0))
      throw std::runtime_error("the axis is zero: give the direction the tool comes in along");
#ifdef BM_WITH_IO
    const nlohmann::json spec = nlohmann::json::parse(this->GetBoneSpecification());
    in.Bone = std::make_unique<bm::Voxmap>(bm::MakeCTVoxmap(spec, "", this->Resolution));
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
  os << indent << "ROI: " << this->ROI[0] << " " << this->ROI[1] << " " << this->ROI[2] << " "
     << this->ROI[3] << " " << this->ROI[4] << " " << this->ROI[5] << " mm\n";
  os << indent << "Resolution: " << this->Resolution << "\n";
  os << indent << "BoneVoxels: " << this->BoneVoxels << ", " << this->BoneVolumeMm3 << " mm^3\n";
}
