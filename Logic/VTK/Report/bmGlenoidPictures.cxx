// bmGlenoidPictures.cxx - see bmGlenoidPictures.h.
#include "bmGlenoidPictures.h"

#include "bmBoneSurface.h"
#include "bmSurfaceImage.h"
#include "bmVoxmap.h"

#include <vtkAppendPolyData.h>
#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>
#include <vtkTubeFilter.h>
#include <vtkUnsignedCharArray.h>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace bm {
namespace {

using RGB = std::array<unsigned char, 3>;

Eigen::Vector3d Vec(const nlohmann::json& j, const std::string& what) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throw std::invalid_argument("the plan's '" + what + "' must be an array of 3 numbers");
  const Eigen::Vector3d v(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
  if (!v.allFinite())
    throw std::invalid_argument("the plan's '" + what + "' is not finite");
  return v;
}

/// Every point of `mesh` coloured `rgb` (the "Colors" array bmSurfaceImage.h draws).
void Paint(vtkPolyData* mesh, const RGB& rgb) {
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  colors->SetNumberOfTuples(mesh->GetNumberOfPoints());
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
    colors->SetTypedTuple(i, rgb.data());
  mesh->GetPointData()->AddArray(colors);
}

/// A polyline through `points` (closed: back to the first) as a tube of radius `radiusMm`.
vtkSmartPointer<vtkPolyData> Tube(const std::vector<Eigen::Vector3d>& points, bool closed,
                                  double radiusMm, const RGB& rgb) {
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> lines;
  const vtkIdType n = vtkIdType(points.size());
  lines->InsertNextCell(n + (closed ? 1 : 0));
  for (vtkIdType i = 0; i < n; ++i) {
    pts->InsertNextPoint(points[size_t(i)].data());
    lines->InsertCellPoint(i);
  }
  if (closed)
    lines->InsertCellPoint(0);
  vtkNew<vtkPolyData> line;
  line->SetPoints(pts);
  line->SetLines(lines);
  vtkNew<vtkTubeFilter> tube;
  tube->SetInputData(line);
  tube->SetRadius(radiusMm);
  tube->SetNumberOfSides(12);
  tube->CappingOn();
  tube->Update();
  vtkSmartPointer<vtkPolyData> out = tube->GetOutput();
  out->GetPointData()->Initialize(); // only the colours below travel through the append
  Paint(out, rgb);
  return out;
}

/// The bone's surface, ivory, with the overlays appended, and normals for shading.
vtkSmartPointer<vtkPolyData> Scene(const Voxmap& bone,
                                   const std::vector<vtkSmartPointer<vtkPolyData>>& overlays) {
  BoneSurface extractor;
  extractor.Update(bone);
  vtkNew<vtkPolyData> surface;
  surface->DeepCopy(extractor.GetOutput());
  surface->GetPointData()->Initialize();
  Paint(surface, {237, 227, 199});
  vtkNew<vtkAppendPolyData> append;
  append->AddInputData(surface);
  for (const auto& o : overlays)
    append->AddInputData(o);
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputConnection(append->GetOutputPort());
  normals->SplittingOff();
  normals->ConsistencyOff();
  normals->Update();
  return normals->GetOutput();
}

} // namespace

GlenoidPictureFiles WriteGlenoidPictures(const std::string& dir, const Voxmap& before,
                                         const Voxmap& after, const nlohmann::json& planning,
                                         int sizePx) {
  if (!planning.is_object() || !planning.contains("entry_mm") || !planning.contains("axis"))
    throw std::invalid_argument("the plan has no 'planning' block with 'entry_mm' and 'axis'");
  const Eigen::Vector3d centre = Vec(planning["entry_mm"], "entry_mm");
  Eigen::Vector3d axis = Vec(planning["axis"], "axis");
  if (!(axis.norm() > 0))
    throw std::invalid_argument("the plan's 'axis' is zero");
  axis.normalize();
  const double reamerRadius = 0.5 * planning.value("reamer_diameter_mm", 36.5);
  const nlohmann::json landmarks = planning.value("landmarks", nlohmann::json::object());

  // Overlays: axis, face normal, face plane circle, rim.
  std::vector<vtkSmartPointer<vtkPolyData>> overlays;
  overlays.push_back(Tube({centre, centre + 40.0 * axis}, false, 0.5, {220, 40, 40}));
  if (landmarks.contains("face_normal")) {
    const Eigen::Vector3d n = Vec(landmarks["face_normal"], "landmarks.face_normal").normalized();
    overlays.push_back(Tube({centre, centre + 25.0 * n}, false, 0.4, {40, 190, 60}));
  }
  // Two directions across the axis for the circle (any pair perpendicular to it).
  Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
  std::vector<Eigen::Vector3d> circle;
  for (int k = 0; k < 96; ++k) {
    const double t = 2 * 3.14159265358979323846 * k / 96.0;
    circle.push_back(centre + reamerRadius * (std::cos(t) * u + std::sin(t) * v));
  }
  overlays.push_back(Tube(circle, true, 0.25, {250, 250, 250}));
  if (landmarks.contains("rim_mm") && landmarks["rim_mm"].is_array() &&
      landmarks["rim_mm"].size() >= 3) {
    std::vector<Eigen::Vector3d> rim;
    for (const auto& p : landmarks["rim_mm"])
      rim.push_back(Vec(p, "landmarks.rim_mm"));
    overlays.push_back(Tube(rim, true, 0.3, {240, 200, 40}));
  }

  // Down the axis, tilted 30 deg toward the world axis least aligned with it.
  int least = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(axis[a]) < std::abs(axis[least]))
      least = a;
  Eigen::Vector3d up = Eigen::Vector3d::Unit(least);
  up = (up - up.dot(axis) * axis).normalized();
  const double tilt = 30.0 * 3.14159265358979323846 / 180.0;
  const Eigen::Vector3d toCamera = (std::cos(tilt) * axis - std::sin(tilt) * up).normalized();
  SurfaceView view;
  view.focalMm = {centre.x(), centre.y(), centre.z()};
  view.toCamera = {toCamera.x(), toCamera.y(), toCamera.z()};
  view.viewUp = {up.x(), up.y(), up.z()};
  view.halfHeightMm = 1.4 * reamerRadius;
  view.widthPx = view.heightPx = sizePx;

  const std::filesystem::path d(dir);
  std::filesystem::create_directories(d);
  GlenoidPictureFiles files{"glenoid_before.png", "glenoid_after.png"};
  WriteSurfacePng((d / files.before).string(), Scene(before, overlays), view);
  WriteSurfacePng((d / files.after).string(), Scene(after, overlays), view);
  return files;
}

} // namespace bm
