// bmVTKImageVolume.h - a CT held as VTK image data (an image open in ParaView, a .vti or legacy
// .vtk file) handed to the CT import as a bm::CTVolumeView (bmCTVoxmap.h): the BM CT Bone source
// and `bmsim import FILE.vti` read VTK images this one way (the volume with the IO library only).
#pragma once

#include <string>
#include <vector>

#include "vtkSmartPointer.h"
#ifdef BM_WITH_IO
#include "bmCTVoxmap.h"
#endif

class vtkImageData;

namespace bm {

/// Whether the path names a VTK image file (.vti XML image data, .vtk legacy structured points).
bool IsVTKImageFile(const std::string& path);
/// The VTK image files read here: ".vti" (XML image data) and ".vtk" (legacy).
const std::vector<std::string>& VTKImageExtensions();

/// Reads a VTK image file; throws std::runtime_error naming the file when it is missing, not a
/// regular file, or holds no image points.
vtkSmartPointer<vtkImageData> ReadVTKImageFile(const std::string& path);

#ifdef BM_WITH_IO
/// An image's first point scalars (or first point array) as float values with the image's grid.
struct VTKImageVolume {
  std::vector<float> values; ///< the image's values, x fastest (HU unless told otherwise)
  CTVolumeView view;         ///< points into `values`: valid while this object lives unmoved
};

/// The image as a volume: dims from its extent, spacing (mm), direction, and the world position
/// (mm) of its first voxel (origin + D (extent minimum x spacing)); `source` names it in reports.
/// Throws std::runtime_error when the image has no point values.
void VolumeFromVTKImage(vtkImageData* image, const std::string& source, VTKImageVolume& out);

#endif

} // namespace bm
