// bmPlanGlyphs.h - what a glenoid plan draws over the bone, in the 3D view (BM Glenoid Plan's
// output) and in the report's pictures (bmGlenoidPictures.h) alike: the planned reaming axis
// (red), the measured face normal (green), the planned face plane as the reamer's outline around
// the entry (white), the glenoid rim (yellow), the landmarks as spheres (glenoid centre magenta,
// trigonum blue, inferior angle cyan), each with its name written beside it in its colour. Tubes
// and spheres, not lines and points, so that they show at any zoom over the bone.
//
// The plan's camera (PlanView) looks down the planned axis, tilted 30 deg toward the world axis
// least aligned with it so that the depth of the cut shows; the labels are written facing it.
#pragma once

#include "bmSurfaceImage.h"

#include <nlohmann/json_fwd.hpp>

#include <vtkSmartPointer.h>

class vtkPolyData;

namespace bm {

/// The glyphs' parts, in the cell array "Part".
enum class PlanGlyphPart : int {
  Axis = 0,
  FaceNormal = 1,
  ReamerOutline = 2,
  Rim = 3,
  GlenoidCentre = 4,
  Trigonum = 5,
  InferiorAngle = 6
};
constexpr int kPlanGlyphParts = 7;
/// A part's colour (RGB 0..255) and its label ("planned axis", "face normal", ...).
const unsigned char* PlanGlyphColour(PlanGlyphPart part);
const char* PlanGlyphName(PlanGlyphPart part);

struct PlanGlyphOptions {
  bool labels = true;         ///< write each part's name beside it
  double labelHeightMm = 2.5; ///< letter height, mm (default 2.5: a tenth of a glenoid's width)
  double axisLengthMm = 40;   ///< drawn length of the planned axis from the entry, mm
  double normalLengthMm = 25; ///< drawn length of the face normal from the glenoid centre, mm
};

/// The glyphs of `planning` (a plan scene's "planning" object: GlenoidPlan::ToJson with
/// "landmarks"; bmGlenoidPlan.h PlanningJson): "entry_mm" and "axis" are required; the reamer's
/// outline (radius "reamer_diameter_mm" / 2, default 36.5 mm), the face normal, the rim and the
/// landmarks ("landmarks"."glenoid_centre_mm", "trigonum_mm", "inferior_angle_mm") are drawn when
/// present. Point array "Colors" (RGB, unsigned char), cell array "Part" (PlanGlyphPart). Throws
/// std::invalid_argument naming a missing or malformed key.
vtkSmartPointer<vtkPolyData> MakePlanGlyphs(const nlohmann::json& planning,
                                            const PlanGlyphOptions& options = {});

/// The plan's camera (see the file comment): focal point at the entry, the image half height
/// 1.4 reamer radii. Throws std::invalid_argument as MakePlanGlyphs.
SurfaceView PlanView(const nlohmann::json& planning, int sizePx = 800);

} // namespace bm
