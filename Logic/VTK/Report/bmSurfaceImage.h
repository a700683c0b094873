// bmSurfaceImage.h - a rendered picture of a surface (the cut bone) for reports and scene tests.
//
// Off-screen VTK rendering with an orthographic camera. Rendering needs an X display (Debian's
// ParaView VTK renders through GLX only): RenderSurface calls bm::VirtualDisplay::Ensure() first.
#pragma once

#include <array>
#include <string>

#include <vtkSmartPointer.h>

class vtkImageData;
class vtkPolyData;

namespace bm {

struct SurfaceView {
  std::array<double, 3> focalMm{0, 0, 0};  ///< world point at the image centre, mm
  std::array<double, 3> toCamera{0, 0, 1}; ///< unit direction from the focal point to the eye
  std::array<double, 3> viewUp{0, 1, 0};   ///< world direction shown upward
  double halfHeightMm = 25;                ///< half the image height in world mm (parallel)
  int widthPx = 800, heightPx = 800;
};

/// Replaces `mesh`'s point data with the RGB point array "Colors" that RenderSurface draws, every
/// point `rgb` (0..255).
void PaintPoints(vtkPolyData* mesh, const unsigned char rgb[3]);
/// Bone ivory, as RenderSurface draws a surface without colours (RGB 0..255).
extern const unsigned char kBoneIvory[3];

/// Renders `surface` (RGB point array "Colors" when present, otherwise bone ivory) as seen from
/// `view`, lit by a headlight, on a dark background. Returns the RGB image.
vtkSmartPointer<vtkImageData> RenderSurface(vtkPolyData* surface, const SurfaceView& view);
/// RenderSurface written to `path` as PNG (atomically). Throws std::runtime_error on failure.
void WriteSurfacePng(const std::string& path, vtkPolyData* surface, const SurfaceView& view);
/// Writes an RGB image as PNG (atomically). Throws std::runtime_error on failure.
void WritePng(const std::string& path, vtkImageData* image);

} // namespace bm
