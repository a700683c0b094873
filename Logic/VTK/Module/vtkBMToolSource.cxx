// vtkBMToolSource.cxx - see vtkBMToolSource.h.
#include "vtkBMToolSource.h"

#include "bmToolModel.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataNormals.h"
#include "vtkUnsignedCharArray.h"
#include "bmJson.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <exception>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

namespace {
const char* const kToolTypeNames[] = {"drill", "reamer", "burr"};
/// Outline vertices closer to the axis than this (mm) are poles: one point, not a ring.
constexpr double kPoleRadius = 1e-9;
} // namespace

/// The bm::ToolModel for the current ToolType + Parameters, rebuilt only when they change.
class vtkBMToolSource::vtkInternals {
public:
  /// The tool for (type, parameters), or nullptr with Error set when the parameters are invalid.
  const bm::ToolModel* Get(int type, const char* parameters) {
    std::string params = parameters ? parameters : "";
    if (this->Built && type == this->Type && params == this->Params)
      return this->Tool.get();
    this->Built = true;
    this->Type = type;
    this->Params = params;
    this->Tool.reset();
    this->Error.clear();
    try {
      nlohmann::json spec = nlohmann::json::object();
      if (!params.empty()) {
        spec = bm::ParseJson(params, "the tool's Parameters");
        if (spec.is_null())
          spec = nlohmann::json::object();
        if (!spec.is_object())
          throw std::invalid_argument("Parameters must be a JSON object");
      }
      spec["type"] = kToolTypeNames[type];
      this->Tool = bm::MakeTool(spec);
    } catch (const std::exception& e) {
      this->Error = e.what();
    }
    return this->Tool.get();
  }

  bool Built = false;
  int Type = 0;
  std::string Params;
  std::unique_ptr<bm::ToolModel> Tool;
  std::string Error;
  std::string Specification; ///< GetToolSpecification()'s last answer
};

vtkStandardNewMacro(vtkBMToolSource);

vtkBMToolSource::vtkBMToolSource() : Internals(new vtkInternals) {
  this->SetNumberOfInputPorts(0);
}

vtkBMToolSource::~vtkBMToolSource() {
  this->SetParameters(nullptr);
  delete this->Internals;
}

const char* vtkBMToolSource::GetToolTypeAsString() const {
  return kToolTypeNames[this->ToolType];
}

bool vtkBMToolSource::GetToolIsValid() {
  return this->Internals->Get(this->ToolType, this->Parameters) != nullptr;
}

const char* vtkBMToolSource::GetToolError() {
  this->Internals->Get(this->ToolType, this->Parameters);
  return this->Internals->Error.c_str();
}

double vtkBMToolSource::GetOuterRadius() {
  const bm::ToolModel* tool = this->Internals->Get(this->ToolType, this->Parameters);
  return tool ? tool->OuterRadius() : 0.0;
}

int vtkBMToolSource::GetNumberOfLips() {
  const bm::ToolModel* tool = this->Internals->Get(this->ToolType, this->Parameters);
  return tool ? tool->NumLips() : 0;
}

void vtkBMToolSource::GetAxialRange(double range[2]) {
  const bm::ToolModel* tool = this->Internals->Get(this->ToolType, this->Parameters);
  range[0] = range[1] = 0.0;
  if (tool) {
    const std::array<double, 2> r = tool->AxialRange();
    range[0] = r[0];
    range[1] = r[1];
  }
}

const char* vtkBMToolSource::GetToolSpecification() {
  const bm::ToolModel* tool = this->Internals->Get(this->ToolType, this->Parameters);
  this->Internals->Specification = tool ? tool->Parameters().dump() : std::string();
  return this->Internals->Specification.c_str();
}

double* vtkBMToolSource::GetAxialRange() {
  this->GetAxialRange(this->AxialRange);
  return this->AxialRange;
}

int vtkBMToolSource::RequestData(vtkInformation*, vtkInformationVector**,
                                 vtkInformationVector* outputVector) {
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  const bm::ToolModel* tool = this->Internals->Get(this->ToolType, this->Parameters);
  if (!tool) {
    vtkErrorMacro(<< "invalid " << this->GetToolTypeAsString()
                  << " parameters: " << this->Internals->Error);
    return 0;
  }
  const std::vector<bm::ProfilePoint> profile = tool->Profile(this->MaxSegmentLength);
  const int n = this->Resolution;

  // One point per pole vertex (on the axis), one ring of n points per other vertex.
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  std::vector<vtkIdType> first(profile.size()); // id of each vertex's first point
  std::vector<double> cosPhi(n), sinPhi(n);
  for (int j = 0; j < n; ++j) {
    const double phi = 2.0 * std::numbers::pi * j / n;
    cosPhi[j] = std::cos(phi);
    sinPhi[j] = std::sin(phi);
  }
  auto isPole = [&](size_t i) { return profile[i].rho <= kPoleRadius; };
  for (size_t i = 0; i < profile.size(); ++i) {
    first[i] = points->GetNumberOfPoints();
    if (isPole(i)) {
      points->InsertNextPoint(0.0, 0.0, profile[i].z);
      continue;
    }
    for (int j = 0; j < n; ++j)
      points->InsertNextPoint(profile[i].rho * cosPhi[j], profile[i].rho * sinPhi[j], profile[i].z);
  }

  // Facets between consecutive outline vertices. Vertex order (around phi, then along the outline)
  // makes the right-hand normal point out of the solid.
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkUnsignedCharArray> edgeKind;
  edgeKind->SetName("EdgeKind");
  auto id = [&](size_t i, int j) { return isPole(i) ? first[i] : first[i] + (j % n); };
  for (size_t i = 0; i + 1 < profile.size(); ++i) {
    const bool pole0 = isPole(i), pole1 = isPole(i + 1);
    const bool samePlace = profile[i].rho == profile[i + 1].rho && profile[i].z == profile[i + 1].z;
    if ((pole0 && pole1) || samePlace)
      continue;
    const auto kind = static_cast<unsigned char>(profile[i].kind);
    for (int j = 0; j < n; ++j) {
      if (pole0) {
        const vtkIdType tri[3] = {id(i, j), id(i + 1, j + 1), id(i + 1, j)};
        polys->InsertNextCell(3, tri);
      } else if (pole1) {
        const vtkIdType tri[3] = {id(i, j), id(i, j + 1), id(i + 1, j)};
        polys->InsertNextCell(3, tri);
      } else {
        const vtkIdType quad[4] = {id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)};
        polys->InsertNextCell(4, quad);
      }
      edgeKind->InsertNextValue(kind);
    }
  }

  vtkNew<vtkPolyData> surface;
  surface->SetPoints(points);
  surface->SetPolys(polys);
  surface->GetCellData()->AddArray(edgeKind);

  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(surface);
  normals->SetFeatureAngle(30.0);
  normals->SplittingOn();
  normals->ConsistencyOff(); // the facets are already oriented outward
  normals->AutoOrientNormalsOff();
  normals->ComputePointNormalsOn();
  normals->ComputeCellNormalsOff();
  normals->Update();
  output->ShallowCopy(normals->GetOutput());
  return 1;
}

void vtkBMToolSource::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ToolType: " << this->ToolType << " (" << this->GetToolTypeAsString() << ")\n";
  os << indent << "Parameters: " << (this->Parameters ? this->Parameters : "(none)") << "\n";
  os << indent << "Resolution: " << this->Resolution << "\n";
  os << indent << "MaxSegmentLength: " << this->MaxSegmentLength << " mm\n";
}
