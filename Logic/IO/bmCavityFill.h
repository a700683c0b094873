// bmCavityFill.h - cavities inside a bone mask filled, whatever they touch.
//
// A CT threshold keeps the cortex but loses low-density marrow and cancellous bone (a femoral
// head becomes a 2-3 mm shell). The fill, on the bone mask after separation:
//  1. closing (itk::BinaryMorphologicalClosingImageFilter, a ball of closingRadiusVoxels voxels):
//     seals cracks and pores narrower than the ball, so cavities behind them become closed;
//  2. 3D cavities: background components (6-connected, itk::ConnectedComponentImageFilter) that
//     do not touch the image border;
//  3. cavities cut open by the image border or the region of interest: background components
//     that touch the border, other than the largest (the surroundings), of which at least half
//     the voxels are holes in the slices of one of the three orientations
//     (itk::SliceBySliceImageFilter over itk::BinaryFillholeImageFilter);
//  4. a cavity of (2) or (3) is filled when it is at most maxHoleVolumeMm3 and its mean HU is at
//     least holeMinMeanHU: marrow and cancellous bone are, air cells (mastoid, sinuses) and
//     large cavities (the cranial cavity) are not. A hole drilled into the bone (a pilot hole)
//     opens to the surroundings and is not a cavity.
//  5. with keepBonesApart (several bones kept), the closing and the fill never join two bones:
//     a 6-connected region of added voxels that touches two or more of the bones the threshold
//     left apart (26-connected components) is taken out again. A joint space that the closing
//     encloses (a humeral head 1-2 voxels from the glenoid on a coarse scan) is not a cavity.
// Filled voxels are marked kFilled in the mask (bone of fraction 1); closed voxels kBone.
#pragma once

#include "bmCTImage.h"
#include "bmMask.h"

#include <limits>

namespace bm {

struct CavityFillOptions {
  /// Fill cavities (on by default for bone).
  bool fill = true;
  /// Closing ball radius, voxels (0 = no closing). Default 1.
  int closingRadiusVoxels = 1;
  /// Largest cavity filled, mm^3 (default 20 cm^3: marrow spaces yes, the cranial cavity no).
  double maxHoleVolumeMm3 = 20000.0;
  /// Cavities whose mean HU is below this stay empty (air cells), HU. Default -200 HU.
  float holeMinMeanHU = -200.0f;
  /// Cavities whose mean HU is at or above this stay empty (metal: a screw in the bone), HU.
  /// Default +infinity (none).
  float holeMaxMeanHU = std::numeric_limits<float>::infinity();
  /// Bones that are apart before the fill stay apart (step 5). Default false: one bone kept.
  bool keepBonesApart = false;
};

struct CavityFillResult {
  int holesFilled = 0;       ///< cavities filled (closed and cut open by the border)
  int borderHolesFilled = 0; ///< of which cut open by the image border
  int64_t filledVoxels = 0;  ///< voxels marked kFilled
  int64_t closedVoxels = 0;  ///< voxels added by the closing
  int64_t apartVoxels = 0;   ///< added voxels taken out again to keep bones apart (step 5)
};

/// Mask marks: not bone, bone, bone added by the cavity fill.
constexpr uint8_t kNotBone = 0, kBone = 1, kFilled = 2;

/// Fill the cavities of `mask` (see above; `hu` is the CT on the same grid). Does nothing when
/// options.fill is false. Progress stage "filling cavities".
CavityFillResult FillCavities(MaskImage* mask, const HUImage* hu,
                              const CavityFillOptions& options = {}, const Progress& progress = {});

} // namespace bm
