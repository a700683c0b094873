// bmTestFlyingEdges.h - the reference surface of the Report tests: vtkFlyingEdges3D run once over
// a voxmap's whole grid, padded by a void sample on each side as bm::BoneSurface pads it, at fill
// fraction 0.5. The surfaces the bricks add up to must equal it.
#pragma once

#include <vtkFloatArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include "bmVoxmap.h"

namespace bm::test {

/// Flying edges over the padded grid of `v` (world mm), with point normals when `normals`.
inline vtkSmartPointer<vtkPolyData> WholeGridFlyingEdges(const bm::Voxmap& v, bool normals) {
  const auto& d = v.Dims();
  vtkNew<vtkImageData> image;
  image->SetDimensions(d[0] + 2, d[1] + 2, d[2] + 2);
  image->SetSpacing(v.Spacing(), v.Spacing(), v.Spacing());
  image->SetOrigin(v.Origin()[0] - v.Spacing(), v.Origin()[1] - v.Spacing(),
                   v.Origin()[2] - v.Spacing());
  vtkNew<vtkFloatArray> values;
  values->SetNumberOfValues(vtkIdType(d[0] + 2) * (d[1] + 2) * (d[2] + 2));
  vtkIdType n = 0;
  for (int k = -1; k <= d[2]; ++k)
    for (int j = -1; j <= d[1]; ++j)
      for (int i = -1; i <= d[0]; ++i)
        values->SetValue(n++, v.Contains(i, j, k) ? float(v.Fraction(v.Index(i, j, k))) : 0.0f);
  image->GetPointData()->SetScalars(values);
  vtkNew<vtkFlyingEdges3D> edges;
  edges->SetInputData(image);
  edges->SetValue(0, 0.5);
  edges->SetComputeNormals(normals);
  edges->Update();
  vtkSmartPointer<vtkPolyData> out = edges->GetOutput();
  return out;
}

} // namespace bm::test
