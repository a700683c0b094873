// bmPhantom.h - synthetic CTs with analytic bone, for demos, scene tests and the import checks.
//
// The phantoms' shapes, volumes and tissues: bmAnalyticPhantom.h (Core, no ITK). Here each tissue
// gets its HU: cortical 1500 (the block 1600), cancellous 300 (the humeral head 250), the pilot
// hole's fluid 0, soft tissue 40 (around the block: air, -1000); the shoulder's CT is blurred by
// the scanner's point spread (Gaussian, sigma 1.5 mm by default), which joins the two bones
// across the joint space at the bone threshold, as in a patient's shoulder CT.
//
// CT sampling: 0.5 mm in-plane, 0.625 mm slices (axial, along z), 5 mm margin around the bone;
// each voxel's HU is the mean over 4^3 sub-samples (partial volume, as a scanner's detector
// integrates) plus Gaussian noise (sigma 10 HU, fixed seed: the same CT every time).
#pragma once

#include "bmAnalyticPhantom.h"
#include "bmCTImage.h"
#include "bmDicomSeriesWriter.h"
#include "bmProgress.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace bm {

struct PhantomCTOptions {
  double inPlaneSpacingMm = 0.5;
  double sliceSpacingMm = 0.625;
  double marginMm = 5.0;
  int supersample = 4;   ///< sub-samples per axis per voxel (partial volume)
  double noiseHU = 10.0; ///< Gaussian noise sigma, HU (0 = none)
  /// Point spread of the scanner: Gaussian blur sigma, mm, before the noise (0 = none). Default
  /// (unset): the phantom's own, 1.5 mm for "shoulder", none for the others.
  std::optional<double> blurSigmaMm;
  unsigned noiseSeed = 20240607;
};

/// HU of the phantom's material at world point p (mm), without partial volume or noise.
float PhantomHU(const std::string& name, const std::array<double, 3>& p);
/// The phantom as a CT (axial, identity direction).
CTImage MakePhantomCT(const std::string& name, const PhantomCTOptions& options = {},
                      const Progress& progress = {});
/// Make the phantom CT and write it as a DICOM series into folder (atomic, see
/// WriteDicomSeries; the series description names the phantom). Returns the phantom's info.
PhantomInfo WritePhantomSeries(const std::string& name, const std::string& folder,
                               const PhantomCTOptions& ctOptions = {},
                               DicomWriteOptions dicomOptions = {}, const Progress& progress = {});

} // namespace bm
