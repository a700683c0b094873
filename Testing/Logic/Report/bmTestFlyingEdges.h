// bmTestFlyingEdges.h - what the Report tests share: the reference surface (vtkFlyingEdges3D run
// once over a voxmap's whole grid, padded by a void sample on each side as bm::BoneSurface pads
// it, at fill fraction 0.5; the surfaces the bricks add up to must equal it) and the cut they
// make with a ball tool.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

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

/// One cut: a ball tool of radius r (mm) at `centre` (world mm) takes `share` of the bone it
/// overlaps (the overlap ramped over one voxel of `voxelMm`). offIso > 0: a fill left within
/// offIso units of half a voxel is lowered to half a voxel less offIso (keeps samples off the
/// iso, where float rounding could tip a sample either side).
inline void CutBall(bm::Voxmap& v, const std::array<double, 3>& centre, double r, double share,
                    double voxelMm, bm::Voxmap::Fill offIso = 0) {
  constexpr bm::Voxmap::Fill kHalf = bm::Voxmap::kFull / 2;
  for (int k = 0; k < v.Dims()[2]; ++k)
    for (int j = 0; j < v.Dims()[1]; ++j)
      for (int i = 0; i < v.Dims()[0]; ++i) {
        const auto p = v.GridToWorld({double(i), double(j), double(k)});
        const double d = std::sqrt((p[0] - centre[0]) * (p[0] - centre[0]) +
                                   (p[1] - centre[1]) * (p[1] - centre[1]) +
                                   (p[2] - centre[2]) * (p[2] - centre[2]));
        const double overlap = std::clamp(0.5 + (r - d) / voxelMm, 0.0, 1.0);
        const auto units = bm::Voxmap::Fill(overlap * share * bm::Voxmap::kFull);
        const int64_t idx = v.Index(i, j, k);
        bool voided = false;
        if (units > 0 && v.GetFill(idx) > 0) {
          v.Remove(idx, units, voided);
          const bm::Voxmap::Fill f = v.GetFill(idx);
          if (offIso > 0 && std::abs(f - kHalf) < offIso)
            v.Remove(idx, f - (kHalf - offIso), voided);
        }
      }
}

} // namespace bm::test
