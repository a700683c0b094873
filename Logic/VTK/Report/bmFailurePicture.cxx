// bmFailurePicture.cxx - see bmFailurePicture.h.
#include "bmFailurePicture.h"

#include "bmBoneSurface.h"
#include "bmSurfaceImage.h"
#include "bmVoxmap.h"

#include <vtkAppendPolyData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>
#include <vtkSphereSource.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkVectorText.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace bm {
void WriteFailurePicture(const std::string& path, const Voxmap& bone,
                         const std::vector<std::array<double, 3>>& marks, int sizePx) {
  BoneSurface extractor;
  extractor.Update(bone);
  vtkNew<vtkPolyData> surface;
  surface->DeepCopy(extractor.GetOutput());
  if (surface->GetNumberOfPoints() == 0)
    throw std::runtime_error("no bone surface to draw");
  const unsigned char yellow[3] = {250, 210, 0};
  PaintPoints(surface, kBoneIvory);
  double b[6];
  surface->GetBounds(b);
  const double size = std::max({b[1] - b[0], b[3] - b[2], b[5] - b[4]});
  const double radius = std::max(2.0, 0.02 * size), letters = 2.5 * radius;
  vtkNew<vtkAppendPolyData> append;
  append->AddInputData(surface);
  // Marks within two sphere radii of an earlier one (a pair seen from each side: "bone 1 facing
  // bone 4", "bone 4 facing bone 1") share its sphere and label: "1, 2".
  std::vector<std::string> labels(marks.size());
  std::vector<bool> merged(marks.size(), false);
  for (size_t i = 0; i < marks.size(); ++i) {
    if (merged[i])
      continue;
    labels[i] = std::to_string(i + 1);
    for (size_t k = i + 1; k < marks.size(); ++k) {
      const double dx = marks[k][0] - marks[i][0], dy = marks[k][1] - marks[i][1],
                   dz = marks[k][2] - marks[i][2];
      if (!merged[k] && dx * dx + dy * dy + dz * dz < 4 * radius * radius) {
        merged[k] = true;
        labels[i] += ", " + std::to_string(k + 1);
      }
    }
  }
  for (size_t i = 0; i < marks.size(); ++i) {
    if (merged[i])
      continue;
    const std::array<double, 3>& m = marks[i];
    vtkNew<vtkSphereSource> sphere;
    sphere->SetCenter(m[0], m[1], m[2]);
    sphere->SetRadius(radius);
    sphere->SetThetaResolution(16);
    sphere->SetPhiResolution(12);
    sphere->Update();
    vtkNew<vtkPolyData> ball;
    ball->DeepCopy(sphere->GetOutput());
    PaintPoints(ball, yellow);
    append->AddInputData(ball);
    // The number in front of the mark (toward the camera, -y), in the x-z plane facing it: x
    // (the patient's left) appears on the picture's right, as a CT is read from the front.
    vtkNew<vtkVectorText> text;
    text->SetText(labels[i].c_str());
    vtkNew<vtkMatrix4x4> place;
    place->Zero();
    place->SetElement(0, 0, letters);  // text x -> world x
    place->SetElement(2, 1, letters);  // text y -> world z (superior)
    place->SetElement(1, 2, -letters); // text z -> world -y (toward the camera)
    place->SetElement(0, 3, m[0] + 1.2 * radius);
    place->SetElement(1, 3, b[2] - radius); // in front of all the bone
    place->SetElement(2, 3, m[2] + 0.5 * radius);
    place->SetElement(3, 3, 1);
    vtkNew<vtkTransform> transform;
    transform->SetMatrix(place);
    vtkNew<vtkTransformPolyDataFilter> placed;
    placed->SetInputConnection(text->GetOutputPort());
    placed->SetTransform(transform);
    placed->Update();
    vtkNew<vtkPolyData> number;
    number->DeepCopy(placed->GetOutput());
    PaintPoints(number, yellow);
    append->AddInputData(number);
  }
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputConnection(append->GetOutputPort());
  normals->SplittingOff();
  normals->ConsistencyOff();
  normals->Update();
  SurfaceView view;
  view.focalMm = {0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])};
  view.toCamera = {0, -1, 0}; // from the front (anterior, LPS -y)
  view.viewUp = {0, 0, 1};
  view.halfHeightMm = 0.55 * std::max(b[1] - b[0], b[5] - b[4]);
  view.widthPx = view.heightPx = sizePx;
  WriteSurfacePng(path, normals->GetOutput(), view);
}

} // namespace bm
