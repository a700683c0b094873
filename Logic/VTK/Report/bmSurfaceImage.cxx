// bmSurfaceImage.cxx - see bmSurfaceImage.h.
#include "bmSurfaceImage.h"

#include <filesystem>
#include <stdexcept>

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include "bmAtomicFile.h"
#include "bmVirtualDisplay.h"

namespace bm {

const unsigned char kBoneIvory[3] = {237, 227, 199};

void PaintPoints(vtkPolyData* mesh, const unsigned char rgb[3]) {
  mesh->GetPointData()->Initialize();
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetName("Colors");
  colours->SetNumberOfComponents(3);
  colours->SetNumberOfTuples(mesh->GetNumberOfPoints());
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
    colours->SetTypedTuple(i, rgb);
  mesh->GetPointData()->AddArray(colours);
}

vtkSmartPointer<vtkImageData> RenderSurface(vtkPolyData* surface, const SurfaceView& view) {
  VirtualDisplay::Ensure();
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(surface);
  if (surface->GetPointData()->GetArray("Colors")) {
    mapper->SetScalarModeToUsePointFieldData();
    mapper->SelectColorArray("Colors");
    mapper->SetColorModeToDirectScalars();
    mapper->ScalarVisibilityOn();
  } else {
    mapper->ScalarVisibilityOff();
  }
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.93, 0.89, 0.78); // bone ivory
  actor->GetProperty()->SetSpecular(0.15);
  actor->GetProperty()->SetSpecularPower(20);

  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  renderer->SetBackground(0.12, 0.13, 0.16);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->ParallelProjectionOn();
  camera->SetFocalPoint(view.focalMm.data());
  const double distance = 10.0 * view.halfHeightMm;
  camera->SetPosition(view.focalMm[0] + distance * view.toCamera[0],
                      view.focalMm[1] + distance * view.toCamera[1],
                      view.focalMm[2] + distance * view.toCamera[2]);
  camera->SetViewUp(view.viewUp.data());
  camera->OrthogonalizeViewUp();
  camera->SetParallelScale(view.halfHeightMm);
  camera->SetClippingRange(distance * 0.01, distance * 3.0);

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(view.widthPx, view.heightPx);
  window->AddRenderer(renderer);
  window->Render();

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  vtkSmartPointer<vtkImageData> image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(grab->GetOutput());
  return image;
}

void WritePng(const std::string& path, vtkImageData* image) {
  const std::string tmp = TemporarySibling(path);
  vtkNew<vtkPNGWriter> png;
  png->SetFileName(tmp.c_str());
  png->SetInputData(image);
  png->Write();
  std::error_code ec;
  if (png->GetErrorCode() != 0 || !std::filesystem::exists(tmp)) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error("cannot write " + path);
  }
  std::filesystem::rename(tmp, path);
}

void WriteSurfacePng(const std::string& path, vtkPolyData* surface, const SurfaceView& view) {
  WritePng(path, RenderSurface(surface, view));
}

} // namespace bm
