// bmScapulaCT.h - the scapula phantom as a CT (HU with partial volume and noise, as the built-in
// phantoms of bmPhantom.h) and as a DICOM series with its truth beside it. Built only with CT
// import (BMIO).
#pragma once

#include "bmCTImage.h"
#include "bmDicomSeriesWriter.h"
#include "bmPhantom.h"
#include "bmProgress.h"
#include "bmScapulaPhantom.h"

#include <string>
#include <vector>

namespace bm {

/// CT sampling for the scapula (a larger bone than the glenoid cap): 0.75 mm in-plane, 1 mm
/// axial slices, 5 mm margin, 4^3 sub-samples where a voxel straddles tissues, 10 HU noise.
PhantomCTOptions ScapulaCTDefaults();

/// The phantom as an axial CT (identity direction) over its bone box plus the margin. Each
/// voxel's HU is ScapulaVoxelHU (partial volume) plus Gaussian noise (fixed seed).
CTImage MakeScapulaCT(const ScapulaPhantom& phantom, const PhantomCTOptions& options,
                      const Progress& progress = {});
/// Several phantoms in one CT (both shoulders of one patient): the CT covers all their bone
/// boxes, each voxel the densest tissue any phantom puts there (they must not overlap).
CTImage MakeScapulaCT(const std::vector<const ScapulaPhantom*>& phantoms,
                      const PhantomCTOptions& options, const Progress& progress = {});

/// Make the CT and write it as a DICOM series into `folder` (atomic, see WriteDicomSeries), then
/// the truth as folder/truth.json (the CT reader skips .json files).
void WriteScapulaSeries(const ScapulaPhantom& phantom, const std::string& folder,
                        const PhantomCTOptions& ctOptions, DicomWriteOptions dicomOptions = {},
                        const Progress& progress = {});

} // namespace bm
