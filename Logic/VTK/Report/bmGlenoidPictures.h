// bmGlenoidPictures.h - pictures of the glenoid before and after a plan's steps, with what the
// surgeon planned drawn on the bone: the planned reaming axis (red), the measured face normal
// (green), the glenoid rim (yellow) and the planned face plane as a circle of the reamer's radius
// around the glenoid centre (white). The camera looks down the planned axis, tilted 30 deg toward
// the bone's superior side so that the depth of the cut shows. Rendering needs an X display
// (bmSurfaceImage.h).
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
