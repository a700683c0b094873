// bmGlenoidPictures.cxx - see bmGlenoidPictures.h.
#include "bmGlenoidPictures.h"

#include "bmBoneSurface.h"
#include "bmPlanGlyphs.h"
#include "bmSurfaceImage.h"
#include "bmVoxmap.h"

#include <vtkAppendPolyData.h>
#include <vtkCellData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace bm {
namespace {

/// The bone's surface, ivory, with the overlays appended, and normals for shading.
vtkSmartPointer<vtkPolyData> Scene(const Voxmap& bone, vtkPolyData* glyphs) {
  BoneSurface extractor;
  extractor.Update(bone);
  vtkNew<vtkPolyData> surface;
  surface->DeepCopy(extractor.GetOutput());
  surface->GetPointData()->Initialize();
  PaintPoints(surface, kBoneIvory);
  vtkNew<vtkPolyData> overlay;
  overlay->ShallowCopy(glyphs);
  overlay->GetCellData()->Initialize(); // only the colours travel through the append
  vtkNew<vtkAppendPolyData> append;
  append->AddInputData(surface);
  append->AddInputData(overlay);
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
  const SurfaceView view = PlanView(planning, sizePx); // throws naming a missing key
  const vtkSmartPointer<vtkPolyData> glyphs = MakePlanGlyphs(planning);

  const std::filesystem::path d(dir);
  std::filesystem::create_directories(d);
  GlenoidPictureFiles files{"glenoid_before.png", "glenoid_after.png"};
  WriteSurfacePng((d / files.before).string(), Scene(before, glyphs), view);
  WriteSurfacePng((d / files.after).string(), Scene(after, glyphs), view);
  return files;
}

} // namespace bm
