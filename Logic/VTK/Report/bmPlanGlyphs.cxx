// bmPlanGlyphs.cxx - see bmPlanGlyphs.h.
#include "bmPlanGlyphs.h"

#include <vtkAppendPolyData.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkIntArray.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkTubeFilter.h>
#include <vtkVectorText.h>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace bm {
namespace {

constexpr double kPi = 3.14159265358979323846;

const unsigned char kColours[kPlanGlyphParts][3] = {{220, 40, 40},   // planned axis: red
                                                    {40, 190, 60},   // face normal: green
                                                    {250, 250, 250}, // reamer outline: white
                                                    {240, 200, 40},  // rim: yellow
                                                    {220, 60, 220},  // glenoid centre: magenta
                                                    {60, 140, 255},  // trigonum: blue
                                                    {0, 200, 200}};  // inferior angle: cyan
const char* const kNames[kPlanGlyphParts] = {
    "planned axis", "face normal", "reamer", "rim", "glenoid centre", "trigonum", "inferior angle"};

Eigen::Vector3d Vec(const nlohmann::json& j, const std::string& what) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throw std::invalid_argument("the plan's '" + what + "' must be an array of 3 numbers");
  const Eigen::Vector3d v(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
  if (!v.allFinite())
    throw std::invalid_argument("the plan's '" + what + "' is not finite");
  return v;
}

/// Every point of `mesh` in the part's colour, every cell marked with the part; no other arrays.
void Mark(vtkPolyData* mesh, PlanGlyphPart part) {
  PaintPoints(mesh, PlanGlyphColour(part));
  mesh->GetCellData()->Initialize();
  vtkNew<vtkIntArray> parts;
  parts->SetName("Part");
  parts->SetNumberOfTuples(mesh->GetNumberOfCells());
  parts->FillValue(int(part));
  mesh->GetCellData()->AddArray(parts);
}

/// A polyline through `points` (closed: back to the first) as a capped tube.
vtkSmartPointer<vtkPolyData> Tube(const std::vector<Eigen::Vector3d>& points, bool closed,
                                  double radiusMm, PlanGlyphPart part) {
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
  Mark(out, part);
  return out;
}

vtkSmartPointer<vtkPolyData> Sphere(const Eigen::Vector3d& c, double radiusMm, PlanGlyphPart part) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(c.data());
  sphere->SetRadius(radiusMm);
  sphere->SetThetaResolution(16);
  sphere->SetPhiResolution(12);
  sphere->Update();
  vtkSmartPointer<vtkPolyData> out = sphere->GetOutput();
  Mark(out, part);
  return out;
}

/// The part's name in letters `heightMm` high, its lower left corner at `at`, in the plane that
/// faces `view` (x along the view's right, y along its up).
vtkSmartPointer<vtkPolyData> Label(const Eigen::Vector3d& at, double heightMm,
                                   const SurfaceView& view, PlanGlyphPart part) {
  const Eigen::Vector3d toCamera(view.toCamera[0], view.toCamera[1], view.toCamera[2]);
  const Eigen::Vector3d up(view.viewUp[0], view.viewUp[1], view.viewUp[2]);
  const Eigen::Vector3d right = up.cross(toCamera);
  vtkNew<vtkVectorText> text;
  text->SetText(PlanGlyphName(part));
  vtkNew<vtkMatrix4x4> m;
  for (int r = 0; r < 3; ++r) {
    m->SetElement(r, 0, heightMm * right[r]);
    m->SetElement(r, 1, heightMm * up[r]);
    m->SetElement(r, 2, heightMm * toCamera[r]);
    m->SetElement(r, 3, at[r]);
  }
  vtkNew<vtkTransform> place;
  place->SetMatrix(m);
  vtkNew<vtkTransformPolyDataFilter> placed;
  placed->SetInputConnection(text->GetOutputPort());
  placed->SetTransform(place);
  placed->Update();
  vtkSmartPointer<vtkPolyData> out = placed->GetOutput();
  Mark(out, part);
  return out;
}

} // namespace

const unsigned char* PlanGlyphColour(PlanGlyphPart part) {
  return kColours[int(part)];
}

const char* PlanGlyphName(PlanGlyphPart part) {
  return kNames[int(part)];
}

SurfaceView PlanView(const nlohmann::json& planning, int sizePx) {
  if (!planning.is_object() || !planning.contains("entry_mm") || !planning.contains("axis"))
    throw std::invalid_argument("the plan has no 'planning' block with 'entry_mm' and 'axis'");
  const Eigen::Vector3d centre = Vec(planning["entry_mm"], "entry_mm");
  Eigen::Vector3d axis = Vec(planning["axis"], "axis");
  if (!(axis.norm() > 0))
    throw std::invalid_argument("the plan's 'axis' is zero");
  axis.normalize();
  int least = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(axis[a]) < std::abs(axis[least]))
      least = a;
  Eigen::Vector3d up = Eigen::Vector3d::Unit(least);
  up = (up - up.dot(axis) * axis).normalized();
  const double tilt = 30.0 * kPi / 180.0;
  const Eigen::Vector3d toCamera = (std::cos(tilt) * axis - std::sin(tilt) * up).normalized();
  up = (up - up.dot(toCamera) * toCamera).normalized(); // square to the line of sight
  SurfaceView view;
  view.focalMm = {centre.x(), centre.y(), centre.z()};
  view.toCamera = {toCamera.x(), toCamera.y(), toCamera.z()};
  view.viewUp = {up.x(), up.y(), up.z()};
  view.halfHeightMm = 1.4 * 0.5 * planning.value("reamer_diameter_mm", 36.5);
  view.widthPx = view.heightPx = sizePx;
  return view;
}

vtkSmartPointer<vtkPolyData> MakePlanGlyphs(const nlohmann::json& planning,
                                            const PlanGlyphOptions& options) {
  const SurfaceView view = PlanView(planning);
  const Eigen::Vector3d entry = Vec(planning["entry_mm"], "entry_mm");
  const Eigen::Vector3d axis = Vec(planning["axis"], "axis").normalized();
  const double reamerRadius = 0.5 * planning.value("reamer_diameter_mm", 36.5);
  const nlohmann::json landmarks = planning.value("landmarks", nlohmann::json::object());
  const Eigen::Vector3d up(view.viewUp[0], view.viewUp[1], view.viewUp[2]);
  const double gap = 0.4 * options.labelHeightMm;

  vtkNew<vtkAppendPolyData> append;
  auto add = [&](vtkSmartPointer<vtkPolyData> mesh) { append->AddInputData(mesh); };
  auto label = [&](const Eigen::Vector3d& at, PlanGlyphPart part) {
    if (options.labels)
      add(Label(at, options.labelHeightMm, view, part));
  };
  const Eigen::Vector3d right(view.toCamera[1] * up[2] - view.toCamera[2] * up[1],
                              view.toCamera[2] * up[0] - view.toCamera[0] * up[2],
                              view.toCamera[0] * up[1] - view.toCamera[1] * up[0]);
  const double h = options.labelHeightMm;
  // Labels on the bone are lifted toward the plan's camera, out of the concave face that would
  // hide them.
  const Eigen::Vector3d toCamera(view.toCamera[0], view.toCamera[1], view.toCamera[2]);
  const double lift = 10.0;
  // Labels beside their parts, to the right on the plan's picture (the camera looks down the
  // axis: the axis's and the normal's labels sit a third of the way out, where they are seen).
  const Eigen::Vector3d axisEnd = entry + options.axisLengthMm * axis;
  add(Tube({entry, axisEnd}, false, 0.5, PlanGlyphPart::Axis));
  label(entry + 0.3 * options.axisLengthMm * axis + gap * right, PlanGlyphPart::Axis);
  const Eigen::Vector3d centre = landmarks.contains("glenoid_centre_mm")
                                     ? Vec(landmarks["glenoid_centre_mm"], "glenoid_centre_mm")
                                     : entry;
  if (landmarks.contains("face_normal")) {
    const Eigen::Vector3d n = Vec(landmarks["face_normal"], "landmarks.face_normal").normalized();
    const Eigen::Vector3d end = centre + options.normalLengthMm * n;
    add(Tube({centre, end}, false, 0.4, PlanGlyphPart::FaceNormal));
    label(end + gap * right - h * up, PlanGlyphPart::FaceNormal);
  }
  // The planned face plane: the reamer's outline around the entry, across the axis.
  const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
  std::vector<Eigen::Vector3d> circle;
  for (int k = 0; k < 96; ++k) {
    const double t = 2 * kPi * k / 96.0;
    circle.push_back(entry + reamerRadius * (std::cos(t) * u + std::sin(t) * v));
  }
  add(Tube(circle, true, 0.25, PlanGlyphPart::ReamerOutline));
  const Eigen::Vector3d across = (up - up.dot(axis) * axis).normalized();
  label(entry - (reamerRadius + gap + h) * across, PlanGlyphPart::ReamerOutline);
  if (landmarks.contains("rim_mm") && landmarks["rim_mm"].is_array() &&
      landmarks["rim_mm"].size() >= 3) {
    std::vector<Eigen::Vector3d> rim;
    for (const auto& p : landmarks["rim_mm"])
      rim.push_back(Vec(p, "landmarks.rim_mm"));
    add(Tube(rim, true, 0.3, PlanGlyphPart::Rim));
    // Beside the rim's rightmost point on the picture.
    Eigen::Vector3d side = rim[0];
    for (const auto& p : rim)
      if (p.dot(right) > side.dot(right))
        side = p;
    label(side + gap * right + lift * toCamera, PlanGlyphPart::Rim);
  }
  const std::pair<const char*, PlanGlyphPart> points[] = {
      {"glenoid_centre_mm", PlanGlyphPart::GlenoidCentre},
      {"trigonum_mm", PlanGlyphPart::Trigonum},
      {"inferior_angle_mm", PlanGlyphPart::InferiorAngle}};
  for (const auto& [key, part] : points)
    if (landmarks.contains(key)) {
      const Eigen::Vector3d p = Vec(landmarks[key], std::string("landmarks.") + key);
      add(Sphere(p, 1.5, part));
      label(p + (1.5 + gap) * right - h * up + lift * toCamera, part);
    }
  append->Update();
  vtkSmartPointer<vtkPolyData> out = append->GetOutput();
  return out;
}

} // namespace bm
