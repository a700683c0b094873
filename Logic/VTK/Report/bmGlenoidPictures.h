// bmGlenoidPictures.h - pictures of the glenoid before and after a plan's steps, with what the
// surgeon planned drawn on the bone as the 3D view draws it (bmPlanGlyphs.h): the planned reaming
// axis (red), the measured face normal (green), the glenoid rim (yellow), the planned face plane
// as the reamer's outline around the entry (white) and the glenoid centre, each labelled. The
// camera is the plan's (PlanView: down the planned axis, tilted 30 deg so that the depth of the
// cut shows). Rendering needs an X display (bmSurfaceImage.h).
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <string>

namespace bm {

class Voxmap;

struct GlenoidPictureFiles {
  std::string before, after; ///< PNG file names, relative to the folder they were written to
};

/// Writes "glenoid_before.png" and "glenoid_after.png" (sizePx square) into `dir`. `planning`:
/// the plan scene's "planning" object (bmGlenoidPlan.h GlenoidPlan::ToJson, with "landmarks"
/// from bmsim plan): "entry_mm" and "axis" are required; "reamer_diameter_mm",
/// "landmarks"."face_normal" and "landmarks"."rim_mm" are drawn when present. Throws
/// std::invalid_argument naming a missing or malformed key, std::runtime_error when a file
/// cannot be written.
GlenoidPictureFiles WriteGlenoidPictures(const std::string& dir, const Voxmap& before,
                                         const Voxmap& after, const nlohmann::json& planning,
                                         int sizePx = 800);

} // namespace bm
