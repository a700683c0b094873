// bmCTImage.h - a CT volume in Hounsfield units (or raw values when the user asked for them,
// see `intensity`) with what was read about it.
//
// World coordinates are the CT's patient coordinates in mm as ITK reads them (DICOM LPS: x toward
// the patient's left, y posterior, z superior); the image may be oblique (its direction matrix).
// Everything downstream (segmentation, the voxmap, tools in a scene) uses the same world mm.
#pragma once

#include "bmIntensityMapping.h"
#include "bmVoxmap.h" // bm::Box3

#include <itkImage.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace bm {

/// Hounsfield units, float (exact for every integer HU and every rescaled value GDCM produces).
using HUImage = itk::Image<float, 3>;

struct CTImage {
  HUImage::Pointer hu;
  std::string source;            ///< path that was read (folder or file)
  std::string format;            ///< "DICOM", "NRRD", "MetaImage", "NIfTI" or "InVesalius"
  std::string modality;          ///< DICOM Modality (e.g. "CT"); "" when the format does not say
  std::string seriesUID;         ///< DICOM SeriesInstanceUID ("" otherwise)
  std::string seriesDescription; ///< DICOM SeriesDescription ("" otherwise)
  std::string transferSyntax;    ///< DICOM transfer syntax of the first slice ("" otherwise)
  int numFiles = 0;              ///< number of files read (DICOM: slices)
  float huMin = 0, huMax = 0;    ///< HU range of the voxels
  std::vector<std::string> warnings; ///< things the user should know (odd HU range, ...)
  /// How the series or file was chosen when that was not obvious (e.g. a series without
  /// SeriesInstanceUID grouped by other attributes, one file standing for its series).
  std::vector<std::string> notes;
  /// What the voxel values mean (HU, a given mapping, raw values) and why (bmIntensityMapping.h).
  IntensityMapping intensity;

  std::array<int, 3> Size() const;
  std::array<double, 3> Spacing() const; ///< mm, along the image's own axes
  /// Axis-aligned world box (mm) around the outer faces of all voxels.
  Box3 WorldBounds() const;
  /// Bytes of the HU image.
  uint64_t Bytes() const;
};

/// World-axis-aligned box (mm) around the outer faces of the voxels of `region` of `image`.
template <class TImage>
Box3 WorldBoxOfRegion(const TImage* image, const typename TImage::RegionType& region);

} // namespace bm

#include "bmCTImage.txx"
